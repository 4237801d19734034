"""Kinematic models of the catalog robots: ``model(name)``.

Every model has the same interface, vectorised over poses::

    robot = model("KUKA_KR16")
    T_r_f = robot.fk(q_deg)          # (N, 6) deg -> (N, 4, 4) mm, flange in the base frame
    q_deg = robot.ik(T_r_f)          # (N, 4, 4) mm -> (N, M, 6) deg, NaN rows where no branch
    ok    = robot.within_limits(q)   # (..., 6) deg -> (...) bool
    q_c   = robot.controller_joints(q)   # (..., 6) model joints -> the controller's

The catalog entry chooses the kinematics:

* ``opw`` only: closed-form OPW forward and inverse (:mod:`.opw`);
* ``dh`` (FreeCAD Robot workbench rows) and ``opw``: forward exactly as
  FreeCAD's ``Robot6Axis`` computes its TCP (:mod:`.dh`), inverse by the
  equivalent OPW model (``opw`` is derived from ``dh``, see
  :func:`.dh.opw_from_dh`);
* ``ur``: Universal Robots closed form (:mod:`.ur`);
* ``chain``: joint axes and the steps between them (:mod:`.poe`), forward by
  products of exponentials, inverse by the solver class that recognises the
  arm (:mod:`.chain_classes`: offset or spherical wrist).

``M``, the rows of ``ik`` per pose, is :attr:`RobotModel.max_solutions`: 8 for
OPW and UR arms, up to 16 for a chain (an offset wrist); callers read it from
the array's shape, never assume 8.

Joint values ``q`` are those of the serial kinematic model, with the
vendor's signs and zero offsets (the joints of ROS-Industrial's robot
descriptions).  They are the controller's, except J3 of a parallel-arm
robot (``spec.j23_coupled``, the IRB 2400), whose controller reports
``J3 = q2 + q3``.  Joint limits and joint speeds are the controller's, so
every limit or speed test goes through :meth:`RobotModel.controller_joints`
(:meth:`RobotModel.limit_excess`, :meth:`RobotModel.within_limits`).

``ik`` does not apply joint limits; each joint comes wrapped into
(-180, 180] and ``within_limits`` then says which rows the robot can take
(a joint with a range beyond +-180 deg may also take ``q +- 360``; that
choice is the caller's).

Pure numpy: never imports FreeCAD.
"""

import numpy as np

from ...core.frames import invert_transform
from ...errors import InputError
from . import chain_classes, dh, opw, poe, ur
from ..catalog import catalog


