"""The robot catalog: what CadRobot knows about each robot model.

Values come from ``shared/REFERENCE.md`` (sources named there). Where a value
is not published, :attr:`RobotSpec.notes` says so: a user must be able to see
which numbers are uncertain before trusting a reach or timing check.

Lengths are millimetres, angles degrees, joint speeds degrees per second.
This module only holds data; ``robots.kinematics.models.model(name)`` builds the
forward/inverse kinematics from it (``robots.kinematics.opw``, ``robots.kinematics.dh``, ``robots.kinematics.ur``).
"""

import os
from dataclasses import dataclass, field
from typing import Optional, Tuple

from ... import command_line
from ...errors import InputError, UnknownNameError


@dataclass(frozen=True)
class OPWParameters:
    """Ortho-parallel basis with spherical wrist (Brandstötter et al. 2014).

    Lengths in mm; ``offsets_deg`` and ``signs`` map controller joint values to
    the model (``q_model = q * sign - offset``), as in opw_kinematics.
    """

    a1: float
    a2: float
    b: float
    c1: float
    c2: float
    c3: float
    c4: float
    offsets_deg: Tuple[float, ...] = (0, 0, 0, 0, 0, 0)
    signs: Tuple[int, ...] = (1, 1, 1, 1, 1, 1)


@dataclass(frozen=True)
class URParameters:
    """Universal Robots DH lengths in mm (UR's published table; the other
    entries are a1 = a4 = a5 = a6 = 0, d2 = d3 = 0, alpha = 90, 0, 0, 90, -90, 0 deg).

    The wrist is not spherical, so these robots have their own closed form
    (:mod:`.ur`) instead of :class:`OPWParameters`.  ``offsets_deg`` and
    ``signs`` map joint values to the DH angles as for OPW
    (``theta = q * sign - offset``); UR's own arms have none.
    """

    d1: float
    a2: float
    a3: float
    d4: float
    d5: float
    d6: float
    offsets_deg: Tuple[float, ...] = (0, 0, 0, 0, 0, 0)
    signs: Tuple[int, ...] = (1, 1, 1, 1, 1, 1)


@dataclass(frozen=True)
class ChainAxes:
    """A six-axis arm as its joint axes and the steps between them at zero joint values.

    IK-Geo's ``H`` and ``P`` (``robots.kinematics.poe.ChainParameters``, whose
    ``R_6T`` is the catalog entry's ``T_flange_tip``): joint i turns about the
    line through ``steps_mm[0] + ... + steps_mm[i - 1]`` along ``axes[i - 1]``;
    ``steps_mm[6]`` goes from that point of axis 6 to the flange.  Frame {R}, mm;
    the joint values are the URDF's, unchanged.
    """

    axes: Tuple[Tuple[float, float, float], ...]
    steps_mm: Tuple[Tuple[float, float, float], ...]


@dataclass(frozen=True)
class DHRow:
    """One row of a FreeCAD Robot workbench CSV (mm, degrees)."""

    a: float
    alpha: float
    d: float
    theta: float
    rot_dir: int
    max_deg: float
    min_deg: float
    speed_deg_s: float


