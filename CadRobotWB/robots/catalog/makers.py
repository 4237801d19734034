"""Per-maker conventions: default post and how the controller counts J3.

A URDF's joints are what its ROS driver publishes.  Most drivers pass the
controller's joint values through unchanged (only degrees to radians), so
the URDF's joints are the controller's.  Two do not, for J3 only:

* ABB's ``abb_driver`` with ``J23_coupled: true`` (parallel-arm robots):
  controller J3 = URDF q3 + URDF q2;
* FANUC's ``fanuc_driver`` with its ``J23_factor`` (every FANUC arm in the
  data folder): FANUC's J3 is the upper arm's angle from the horizontal,
  controller J3 = URDF q3 - J23_factor * URDF q2.

Both are written here as one integer ``k``, :func:`j23_factor`::

    J3_controller = q3_urdf + k * q2_urdf        (degrees or radians)

with ``k = 0`` when the driver converts nothing, and ``None`` where no
source was found.  Joint limits and joint positions in the controller's
programs and data sheets are in the controller's convention.

Maker names are spelled as in ``shared/data/robots/sources.json`` (field
``maker``).  Every claim names its source (repository, path and commit of
the public code read, or the manual); nothing is assumed without one.

Pure Python: never imports FreeCAD.
"""

import re
from dataclasses import dataclass
from typing import Optional, Tuple

from ...errors import UnknownNameError


@dataclass(frozen=True)
class MakerConvention:
    """What CadRobot knows about one maker's controllers.

    Attributes
    ----------
    maker : str
        As in sources.json's ``maker`` field, e.g. ``"Yaskawa Motoman"``.
    default_post : str or None
        The post a new cell of this maker's arm starts with; None when
        CadRobot has no post for its language yet (the user picks one).
    language : str
        The controller's robot language.
    j23 : str
        ``"none"`` (driver converts no joint), ``"per_model"`` (ABB: the
        support package of each model says), ``"fanuc"`` (FANUC's
        J23_factor) or ``"unknown"``.
    convention : str
        One paragraph: the controller's joint convention against the URDF's.
    sources : tuple of str
        Where each statement comes from.
    """

    maker: str
    default_post: Optional[str]
    language: str
    j23: str
    convention: str
    sources: Tuple[str, ...]


_ABB = MakerConvention(
    maker="ABB",
    default_post="abb_rapid",
    language="RAPID (IRC5 / S4C+)",
    j23="per_model",
    convention=(
        "ROS-Industrial's abb_driver passes the controller's axis values through (degrees to "
        "radians) except on robots whose support package sets J23_coupled: true, the "
        "parallel-arm robots (IRB 2400, IRB 4400, IRB 5400 in the data folder), where the "
        "state node applies linkage_transform with factor -1 (ROS J3 = controller J3 - J2) "
        "and the motion node the inverse: controller J3 = URDF q3 + URDF q2, the upper arm's "
        "angle against the base.  ABB's joint limits for those robots (data sheet: IRB 2400 "
        "axis 3 +65/-60) are for that J3.  The URDFs' axes turn the way ABB's do (checked on "
        "the IRB 2400, 2600 and 4600: same flange for the same joint values as CadRobot's "
        "catalog models)."),
    sources=(
        "abb_driver robot state node (J23_coupled -> linkage_transform factor -1 for "
        "motor->joint): copy in krebsalad/ProjectAbsoluteAccuracy "
        "abb_driver/src/abb_robot_state_node.cpp @3ee7fa6b; linkage_transform adds "
        "factor * J2 to J3 (ros-industrial/fanuc fanuc_driver/src/fanuc_utils.cpp @93b75377, "
        "'basically a copy of abb_utils.cpp')",
        "per-model J23_coupled: the robot_interface_download_*.launch files of the support "
        "packages in ros-industrial/abb and ros-industrial/abb_experimental (see "
        "j23_source())",
        "ros-industrial/abb_experimental PR #139 / #155 ('Correct J23_coupled default for "
        "serial robots', merged 2025-04-04); ros-industrial/abb PR #68 (IRB 5400 true, "
        "'confirmed by RobotStudio') and issue #206 (IRB 5400 to be verified again)",
    ),
)

