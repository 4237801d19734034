"""The configuration data of each robot language, from one joint vector.

:func:`abb_confdata`, :func:`kuka_status_turn`, :func:`fanuc_config` and
:func:`motoman_rconf` are pure functions of one joint vector (degrees, model
joints) and the robot's geometry; their docstrings name the sources and what
could not be verified.  :func:`kuka_status_turns`,
:func:`fanuc_configs` and :func:`motoman_rconfs` compute the same for many
joint vectors at once (a long program's posts).

The arms that are neither OPW nor UR ("chain" models: the offset-wrist cobots
FANUC CRX-10iA/L and M-430iA/2P, the Yaskawa HC10 family, ABB CRB 15000; the
spherical-wrist KUKA KR ... R1100-3 etc. and the oblique-wrist MPX3500) get the
same fields from the same three measures of their own geometry
(:mod:`..kinematics.chain_families`: the wrist point where axes 4 and 5 meet,
axis 5 from the straight wrist).  On the spherical-wrist arms that is exactly
the makers' definition (the wrist root point of KUKA's Status is that point).
On the offset wrists it is the natural reading of the same definitions, which
no maker's document at hand states for these arms:

* FANUC CRX: not verified against a FANUC document (none was reachable); checked
  against a third party's table instead (:func:`fanuc_config`: the
  ``'F/N U/D T/B, t1, t4, t6'`` string, F for J5 > 0, U/D at the point where
  J4 and J5 meet, T/B at the point where J5 and J6 meet).  FANUC's ROBOGUIDE
  gives 8 of the CRX's up to 16 solutions (Abbes and Poisson, "Geometric
  Approach for Inverse Kinematics of the FANUC CRX Collaborative Robot",
  Robotics 13(6), 91, 2024): up to three solutions can share one string, and
  the controller's choice among them is not documented (the joints written by
  ``joint_targets`` leave no doubt);
* Yaskawa HC10: unverified: the ``///RCONF`` fields of the NX100/DX100
  manuals (:func:`motoman_rconf`, pages cited there) applied unchanged, at W;
  no YRC1000 or HC-series document was reachable;
* ABB CRB 15000: unverified: ``cfx`` as for ABB's spherical-wrist arms
  (:func:`abb_confdata`), at W; RobotStudio's API says only that cfx's use
  "depends on the robot model" (``ConfigurationData.Cfx``), and no RAPID
  reference section for the CRB 15000 or GoFa was reachable.

Pure numpy: never imports FreeCAD.
"""

import math

import numpy as np

from ..kinematics import chain_families, models
from ..kinematics.arm_families import (_on_angle_grid, _spec, _wrap, arm_geometry,
                                       chain_parameters)


def _joints(q_deg):
    """The 6 joints (deg) the configuration data is read from, on the 1e-9 deg grid
    (:func:`_on_angle_grid`) so rounding noise never moves a joint across a boundary
    (J4 = -1e-14 must not be quadrant -1 one time and 0 the next)."""
    q = np.asarray(q_deg, dtype=float).reshape(-1)
    if q.shape != (6,):
        raise ValueError("need 6 finite joint values in degrees, got %r" % (q_deg,))
    return _joint_rows(q[None])[0]


def _joint_rows(q_deg):
    """:func:`_joints` of each row of an (N, 6) array."""
    q = np.asarray(q_deg, dtype=float)
    if q.ndim != 2 or q.shape[1] != 6 or not np.all(np.isfinite(q)):
        raise ValueError("need rows of 6 finite joint values in degrees")
    return _on_angle_grid(q)


def _arm(robot, language):
    """`robot` itself if its configuration data can be computed: an OPW or a chain arm."""
    spec = _spec(robot)
    if spec.opw is None and chain_parameters(robot) is None:
        raise ValueError("%s configuration data needs an OPW or a chain robot; %s is neither"
                         % (language, spec.name))
    return robot