@dataclass(frozen=True)
class RobotSpec:
    """A robot model.

    Attributes
    ----------
    name : str
        Catalog name, e.g. ``"ABB_IRB2400"``.
    manufacturer, model, controller : str
    default_post : str
        Post-processor for this robot's controller.
    payload_kg : float or None
        Rated payload; None where not known.
    joint_min_deg, joint_max_deg : tuple of 6 float
        Joint limits in the controller's convention (see ``j23_coupled``).
    joint_speed_deg_s : tuple of 6 float
        Top joint speeds, controller's convention (see ``j23_coupled``).
    opw : OPWParameters or None
    dh : tuple of DHRow or None
        For robots defined like FreeCAD's Robot workbench: their forward
        kinematics is FreeCAD's (``robots.kinematics.dh``); ``opw`` then holds the
        equivalent OPW model used for the closed-form inverse.
    ur : URParameters or None
        For Universal Robots arms (non-spherical wrist, ``robots.kinematics.ur``).
    chain : ChainAxes or None
        For the other arms (offset or oblique wrists): joint axes and the steps
        between them at zero joint values, in {R}, solved by a class of
        ``robots.kinematics.chain_classes``; the flange's rotation at zero is
        ``T_flange_tip``.
    T_root_base : tuple of 4 tuples of 4 float, or None
        The kinematic model's base frame (OPW or UR) in the robot's base frame
        {R}, mm; None for the identity.  A robot read from a URDF has {R} = the
        URDF's root link (:mod:`.identify`).
    T_flange_tip : tuple of 4 tuples of 4 float, or None
        The robot's flange {F} in the kinematic model's flange frame, mm; None
        for the identity.  A robot read from a URDF has {F} = its ``tool0``.
    reach_mm : float or None
        Largest distance from axis 1 to the wrist centre (the point axes 4
        and 5 meet), as data sheets give reach.
    meshes : str
        Path of the link meshes file (:mod:`.link_meshes`), "" for simple solids.
    source, license : str
        Where the kinematics came from and its license (catalog table rows).
    j23_coupled : bool
        True for a parallel-arm robot (J2/J3 linkage, e.g. the IRB 2400):
        its controller's J3 sets the upper arm's angle against the base, not
        against the lower arm, so ``J3_ctrl = q3 + q2`` of the serial
        kinematic model (``opw``/``dh``).  ``joint_min_deg[2]``,
        ``joint_max_deg[2]`` and ``joint_speed_deg_s[2]`` then apply to
        ``q2 + q3``, and J3 is reported that way; the kinematics
        (``fk``/``ik``) keep the serial joints.  The convention of
        ROS-Industrial's abb_driver (parameter ``J23_coupled``: controller
        J3 = serial J3 + serial J2, and back).  See
        ``robots.kinematics.models.RobotModel.controller_joints``.  Default False.
    j23_factor : int
        When ``j23_coupled``: ``k`` of ``J3_ctrl = q3 + k * q2`` (+1 for ABB's
        parallel arms, -1 for FANUC, whose J3 is the upper arm's angle from
        the horizontal; :mod:`.makers` names the sources).  Default 1.
    notes : str
        Uncertain or derived values, stated plainly.
    uncertain : tuple of str
        Names of the fields (or field entries) that :attr:`notes` calls uncertain.
    """

    name: str
    manufacturer: str
    model: str
    controller: str
    default_post: str
    payload_kg: float
    joint_min_deg: Tuple[float, ...]
    joint_max_deg: Tuple[float, ...]
    joint_speed_deg_s: Tuple[float, ...]
    opw: Optional[OPWParameters] = None
    dh: Optional[Tuple[DHRow, ...]] = None
    ur: Optional[URParameters] = None
    chain: Optional[ChainAxes] = None
    j23_coupled: bool = False
    j23_factor: int = 1
    notes: str = ""
    uncertain: Tuple[str, ...] = field(default_factory=tuple)
    T_root_base: Optional[Tuple[Tuple[float, ...], ...]] = None
    T_flange_tip: Optional[Tuple[Tuple[float, ...], ...]] = None
    reach_mm: Optional[float] = None
    meshes: str = ""
    source: str = ""
    license: str = ""


_ABB_OFFSETS = (0, 0, -90, 0, 0, 0)

# j23_coupled: of the ABB arms here only the IRB 2400 has the parallel J2/J3 linkage;
# the IRB 2600 and IRB 4600 are serial (abb_driver J23_coupled: false).