_FANUC = MakerConvention(
    maker="FANUC",
    default_post="fanuc_ls",
    language="TP / LS (R-30iA, R-30iB)",
    j23="fanuc",
    convention=(
        "FANUC's controller measures J3 from the horizontal (the J2/J3 interaction): ROS-"
        "Industrial's fanuc_driver converts with the integer parameter J23_factor, which the "
        "driver's generic launch file requires (no default; the state node assumes 0 and logs "
        "an error when it is missing, the motion node refuses to start).  The state node "
        "publishes ROS J3 = controller J3 + J23_factor * J2, the motion node sends controller "
        "J3 = ROS J3 - J23_factor * J2.  Every support package read sets J23_factor = 1 (URDF "
        "J3 axis -Y: controller J3 = q3 - q2); the M-430iA sets -1 (its URDF J3 axis is +Y: "
        "controller J3 = q3 + q2).  FANUC's joint limits are in the controller's J3."),
    sources=(
        "ros-industrial/fanuc fanuc_driver/src/fanuc_utils.cpp @93b75377 (linkage_transform: "
        "J3 += J23_factor * J2)",
        "ros-industrial/fanuc fanuc_driver/src/fanuc_robot_state_node.cpp @93b75377 "
        "(J23_factor_ default 0, ROS_ERROR when missing) and "
        "fanuc_driver/src/fanuc_joint_streamer_node.cpp @37ea311a ('sending points back to "
        "the Fanuc, so invert factor'; runtime_error when missing)",
        "ros-industrial/fanuc fanuc_driver/launch/robot_interface_streaming.launch @ed3dfe5b "
        "(J23_factor: -1, 0 or 1; no default)",
        "J23_factor = 1: ros-industrial/fanuc fanuc_m10ia_support/launch/"
        "robot_interface_streaming_m10ia.launch @ed3dfe5b, fanuc_lrmate200ic_support/launch/"
        "robot_interface_streaming_lrmate200ic.launch @ed3dfe5b and "
        "robot_interface_streaming_cr7ial.launch @fe0b7675; ros-industrial/fanuc_experimental "
        "fanuc_r2000ic_support/launch/robot_interface_streaming_r2000ic125l.launch @d2912705",
        "J23_factor = -1: fanuc_m430ia_support robot_interface_streaming_m430ia2f.launch "
        "('Defaults provided for M-430iA/2F: J23_factor = -1')",
    ),
)

_KUKA = MakerConvention(
    maker="KUKA",
    default_post="kuka_krl",
    language="KRL (KR C2 / KR C4 / KR C5)",
    j23="none",
    convention=(
        "KUKA's RSI interface reports the axis values A1..A6 and ROS-Industrial's "
        "kuka_rsi_hw_interface only converts degrees to radians (joint_position = DEG2RAD * "
        "AIPos): the URDF's joints are KUKA's A1..A6, no J3 coupling, no sign change.  "
        "Checked on the KR 16-2 URDF: the same joint values give CadRobot's KUKA_KR16 flange "
        "to 1e-12 mm.  Not checked for kroshu's ROS 2 kuka_drivers (its RSI driver source "
        "was not read)."),
    sources=(
        "ros-industrial/kuka_experimental kuka_rsi_hw_interface/src/kuka_hardware_interface.cpp "
        "@0c4927c9 (read(): joint_position_[i] = DEG2RAD * rsi_state_.positions[i])",
    ),
)

_MOTOMAN = MakerConvention(
    maker="Yaskawa Motoman",
    default_post="motoman_inform",
    language="INFORM (NX100 / DX100 / DX200 / YRC1000)",
    j23="none",
    convention=(
        "MotoROS (motoman_driver) converts each axis's pulse count to radians with that "
        "axis's pulse-per-radian factor, in the controller's order S, L, U, R, B, T: the "
        "URDF's joints are the controller's pulse positions, no J2/J3 conversion.  The "
        "mechanical cross-axis coupling correction it applies works on motor pulses of the "
        "feedback position, so the published joints are the controller's joint values.  "
        "Zeros differ between models: on the ROS-I MH/GP URDFs B = 0 is the wrist in line "
        "with the forearm, on the MotoMINI B = 0 is the flange pointing down, as on the HP6 "
        "(catalog MOTOMAN_HP6)."),
    sources=(
        "ros-industrial/motoman motoman_driver/MotoPlus/CtrlGroup.c @1289a814 "
        "(Ros_CtrlGroup_ConvertToRosPos: rosPos[i] = pulsePos[i] / pulseToRad.PtoR[i]; "
        "Ros_CtrlGroup_GetFBPulsePos: cross-axis correction on feedback pulses)",
    ),
)