def _axis5(q, robot):
    """Axis 5 (deg, the controller's direction) from the straight wrist: shape (...).

    `q` is one joint vector (6,) or the joints as rows (6, N).  A chain arm's
    joints are the controller's (:func:`.chain_families.axis5_from_straight`);
    an OPW arm's straight wrist is where its model's ``theta5`` is 0
    (:func:`_axis5_from_straight`).
    """
    params = chain_parameters(robot)
    if params is not None:
        return chain_families.axis5_from_straight(chain_families.arm_of(params), q[4])
    return _axis5_from_straight(q, _spec(robot))


def _axis5_from_straight(q, spec):
    """Axis 5 (deg, the controller's direction) measured from the straight wrist.

    The configuration data of ABB, KUKA and Fanuc read the sign of axis 5,
    which on their arms is 0 with the wrist straight (axes 4 and 6 in line,
    the wrist singularity).  On an arm whose axis 5 has another zero (the
    HP6's B is 0 with the flange pointing down and +90 with the wrist
    straight) the sign is read from the straight wrist, so the bit still
    tells the two wrist solutions apart: ``q5 - q5_straight``, where
    ``q5_straight = offset5 * sign5`` is the controller value at which the
    OPW model's theta5 is 0.  The same as ``q5`` on every arm whose offset5
    is 0.
    """
    p = spec.opw
    return _wrap(q[4] - p.offsets_deg[4] * p.signs[4])


def quadrant(angle_deg):
    """ABB quadrant number of an axis angle: ``floor(angle / 90)``.

    0 for [0, 90), 1 for [90, 180), ..., -1 for [-90, 0), -2 for [-180, -90), ...

    Parameters
    ----------
    angle_deg : float

    Returns
    -------
    int
    """
    return int(math.floor(float(angle_deg) / 90.0))


def abb_confdata(q_deg, robot):
    """ABB RAPID ``confdata`` ``[cf1, cf4, cf6, cfx]`` of a joint vector.

    Definition (ABB, "Technical reference manual - RAPID Instructions,
    Functions and Data types", data type *confdata*, section for serial
    robots with a spherical wrist: IRB 140, 1400, 1600, 2400, 2600, 4400,
    4600, 6400, 6600, 6700, 7600 ...), as reproduced in the
    CEAD-group/py-opw-kinematics documentation (AXIS_CONFIGURATION.md) and
    ABB RobotStudio API ("ConfigurationData: Cf1 the quadrant of axis 1"):

    * ``cf1``, ``cf4``, ``cf6``: quadrant of axes 1, 4 and 6,
      ``floor(angle / 90 deg)`` (0 for 0..90, -1 for -90..0, ...);
    * ``cfx`` 0..7, one of the eight arm configurations::

          cfx  wrist centre vs axis 1   wrist centre vs lower arm   axis 5
          0    in front of              in front of                 positive
          1    in front of              in front of                 negative
          2    in front of              behind                      positive
          3    in front of              behind                      negative
          4    behind                   in front of                 positive
          5    behind                   in front of                 negative
          6    behind                   behind                      positive
          7    behind                   behind                      negative

      so ``cfx = 4 * behind_axis1 + 2 * behind_lower_arm + (axis5 < 0)``.
      "Lower arm" is the line through axes 2 and 3; on the parallel-arm
      IRB 2400 that is the link driven by axis 2 whatever the convention
      of axis 3, and it is measured here geometrically (OPW model), so the
      controller's axis-3 convention does not enter.  Axis 5 exactly 0
      counts as positive; axis 5 is measured from the straight wrist
      (:func:`_axis5_from_straight`: itself on ABB's arms).

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints, degrees (axes 1, 4, 5 and 6 are the controller's on
        every robot).
    robot : RobotModel or RobotSpec
        An OPW robot (``spec.opw``) or a chain arm (:func:`chain_parameters`).

    Returns
    -------
    tuple of 4 int
        ``(cf1, cf4, cf6, cfx)``.
    """
    q = _joints(q_deg)
    robot = _arm(robot, "ABB")
    g = arm_geometry(q, robot)
    a5 = _axis5(q, robot)
    cfx = 4 * int(g.shoulder_mm < 0) + 2 * int(g.elbow_deg < 0) + int(a5 < 0)
    return quadrant(q[0]), quadrant(q[3]), quadrant(q[5]), cfx