_ROBOTS = (
    RobotSpec(
        name="ABB_IRB2400",
        manufacturer="ABB",
        model="IRB 2400/10",
        controller="S4C+ / IRC5",
        default_post="abb_rapid",
        payload_kg=10,
        joint_min_deg=(-180, -100, -60, -200, -120, -400),
        joint_max_deg=(180, 110, 65, 200, 120, 400),
        joint_speed_deg_s=(150, 150, 150, 360, 360, 450),
        opw=OPWParameters(100, -135, 0, 615, 705, 755, 85, _ABB_OFFSETS),
        j23_coupled=True,
        notes=("The paper's seam-tracking robot. Parallel-arm J2/J3 linkage: the controller's "
               "J3 is q2 + q3 of the serial (OPW) model, as ROS-Industrial's abb_driver "
               "converts it (J23_coupled: true for the IRB 2400); the J3 limits -60/+65 deg "
               "(ABB data sheet: axis 3 +65/-60) and J3's speed apply to q2 + q3."),
    ),
    RobotSpec(
        name="ABB_IRB2600",
        manufacturer="ABB",
        model="IRB 2600-12/1.65",
        controller="IRC5",
        default_post="abb_rapid",
        payload_kg=12,
        joint_min_deg=(-180, -95, -180, -400, -120, -400),
        joint_max_deg=(180, 155, 75, 400, 120, 400),
        joint_speed_deg_s=(175, 175, 175, 360, 360, 460),
        opw=OPWParameters(150, -115, 0, 445, 700, 795, 85, _ABB_OFFSETS),
        notes=("The OPW set reproduces ROS-Industrial's IRB 2600-12/1.65 URDF "
               "(abb_irb2600_support/urdf/irb2600_12_165_macro.xacro, ros-industrial/abb and "
               "abb_experimental) exactly: its tool0 equals this flange to 1e-12 mm for the same "
               "joint values, and its joint axes turn the way ABB's axes do (J2 positive tilts "
               "the lower arm forward, J3 positive turns the upper arm down), so the URDF's joints "
               "are the controller's. Joint limits are ABB's: J2 -95/+155, J3 -180/+75, as "
               "robotkinematicscatalogue's ABB_IRB_2600_20_165 (ABB convention) and "
               "PickNikRobotics/abb_ros2's corrected copy of that URDF (same axes, J2 "
               "-1.658/+2.705 rad, J3 -3.142/+1.309 rad) have them. The ROS-Industrial URDF's "
               "J2 -155/+95 is that range mirrored (the arm would lean back 155 deg and forward "
               "only 95) and its J3 -155 is narrower; its sibling IRB 4600 URDF, with the same "
               "axes, has ABB's J2 -90/+150 and J3 -180/+75. ABB's product specification itself "
               "was not at hand. Speeds from the product data sheet."),
        uncertain=("joint_speed_deg_s",),
    ),
    RobotSpec(
        name="ABB_IRB4600",
        manufacturer="ABB",
        model="IRB 4600-60/2.05",
        controller="IRC5",
        default_post="abb_rapid",
        payload_kg=60,
        joint_min_deg=(-180, -90, -180, -400, -125, -400),
        joint_max_deg=(180, 150, 75, 400, 120, 400),
        joint_speed_deg_s=(175, 175, 175, 250, 250, 360),
        opw=OPWParameters(175, -175, 0, 495, 900, 960, 135, _ABB_OFFSETS),
        notes="OPW parameters untested upstream; limits and speeds from the product data sheet.",
        uncertain=("opw", "joint_min_deg", "joint_max_deg", "joint_speed_deg_s"),
    ),
    RobotSpec(
        name="MOTOMAN_HP6",
        manufacturer="Yaskawa Motoman",
        model="HP6",
        controller="NX100",
        default_post="motoman_inform",
        payload_kg=6,
        joint_min_deg=(-170, -90, -175, -180, -45, -360),
        joint_max_deg=(170, 155, 250, 180, 225, 360),
        joint_speed_deg_s=(220, 200, 220, 410, 410, 610),
        opw=OPWParameters(150, -155, 0, 450, 570, 640, 95, (0, 0, -90, 0, -90, 180),
                          (1, 1, -1, -1, -1, -1)),
        notes=("The paper's force-following robot. No published URDF or OPW set: lengths "
               "derived from public DH models (forearm 635 vs 640 mm, 640 chosen for the "
               "1378 mm reach). Joint zeros and directions as the public descriptions have "
               "them: at all joints 0 the lower arm is vertical, the upper arm horizontal and "
               "the flange points down (B = 0; B = +90 puts the flange in line with the upper "
               "arm, pointing forward). Both Peter Corke's Robotics Toolbox model "
               "(mdl_MotomanHP6, whose 'mastering position' q0 is this posture) and "
               "robotkinematicscatalogue's Motoman_MH6S (same joint signs, J5 zero offset 90 deg) "
               "give the same forward kinematics as this model with the lengths above; the "
               "MotoMINI's ROS-Industrial URDF (B -30/+210) also has B = 0 with the flange "
               "down. Before issue 11, B = 0 here was the flange in line with the upper arm (their "
               "B = ours + 90). Joint limits are the HP6 data sheet's (REFERENCE.md), in this "
               "convention: B -45/+225 is +-135 deg about the straight wrist, as "
               "robotkinematicscatalogue has it for the MH6S. Joint speeds unknown: the MH6's "
               "are used."),
        uncertain=("opw", "joint_speed_deg_s"),
    ),
    RobotSpec(
        name="KUKA_KR16",
        manufacturer="KUKA",
        model="KR 16",
        controller="KR C2 / KR C4",
        default_post="kuka_krl",
        payload_kg=16,
        joint_min_deg=(-185, -155, -130, -350, -130, -350),
        joint_max_deg=(185, 35, 154, 350, 130, 350),
        joint_speed_deg_s=(156, 156, 156, 330, 330, 615),
        dh=(
            DHRow(260, -90, 675, 0, -1, 185, -185, 156),
            DHRow(680, 0, 0, 0, 1, 35, -155, 156),
            DHRow(-35, 90, 0, -90, 1, 154, -130, 156),
            DHRow(0, -90, -670, 0, 1, 350, -350, 330),
            DHRow(0, 90, 0, 0, 1, 130, -130, 330),
            DHRow(0, 180, -158, 180, 1, 350, -350, 615),
        ),
        # Derived from the DH rows (robots.kinematics.dh.opw_from_dh; tests prove equal FK).
        opw=OPWParameters(260, 35, 0, 675, 680, 670, 158, (0, -90, 0, 0, 0, 0),
                          (-1, 1, 1, -1, 1, -1)),
        notes=("Same kinematics and limits as FreeCAD's Robot workbench file Lib/Kuka/kr_16.csv; "
               "the OPW set is derived from it. That file has a = -35 mm on axis 3: the wrist "
               "line is 35 mm below the A3 axis (OPW a2 = +35). ROS-Industrial's KR 16-2 URDF "
               "(ros-industrial/kuka_experimental@e78bbd15, "
               "kuka_kr16_support/urdf/kr16_2_macro.xacro: joint_a4 at x 0.67, z -0.035 from "
               "A3) agrees: its tool0, with the same joint values, equals this model's flange "
               "to 1e-12 mm on 1000 random joint sets within the limits (same base frame, "
               "tool0 = flange), and its limits and speeds are these."),
    ),
    RobotSpec(
        name="KUKA_KR6_R700",
        manufacturer="KUKA",
        model="KR 6 R700 sixx",
        controller="KR C4 compact",
        default_post="kuka_krl",
        payload_kg=6,
        joint_min_deg=(-170, -190, -120, -185, -120, -350),
        joint_max_deg=(170, 45, 156, 185, 120, 350),
        joint_speed_deg_s=(360, 300, 360, 381, 388, 615),
        opw=OPWParameters(25, -35, 0, 400, 315, 365, 80, (0, -90, 0, 0, 0, 0),
                          (-1, 1, 1, -1, 1, -1)),
        notes="Limits and speeds from the product data sheet.",
        uncertain=("joint_min_deg", "joint_max_deg", "joint_speed_deg_s"),
    ),
    RobotSpec(
        name="UR5E",
        manufacturer="Universal Robots",
        model="UR5e",
        controller="e-Series (PolyScope 5)",
        default_post="ur_script",
        payload_kg=5,
        joint_min_deg=(-360, -360, -360, -360, -360, -360),
        joint_max_deg=(360, 360, 360, 360, 360, 360),
        joint_speed_deg_s=(180, 180, 180, 180, 180, 180),
        ur=URParameters(d1=162.5, a2=-425, a3=-392.2, d4=133.3, d5=99.7, d6=99.6),
        notes=("Non-spherical wrist: closed form of its own (robots.ur). DH lengths from "
               "Universal Robots' published DH table (nominal values: every arm ships with its own "
               "calibration, which differs slightly). Joint limits and speeds from the UR5e "
               "data sheet."),
    ),
)