class RobotModel:
    """Kinematics of one catalog robot (build it with :func:`model`).

    Attributes
    ----------
    name : str
        Catalog name.
    spec : RobotSpec
        The catalog entry (limits, speeds, parameters, notes).
    kind : str
        ``"opw"``, ``"dh+opw"``, ``"ur"`` or ``"chain"``: which equations are used.
    max_solutions : int
        Rows of :meth:`ik` per pose.
    """

    kind = ""
    max_solutions = 8

    def __init__(self, spec):
        self.name = spec.name
        self.spec = spec
        self.joint_min_deg = np.asarray(spec.joint_min_deg, dtype=float)
        self.joint_max_deg = np.asarray(spec.joint_max_deg, dtype=float)

    def __repr__(self):
        return "<RobotModel %s (%s)>" % (self.name, self.kind)

    def fk(self, q_deg):
        """Flange pose for joint values.

        Parameters
        ----------
        q_deg : array_like, shape (N, 6) or (6,)
            Joint values in degrees, controller convention.

        Returns
        -------
        T_r_f : ndarray, shape (N, 4, 4) or (4, 4)
            Flange frame {F} in the robot base frame {R}, mm.
        """
        raise NotImplementedError

    def ik(self, T_r_f):
        """All closed-form inverse kinematic solutions.

        Parameters
        ----------
        T_r_f : array_like, shape (N, 4, 4) or (4, 4)
            Flange poses in the robot base frame, mm.

        Returns
        -------
        q_deg : ndarray, shape (N, M, 6) or (M, 6)
            ``M =`` :attr:`max_solutions` rows per pose (8 branches of an OPW or
            UR arm), degrees in (-180, 180]; a row is NaN where that branch
            does not exist.  Joint limits are not applied.
        """
        raise NotImplementedError

    def controller_joints(self, q_deg):
        """The controller's joint values of model joints.

        The same values, except where the controller counts J3 against the
        base (``spec.j23_coupled``): there it is ``q3 + k * q2`` with ``k =
        spec.j23_factor`` (+1 on ABB's parallel arms, ROS-Industrial abb_driver's
        ``J23_coupled``; -1 on FANUC arms, fanuc_driver's ``J23_factor``).

        Parameters
        ----------
        q_deg : array_like, shape (..., 6)
            Model joints (as :meth:`fk` takes them), degrees.

        Returns
        -------
        ndarray, shape (..., 6)
            A new array, degrees.
        """
        q = np.array(q_deg, dtype=float)
        if self.spec.j23_coupled:
            q[..., 2] += self.spec.j23_factor * q[..., 1]
        return q

    def model_joints(self, q_ctrl_deg):
        """The model joints of controller joint values (inverse of :meth:`controller_joints`).

        Parameters
        ----------
        q_ctrl_deg : array_like, shape (..., 6)
            Joint values as the controller has them, degrees.

        Returns
        -------
        ndarray, shape (..., 6)
            A new array, degrees: ``q3 = J3 - k * J2`` where J3 is counted
            against the base.
        """
        q = np.array(q_ctrl_deg, dtype=float)
        if self.spec.j23_coupled:
            q[..., 2] -= self.spec.j23_factor * q[..., 1]
        return q

    def limit_excess(self, q_deg, controller=False):
        """How far each joint is outside its limits, in the controller's convention.

        Parameters
        ----------
        q_deg : array_like, shape (..., 6)
            Model joints, degrees (controller joints when `controller`).
        controller : bool
            `q_deg` already holds the controller's values.  Default False.

        Returns
        -------
        ndarray, shape (..., 6)
            Degrees below ``joint_min_deg`` or above ``joint_max_deg`` of each
            controller joint; 0 within the limits (limits included, and up to
            ``opw.ANGLE_TOLERANCE_DEG`` past them: rounding noise); NaN where the
            joints are NaN.
        """
        q = np.asarray(q_deg, dtype=float) if controller else self.controller_joints(q_deg)
        excess = np.maximum(self.joint_min_deg - q, 0.0) + np.maximum(q - self.joint_max_deg, 0.0)
        return np.where(excess <= opw.ANGLE_TOLERANCE_DEG, 0.0, excess)

    def within_limits(self, q_deg):
        """Whether joint values lie within the catalog's joint limits.

        Parameters
        ----------
        q_deg : array_like, shape (..., 6)
            Model joints in degrees, e.g. (N, 6) or the (N, 8, 6) of :meth:`ik`.

        Returns
        -------
        ok : ndarray of bool, shape (...)
            True where every controller joint (:meth:`controller_joints`) is
            within ``[joint_min_deg, joint_max_deg]`` (limits included);
            False for NaN rows.
        """
        return np.all(self.limit_excess(q_deg) == 0.0, axis=-1)

    def joint_label(self, j):
        """How messages name joint `j` (0-based): ``"J4"``, or for the
        controller's J3 of a parallel-arm robot
        ``"J3 (= q2 + q3 on this parallel-arm robot)"``.

        Returns
        -------
        str
        """
        if j == 2 and self.spec.j23_coupled:
            if self.spec.j23_factor == 1:
                return "J3 (= q2 + q3 on this parallel-arm robot)"
            return "J3 (= q3 %+d q2: this controller counts J3 from the horizontal)" % self.spec.j23_factor
        return "J%d" % (j + 1)


class _FramedModel(RobotModel):
    """A closed form between fixed base and flange transforms (``spec.T_root_base``,
    ``spec.T_flange_tip``: the frames of a robot read from a URDF)."""

    _forward = _inverse = None

    def __init__(self, spec):
        super().__init__(spec)
        self.T_root_base = None if spec.T_root_base is None else np.array(spec.T_root_base)
        self.T_flange_tip = None if spec.T_flange_tip is None else np.array(spec.T_flange_tip)
        self._params = getattr(spec, self.kind)

    def fk(self, q_deg):
        T = self._forward(self._params, q_deg)
        if self.T_root_base is not None:
            T = self.T_root_base @ T
        if self.T_flange_tip is not None:
            T = T @ self.T_flange_tip
        return T

    def ik(self, T_r_f):
        T = np.asarray(T_r_f, dtype=float)
        if self.T_root_base is not None:
            T = invert_transform(self.T_root_base) @ T
        if self.T_flange_tip is not None:
            T = T @ invert_transform(self.T_flange_tip)
        return self._inverse(self._params, T)

    fk.__doc__ = RobotModel.fk.__doc__
    ik.__doc__ = RobotModel.ik.__doc__


class OPWModel(_FramedModel):
    """Closed-form OPW forward and inverse kinematics (:mod:`.opw`)."""

    kind = "opw"
    _forward = staticmethod(opw.forward)
    _inverse = staticmethod(opw.inverse)