def kuka_status_turn(q_deg, robot):
    """KUKA KRL Status and Turn (``S``, ``T`` of a POS/E6POS) of a joint vector.

    Definition (KUKA System Software 8.x, "Operating and Programming
    Instructions for System Integrators", section Status and Turn; the bit-0
    text is quoted in robot-forum.com thread 7173, "x-value of wrist root
    point"):

    * Status bit 0: 1 when the wrist root point (intersection of A4, A5, A6)
      is in the *overhead area*, i.e. its x in the A1 coordinate system
      (``$ROBROOT`` turned with A1) is negative; 0 in the basic area.
    * Status bit 1: 1 when A3 is at or beyond the angle where the arm is
      stretched (``A3 >= phi``; phi = 0 when A3 and A4 intersect, otherwise
      set by the offset), i.e. the wrist root point is in front of the lower
      arm; 0 behind it.  Measured here geometrically with the OPW model.
    * Status bit 2: 1 when A5 <= 0, 0 when A5 > 0 (A5 from the straight
      wrist, :func:`_axis5_from_straight`: A5 itself on KUKA's arms).
    * Turn bit i (i = 0..5): 1 when axis A(i+1) < 0, 0 when >= 0.

    Checked against typical taught data: ``S 2, T 2`` (basic area, elbow
    up, A5 > 0, only A2 < 0) and ``S 6, T 18`` (A5 < 0).  Not verified on a
    controller; a forum thread (robot-forum.com 45777) reports bit 2 can
    disagree with the sign of A5 on robots with an A3/A4 offset.

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints A1..A6, degrees (the turn bits use the controller's values).
    robot : RobotModel or RobotSpec
        An OPW robot or a chain arm.

    Returns
    -------
    (int, int)
        ``(S, T)``: S in 0..7, T in 0..63.
    """
    status, turn = kuka_status_turns(_joints(q_deg)[None], robot)
    return int(status[0]), int(turn[0])


def kuka_status_turns(q_deg, robot):
    """:func:`kuka_status_turn` of many joint vectors at once.

    Parameters
    ----------
    q_deg : array_like, shape (N, 6)
        Model joints, degrees, finite.
    robot : RobotModel or RobotSpec
        An OPW robot or a chain arm.

    Returns
    -------
    status, turn : ndarray of int, shape (N,)
    """
    q = _joint_rows(q_deg)
    robot = _arm(robot, "KUKA")
    g = arm_geometry(q, robot)
    a5 = _axis5(q.T, robot)
    status = (g.shoulder_mm < 0) + 2 * (g.elbow_deg >= 0) + 4 * (a5 <= 0)
    negative = models.as_model(robot).controller_joints(q) < 0
    return status.astype(int), negative.astype(int) @ (1 << np.arange(6))