#: The catalog table: arms read from URDF descriptions (``tools/build_catalog.py``).
_PACKAGE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TABLE_PATH = os.path.join(_PACKAGE, "resources", "robots", "catalog.csv")

_user_folder = ""
_cache = {}


def set_user_folder(path):
    """Use the robots imported into `path` (one-row table files, ``*.csv``).

    Parameters
    ----------
    path : str
        The user robot folder ("" for none); the App layer passes the
        preference's value.
    """
    global _user_folder
    if path != _user_folder:
        _user_folder = path
        _cache.pop("user", None)


def user_folder():
    """str: the user robot folder in use ("" for none)."""
    return _user_folder


def forget_user_robots():
    """Read the user robot folder again at the next lookup (after an import)."""
    _cache.pop("user", None)


def _table_robots():
    if "table" not in _cache:
        from . import catalog_table
        _cache["table"] = catalog_table.read_table(TABLE_PATH) if os.path.isfile(TABLE_PATH) else []
    return _cache["table"]


def _user_robots():
    if "user" not in _cache:
        robots, problems = [], []
        if _user_folder and os.path.isdir(_user_folder):
            for entry in sorted(os.listdir(_user_folder)):
                if entry.endswith(".csv"):
                    found, problem = _user_file(os.path.join(_user_folder, entry))
                    robots.extend(found)
                    problems.extend([problem] if problem else [])
        _cache["user"] = robots
        _cache["user_problems"] = problems
    return _cache["user"]