_STAUBLI = MakerConvention(
    maker="Staubli",
    default_post=None,
    language="VAL3 (CS8 / CS9)",
    j23="none",
    convention=(
        "staubli_val3_driver's joint feedback handler copies the joint positions the VAL3 "
        "server sends into the ROS joint states with no transform (the code has only a "
        "'transform joint data?' placeholder): the URDF's joints are the controller's, no J3 "
        "coupling.  CadRobot has no VAL3 post yet."),
    sources=(
        "ros-industrial/staubli_val3_driver staubli_val3_driver/src/industrial_robot_client/"
        "joint_feedback_relay_handler.cpp @54ccabcb (createMessages)",
    ),
)

_UR = MakerConvention(
    maker="Universal Robots",
    default_post="ur_script",
    language="URScript (CB3 / e-Series)",
    j23="none",
    convention=(
        "The UR ROS 2 driver reads the RTDE field actual_q (the controller's joint positions, "
        "radians) straight into the joint states: the URDF's joints are the controller's.  "
        "UR measures every joint against the previous link; no coupling."),
    sources=(
        "UniversalRobots/Universal_Robots_ROS2_Driver ur_robot_driver/src/hardware_interface.cpp "
        "@ca5fb3e2 (read(): readData(data_pkg, \"actual_q\", urcl_joint_positions_))",
    ),
)

_KAWASAKI = MakerConvention(
    maker="Kawasaki",
    default_post=None,
    language="AS (E / F controllers)",
    j23="none",
    convention=(
        "khi_robot's KRNX driver copies the controller's current joint angles "
        "(krnx_GetCurMotionData ang, radians; prismatic joints mm to m) into the joint "
        "states and sends back offsets from the same values: the URDF's joints are the "
        "controller's, no J3 coupling.  CadRobot has no AS post yet."),
    sources=(
        "Kawasaki-Robotics/khi_robot khi_robot_control/src/khi_robot_krnx_driver.cpp @0e7d6e12 "
        "(readData: data.arm[ano].pos[jt] = ang[ano][jt]; writeData: cmd - home)",
    ),
)

_DENSO = MakerConvention(
    maker="DENSO",
    default_post=None,
    language="PacScript (RC8 / RC9)",
    j23="none",
    convention=(
        "denso_robot_control reads the controller's current joints (b-CAP CurJnt, degrees) "
        "and converts only the unit (DEG2RAD; mm to m for prismatic axes), and writes back "
        "RAD2DEG: the URDF's joints are the controller's, no J3 coupling.  CadRobot has no "
        "PacScript post yet."),
    sources=(
        "DENSORobot/denso_robot_ros denso_robot_control/src/denso_robot_hw.cpp @0bd656cd "
        "(read(): m_pos[i] = DEG2RAD(m_joint[i]))",
    ),
)

_BY_MAKER = {c.maker: c for c in (_ABB, _DENSO, _FANUC, _KAWASAKI, _KUKA, _STAUBLI, _UR,
                                   _MOTOMAN)}

#: The makers of ``shared/data/robots`` (sources.json's spelling).
MAKERS = tuple(sorted(_BY_MAKER))

#: Other spellings accepted by :func:`convention` (lower case, no punctuation).
_ALIASES = {"yaskawa": "Yaskawa Motoman", "motoman": "Yaskawa Motoman",
            "staubli": "Staubli", "stäubli": "Staubli", "ur": "Universal Robots",
            "universalrobots": "Universal Robots", "kawasaki": "Kawasaki",
            "kawasakirobotics": "Kawasaki", "denso": "DENSO", "densowave": "DENSO",
            "abb": "ABB", "fanuc": "FANUC", "kuka": "KUKA", "yaskawamotoman": "Yaskawa Motoman"}


# --- ABB: J23_coupled per model, as the support packages set it ------------------------------

_ABB_GIT = "ros-industrial/abb"
_ABB_EXP = "ros-industrial/abb_experimental"