def fanuc_config(q_deg, robot):
    """Fanuc LS position configuration string, e.g. ``'N U T, 0, 0, 0'``.

    Fields: wrist ``F`` (flip) / ``N`` (no flip), arm ``U`` (up) / ``D``
    (down), ``T`` (front) / ``B`` (back), then the turn numbers of J1, J4
    and J6 (0 for -180 < angle <= 180, 1 for 180 < angle <= 540, -1 for
    -540 < angle <= -180).

    ``U``/``D`` is the elbow of :func:`arm_geometry` (``U``: wrist centre in
    front of the lower arm); ``T``/``B`` the side of the plane of axis 1
    (across the arm's plane) that the wrist centre is on, ``T`` in front;
    ``F`` when J5 > 0 (J5 from the straight wrist,
    :func:`_axis5_from_straight`).  On an offset wrist (CRX; the M-430iA/2P by
    analogy, unverified) there is no wrist centre: U/D is read where J4 and J5
    meet and T/B where J5 and J6 meet (:func:`_fanuc_front_mm`).

    NOT verified against a FANUC manual (none was reachable: FANUC's operator
    and KAREL manuals are stored only by their first pages; a translated KAREL
    reference in a public repository lists CONFIG's fields ``CFG_TURN_NO1..3,
    CFG_FLIP, CFG_LEFT, CFG_UP, CFG_FRONT`` without saying what decides them).
    Checked against a third party's CRX-10iA table (secondary source):
    frfournier/robodk_crx_kinematics, ``tests/fixtures/CRX10iA-solutions.csv``
    @1ce15fc, whose README gives "FANUC RoboGuide simulation results" and
    Abbes and Poisson 2024 as its sources: 83 joint sets of 25 poses with their
    letters.  With J3 counted from the horizontal (the URDF's J3 = J3 + J2),
    81 reproduce the table's position to 0.03 mm (the other two by exactly the J2
    height, 245 mm, in Z).  The rule here gives the table's letters on 79 of
    83 rows; the other four are the pose with the J5/J6 point exactly on axis
    1 (table B, here T), a row whose three letters contradict every other row
    (J5 = +60.2 labelled N, elbow 107.8 deg below the upper arm labelled U),
    its mirror (U) and a row whose U/D and T/B columns are swapped.  Read at
    the point where J4 and J5 meet, T/B would disagree on four more rows
    (Abbes and Poisson's Table 6), where that point is 0.9 to 5.7 mm from the
    plane of axis 1 and the J5/J6 point 40.6 to 45.5 mm, on the table's side.
    The turn numbers of J1, J4 and J6 follow a third party's reading too
    (danielcranston/crx_kinematics FANUC_DETAILS.md @cce6ba3, which says no
    FANUC document verifies it): unverified.

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints J1..J6, degrees (J1, J4, J5 and J6 are read as they are;
        J2 and J3 only through the arm's geometry, :func:`arm_geometry`).
    robot : RobotModel or RobotSpec
        An OPW robot or a chain arm.

    Returns
    -------
    str
    """
    return fanuc_configs(_joints(q_deg)[None], robot)[0]


def fanuc_configs(q_deg, robot):
    """:func:`fanuc_config` of many joint vectors at once.

    Parameters
    ----------
    q_deg : array_like, shape (N, 6)
        Model joints, degrees, finite.
    robot : RobotModel or RobotSpec
        An OPW robot or a chain arm.

    Returns
    -------
    list of str
    """
    q = _joint_rows(q_deg)
    robot = _arm(robot, "Fanuc")
    g = arm_geometry(q, robot)
    flip = np.where(_axis5(q.T, robot) > 0, "F", "N")
    up = np.where(g.elbow_deg < 0, "D", "U")
    front = np.where(_fanuc_front_mm(q, robot, g) < 0, "B", "T")
    turns = np.ceil((q[:, [0, 3, 5]] - 180.0) / 360.0).astype(int).tolist()
    return ["%s %s %s, %d, %d, %d" % (f, u, t, j1, j4, j6)
            for f, u, t, (j1, j4, j6) in zip(flip, up, front, turns)]


def _fanuc_front_mm(q, robot, geometry):
    """Where FANUC's Front/Back is read, along the arm's forward direction from axis 1
    (mm, in the frame axis 1 turns), for joint rows `q` (N, 6).

    On a chain arm it is the point where axes 5 and 6 meet
    (:func:`.chain_families.axis56_shoulder_mm`), which on an offset wrist (CRX)
    is not W; on an OPW arm that point is the wrist centre (``geometry.shoulder_mm``).
    """
    params = chain_parameters(robot)
    if params is None:
        return geometry.shoulder_mm
    return chain_families.axis56_shoulder_mm(chain_families.arm_of(params), q)