def _user_file(path):
    """The robots of one user robot file and a warning ("" for none): a file that cannot
    be read gives no robot, a link hulls file that cannot be read leaves simple solids."""
    import csv
    import dataclasses

    from . import catalog_table
    try:
        specs = catalog_table.read_table(path, catalog_table.MAX_USER_TABLE_BYTES)
    except InputError as exc:
        return [], "Robot file skipped: %s" % exc
    except (OSError, ValueError, csv.Error) as exc:
        return [], ("Robot file '%s' skipped: it cannot be read as a table (%s); delete it or "
                    "import the robot again." % (path, " ".join(str(exc).split())))
    if not specs:
        return [], ("Robot file '%s' skipped: it holds no robot row under its header; delete it or "
                    "import the robot again." % path)
    problems = []
    for i, spec in enumerate(specs):
        problem = catalog_table.meshes_problem(spec.meshes) if spec.meshes else ""
        if problem:
            specs[i] = dataclasses.replace(spec, meshes="")
            problems.append("Robot %s: its link solids file '%s' %s: it is drawn with simple "
                            "solids; import its URDF again to make the file."
                            % (spec.name, spec.meshes, problem))
    return specs, " ".join(problems)


def user_folder_problems():
    """list of str: one warning per user robot file skipped (or whose link solids were
    left out) at the last reading of the user robot folder, naming the file and the fix."""
    _user_robots()
    return list(_cache.get("user_problems", ()))


def _by_name():
    if "user" not in _cache or "all" not in _cache:
        by_name = {}
        for spec in list(_ROBOTS) + _table_robots() + _user_robots():
            by_name.setdefault(spec.name, spec)
        _cache["all"] = by_name
    return _cache["all"]


def specs():
    """list of RobotSpec: the built-in robots, the table's, then the user's imported ones."""
    return list(_by_name().values())


def reach_mm(spec):
    """Largest distance from axis 1 to the wrist centre, mm: ``spec.reach_mm``, or from
    the kinematic lengths (OPW ``|a1| + c2 + sqrt(a2² + c3²)`` beside ``b``; UR
    ``|a2| + |a3|`` beside ``d4``).  A chain's (kind ``chain``: to the point where
    axes 4 and 5 meet, ``robots.kinematics.chain_geometry.reach_mm``) is only the
    given one: its table row and an import always give it.

    Parameters
    ----------
    spec : RobotSpec

    Returns
    -------
    float or None
        None for a robot with no kinematic lengths, or a chain without ``reach_mm``.
    """
    import math
    if spec.reach_mm is not None:
        return spec.reach_mm
    if spec.opw is not None:
        p = spec.opw
        return math.hypot(abs(p.a1) + p.c2 + math.hypot(p.a2, p.c3), p.b)
    if spec.ur is not None:
        return math.hypot(abs(spec.ur.a2) + abs(spec.ur.a3), spec.ur.d4)
    return None


def hand_written_names():
    """list of str: the robots defined in this module (not in the table), in order."""
    return [r.name for r in _ROBOTS]


def builtin_names():
    """set of str: names of the robots that ship with CadRobot (not imported by the user)."""
    return {r.name for r in _ROBOTS} | {r.name for r in _table_robots()}


def names():
    """list of str: catalog names, in catalog order."""
    return [r.name for r in specs()]


def get(name):
    """The :class:`RobotSpec` called `name`.

    Raises
    ------
    UnknownNameError
        When the catalog has no such robot.
    """
    try:
        return _by_name()[name]
    except (KeyError, TypeError):
        pass
    known = names()
    skipped = [p for p in user_folder_problems() if "%s%s.csv" % (os.sep, name) in p]
    if skipped:
        raise UnknownNameError(skipped[0])
    close = [n for n in known if isinstance(name, str) and name.upper() in n]
    if command_line.in_gui():
        where = "New cell lists them and imports a URDF (Import URDF...)"
    else:
        where = ("run `%s` to list them, or import its URDF with `%s`"
                 % (command_line.as_typed("robots"), command_line.as_typed("robots", "--import",
                                                                          "FILE.urdf")))
    raise UnknownNameError("Unknown robot '%s'. %s%d robots are known: %s." % (
        name, ("Did you mean %s? " % ", ".join(close[:5])) if close else "", len(known), where))