#: (model key, J23_coupled or None, source).  The key is matched against the start of the
#: model name with everything but letters and digits removed and any leading "abb" dropped.
_ABB_J23 = (
    ("irb2400", True, "%s abb_irb2400_support/launch/robot_interface_download_irb2400.launch "
     "@10411781 (J23_coupled default true); parallel J2/J3 linkage (the 12/1.55 URDF models "
     "its levers as mimic joints of joint_3)" % _ABB_GIT),
    ("irb4400", True, "%s abb_irb4400_support/launch/robot_interface_download_irb4400l_30_243"
     ".launch @dab0605a (default true)" % _ABB_GIT),
    ("irb5400", True, "%s abb_irb5400_support/launch/robot_interface_download_irb5400.launch "
     "@2093c17d (default true; PR #68: 'confirmed by RobotStudio'; issue #206 asks to verify "
     "it again)" % _ABB_GIT),
    ("irb120", False, "%s abb_irb120_support/launch/robot_interface_download_irb120_3_58.launch "
     "@8a615080 (default false)" % _ABB_GIT),
    ("irb1200", False, "%s abb_irb1200_support/launch/robot_interface_download_irb1200_5_90"
     ".launch @3a9c9bfa and ..._7_70.launch (%s @30e6c442) (default false)"
     % (_ABB_EXP, _ABB_GIT)),
    ("irb1600", False, "serial arm: the 7/1.45 and 8/1.45 launch files default to false "
     "(%s @85663ac0, %s @7e1505fb); older 6/1.2 and 10/1.45 files said true, which "
     "abb_experimental PR #139/#155 ('Correct J23_coupled default for serial robots', the "
     "author: 'the mismatch between the previous irb1600 default of J23_coupled = true') "
     "set to false" % (_ABB_EXP, _ABB_GIT)),
    ("irb2600", False, "%s abb_irb2600_support/launch/robot_interface_download_irb2600_12_165"
     ".launch @566bf7ed (default false)" % _ABB_GIT),
    ("irb4600", False, "%s abb_irb4600_support/launch/robot_interface_download_irb4600_60_205"
     ".launch @21cd30e0 (default false)" % _ABB_GIT),
    ("irb6600", False, "%s abb_irb6600_support/launch/robot_interface_download_irb6600.launch "
     "@10411781 (default false)" % _ABB_GIT),
    ("irb6640", False, "%s abb_irb6600_support/launch/robot_interface_download_irb6640.launch "
     "@39b455c2 and abb_irb6640_support/launch/robot_interface_download_irb6640_185_280.launch "
     "@9c626548 (default false)" % _ABB_GIT),
    ("irb6700", False, "%s abb_irb6700_support/launch/robot_interface_download_irb6700_235_265"
     ".launch @e104027b (default false); an older copy of the file (@3111b717, its comment "
     "copied from the IRB 52) and the 200/2.60 file read (@9ba2c584) say true: serial arm, "
     "its URDF mimic joints are the J2 balancing cylinder, not a J3 linkage" % _ABB_GIT),
    ("irb6650s", None, "unknown: %s abb_irb6650s_support/launch/robot_interface_download_"
     "irb6650s_125_350.launch @6740bbd9 says true, but abb_experimental PR #155 corrected "
     "the defaults of serial robots to false and the version read may predate it; not "
     "verified" % _ABB_GIT),
    ("irb52", None, "unknown: %s abb_irb52_support/launch/robot_interface_download_irb52_7_120"
     ".launch @aad3e2ac says true, but abb_experimental PR #155 corrected the defaults of "
     "serial robots to false and the version read may predate it; not verified" % _ABB_GIT),
    ("crb15000", False, "%s abb_crb15000_support/launch/robot_interface_download_crb15000"
     ".launch @4737a52a (default false)" % _ABB_EXP),
)

# --- FANUC: J23_factor per folder ------------------------------------------------------------

_FANUC_M430IA = ("m430ia", 1, "fanuc_m430ia_support robot_interface_streaming_m430ia2f.launch: "
                 "J23_factor = -1 (URDF J3 axis +Y): controller J3 = q3 + q2")
_FANUC_CRX = ("crx", -1, "as FANUC's other arms (URDF J3 axis -Y): controller J3 = q3 - q2; "
              "ros-industrial/fanuc_experimental's fanuc_crx10ia_support has no driver launch "
              "file, but a third party's CRX-10iA table of ROBOGUIDE and Abbes-Poisson 2024 "
              "solutions (frfournier/robodk_crx_kinematics tests/fixtures/CRX10iA-solutions.csv "
              "@1ce15fc) reproduces its positions to 0.03 mm with J3 counted so (81 of 83 rows), "
              "and danielcranston/crx_kinematics DERIVATION.md: on the controller 'J3=0 means a "
              "horizontal forearm, regardless of the angle of the upper arm' (secondary sources)")