def motoman_rconf(q_deg, robot):
    """Yaskawa Motoman ``///RCONF l,m,n,o,p,q`` fields of a joint vector.

    From the NX100 manual "Interface with an easy offline teaching system"
    (HW0481924, 4.1 Job Data Format, RCONF; the DX100 edition adds 18
    unused fields ``r1..r18``)::

        l  0: Flip,       1: No-flip
        m  0: Upper arm,  1: Lower arm
        n  0: Front,      1: Rear
        o  0: R < 180,    1: R >= 180
        p  0: T < 180,    1: T >= 180
        q  0: S < 180,    1: S >= 180

    and the NX100 operator's manual (RE-CSO-A031, 3.9 "Manipulator Types"):
    Flip/No flip is the *R-axis position*: Flip for -90 < R <= 90 (and
    270 < R <= 360, -360 < R <= -270), No flip for 90 < R <= 270 and
    -270 < R <= -90; "Front/Back" relates the S axis and the TCP;
    "Upper arm/Lower arm" is the configuration of the L and U axes.

    Here: ``l`` from R as above; ``m`` = 1 when the wrist centre is behind
    the lower arm (:func:`arm_geometry` elbow < 0); ``n`` = 1 when the wrist
    centre (not the TCP: the wrist centre is what separates the IK
    solutions) is behind the S axis; ``o``, ``p``, ``q`` = 1 when
    ``|angle| >= 180`` (the only reading that tells R = 300 from R = -60).
    Not verified: the manuals' figures (which side is "Flip", the exact
    front/back and upper/lower criteria) were not available; only the
    texts were.  Read again for issue 24 (faithful copies): the operator's
    manual page 3-76 (149235-1CD, easymanua.ls/yaskawa/nx100/manual?p=140),
    HW0481924 page 4-5 (easymanua.ls/motoman/nx100/manual/228196?p=43), the
    DX100 edition HW0482494 page 4-5 (easymanua.ls/yaskawa/motoman-dx100/
    manual?p=37, which sends the reader to its 4.3 "Configuration of Position
    Data", page 4-21, not reached) and the NX100 remote-command
    specification's "Form" bits in the same order (D0 Flip/No-flip, D1
    Up/Down, D2 Front/Rear, D3-D5 R, T, S < 180 / >= 180).  None names the
    YRC1000 or an offset wrist: the HC10's RCONF (W for the wrist centre,
    :mod:`..kinematics.chain_families`) is unverified.

    Parameters
    ----------
    q_deg : array_like, shape (6,)
        Model joints S, L, U, R, B, T in degrees (S, R and T are the controller's).
    robot : RobotModel or RobotSpec
        An OPW robot or a chain arm.

    Returns
    -------
    tuple of 6 int
        ``(l, m, n, o, p, q)``; a DX100/DX200 post appends its unused zeros.
    """
    return tuple(int(v) for v in motoman_rconfs(_joints(q_deg)[None], robot)[0])


def motoman_rconfs(q_deg, robot):
    """:func:`motoman_rconf` of many joint vectors at once.

    Parameters
    ----------
    q_deg : array_like, shape (N, 6)
        Model joints, degrees, finite.
    robot : RobotModel or RobotSpec
        An OPW robot or a chain arm.

    Returns
    -------
    ndarray of int, shape (N, 6)
        ``l, m, n, o, p, q`` per row.
    """
    q = _joint_rows(q_deg)
    g = arm_geometry(q, _arm(robot, "Motoman"))
    r = _wrap(q[:, 3])
    flip = ~((-90.0 < r) & (r <= 90.0))       # same test for R and R +- 360
    return np.stack([flip, g.elbow_deg < 0, g.shoulder_mm < 0, np.abs(q[:, 3]) >= 180.0,
                     np.abs(q[:, 5]) >= 180.0, np.abs(q[:, 0]) >= 180.0], axis=1).astype(int)