class DHOPWModel(RobotModel):
    """FreeCAD Robot workbench forward kinematics (:mod:`.dh`), OPW inverse."""

    kind = "dh+opw"

    def fk(self, q_deg):
        return dh.forward(self.spec.dh, q_deg)

    def ik(self, T_r_f):
        return opw.inverse(self.spec.opw, T_r_f)

    fk.__doc__ = RobotModel.fk.__doc__
    ik.__doc__ = RobotModel.ik.__doc__


class URModel(_FramedModel):
    """Universal Robots closed-form forward and inverse kinematics (:mod:`.ur`)."""

    kind = "ur"
    _forward = staticmethod(ur.forward)
    _inverse = staticmethod(ur.inverse)


class ChainModel(_FramedModel):
    """An arm given as joint axes and steps (:mod:`.poe`), solved by its class
    (:mod:`.chain_classes`).

    Attributes
    ----------
    params : poe.ChainParameters
        ``spec.chain`` as arrays (:func:`chain_parameters`): the URDF's joints, in {R}.
    """

    kind = "chain"

    def __init__(self, spec):
        super().__init__(spec)
        self.params = self._params = chain_parameters(spec.chain)
        self._solver = None

    @property
    def solver(self):
        """chain_classes.Solver: the arm's class and constants (found at first use).

        Raises
        ------
        InputError
            No class recognises the arm, saying why for each.
        """
        if self._solver is None:
            try:
                self._solver = chain_classes.Solver(self.params)
            except ValueError as exc:
                raise InputError("Robot %s: no inverse kinematics solves this arm: %s; "
                                 "import its URDF again or choose another robot."
                                 % (self.name, exc)) from None
        return self._solver

    @property
    def max_solutions(self):
        return self.solver.max_solutions

    @staticmethod
    def _forward(params, q_deg):
        q = np.asarray(q_deg, dtype=float)
        T = poe.fk(params, np.radians(np.atleast_2d(q)))
        return T[0] if q.ndim == 1 else T

    def _inverse(self, params, T):
        T = np.asarray(T, dtype=float)
        q = self.solver.inverse(T.reshape(-1, 4, 4))
        q_deg = opw.wrap_deg(np.degrees(q))
        return q_deg[0] if T.ndim == 2 else q_deg


def chain_parameters(chain):
    """The :class:`.poe.ChainParameters` of a catalog entry's ``chain`` (``R_6T`` the
    identity: the entry's ``T_flange_tip`` holds the flange's rotation).

    Parameters
    ----------
    chain : catalog.ChainAxes

    Returns
    -------
    poe.ChainParameters
    """
    return poe.ChainParameters(H=np.array(chain.axes, dtype=float),
                               P=np.array(chain.steps_mm, dtype=float), R_6T=np.eye(3))


def kinematic_class(spec):
    """Which inverse kinematics solves a catalog entry.

    Parameters
    ----------
    spec : RobotSpec

    Returns
    -------
    str
        ``"opw"``, ``"ur"`` or the ``KIND`` of its class in :mod:`.chain_classes`
        (e.g. ``"offset_wrist"``).

    Raises
    ------
    ValueError
        A chain that no class recognises.
    """
    if spec.opw is not None:
        return "opw"
    if spec.ur is not None:
        return "ur"
    return chain_classes.classify(chain_parameters(spec.chain)).KIND


def model(name):
    """The kinematic model of catalog robot `name`.

    Parameters
    ----------
    name : str
        A name from ``catalog.names()``, e.g. ``"ABB_IRB2400"``.

    Returns
    -------
    RobotModel
        With ``name``, ``spec``, ``fk``, ``ik``, ``within_limits``.

    Raises
    ------
    UnknownNameError
        For a name not in the catalog.
    """
    return as_model(catalog.get(name))


def as_model(robot):
    """A :class:`RobotModel` for a model, a catalog entry or a catalog name.

    Parameters
    ----------
    robot : RobotModel, RobotSpec or str
        A spec need not be in the catalog (e.g. one with other limits).

    Returns
    -------
    RobotModel
        `robot` itself when it is one.
    """
    if isinstance(robot, RobotModel):
        return robot
    spec = catalog.get(robot) if isinstance(robot, str) else robot
    if spec.ur is not None:
        return URModel(spec)
    if spec.chain is not None:
        return ChainModel(spec)
    if spec.dh is not None and spec.opw is not None:
        return DHOPWModel(spec)
    if spec.opw is not None:
        return OPWModel(spec)
    raise ValueError("catalog entry %s has no kinematic parameters" % spec.name)