_FANUC_DEFAULT = ("", -1, "J23_factor = 1, as every FANUC support package read sets it (M-10iA, "
                  "LR Mate 200iC, CR-7iA/L, R-2000iC/125L; URDF J3 axis -Y): controller J3 = "
                  "q3 - q2")


def convention(maker):
    """The :class:`MakerConvention` of a maker.

    Parameters
    ----------
    maker : str
        As in sources.json (``"Yaskawa Motoman"``), or a common other spelling
        (``"Yaskawa"``, ``"Stäubli"``, ``"UR"``), any case.

    Returns
    -------
    MakerConvention

    Raises
    ------
    UnknownNameError
        For a maker CadRobot knows nothing about.
    """
    if maker in _BY_MAKER:
        return _BY_MAKER[maker]
    key = re.sub(r"[^0-9a-zä]", "", str(maker).lower())
    for name in _BY_MAKER:
        if re.sub(r"[^0-9a-z]", "", name.lower()) == key:
            return _BY_MAKER[name]
    if key in _ALIASES:
        return _BY_MAKER[_ALIASES[key]]
    raise UnknownNameError("Unknown robot maker %r. Known makers: %s."
                           % (maker, ", ".join(MAKERS)))


def default_post(maker):
    """The post a new cell of this maker's arm starts with.

    Returns
    -------
    str or None
        A post name (``"abb_rapid"``, ...), or None when CadRobot has no post
        for the maker's language (Stäubli VAL3, Kawasaki AS, DENSO PacScript).
    """
    return convention(maker).default_post


def _model_key(folder_or_model, maker_prefix):
    key = re.sub(r"[^0-9a-z]", "", str(folder_or_model).lower())
    return key[len(maker_prefix):] if key.startswith(maker_prefix) else key


def _abb_row(folder_or_model):
    key = _model_key(folder_or_model, "abb")
    for model, coupled, source in sorted(_ABB_J23, key=lambda row: -len(row[0])):
        if key.startswith(model):
            return coupled, source
    return None, ("unknown: no ROS-Industrial support package for ABB model %r was read"
                  % (folder_or_model,))


def _fanuc_row(folder_or_model):
    key = _model_key(folder_or_model, "fanuc")
    for model, k, source in (_FANUC_M430IA, _FANUC_CRX):
        if key.startswith(model):
            return k, source
    return _FANUC_DEFAULT[1], _FANUC_DEFAULT[2]


def j23_factor(maker, folder_or_model):
    """How the controller's J3 relates to the URDF's joints.

    ``J3_controller = q3_urdf + k * q2_urdf`` (same unit for all three).

    Parameters
    ----------
    maker : str
        See :func:`convention`.
    folder_or_model : str
        A data folder (``"abb_irb2400_12_155"``) or a model name
        (``"IRB 2400/10"``, ``"m20ia"``); only ABB and FANUC look at it.

    Returns
    -------
    int or None
        ``1`` (ABB J23_coupled; FANUC M-430iA), ``-1`` (FANUC J23_factor = 1),
        ``0`` (the driver converts nothing), None when unknown
        (:func:`j23_source` says why).
    """
    conv = convention(maker)
    if conv.j23 == "none":
        return 0
    if conv.j23 == "per_model":
        coupled, _ = _abb_row(folder_or_model)
        return None if coupled is None else int(coupled)
    if conv.j23 == "fanuc":
        return _fanuc_row(folder_or_model)[0]
    return None


def j23_coupled(maker, folder_or_model):
    """True when the controller's J3 is not the URDF's q3 (see :func:`j23_factor`).

    Returns
    -------
    bool or None
        None when unknown (:func:`j23_source` says why).
    """
    k = j23_factor(maker, folder_or_model)
    return None if k is None else k != 0


def j23_source(maker, folder_or_model):
    """The source (or the reason for "unknown") behind :func:`j23_factor`.

    Returns
    -------
    str
    """
    conv = convention(maker)
    if conv.j23 == "per_model":
        return _abb_row(folder_or_model)[1]
    if conv.j23 == "fanuc":
        return _fanuc_row(folder_or_model)[1]
    return "; ".join(conv.sources)
