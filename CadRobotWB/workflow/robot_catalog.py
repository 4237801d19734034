"""The robots a user can pick: their names, their models, URDF arms imported and edited.

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import os
import re

import numpy as np

from .. import preferences
from ..errors import InputError, NameTakenError
from ..robots.catalog import catalog
from ..robots.kinematics import models
from .arguments import ROBOT_NAME, Arguments


def robot(name):
    """The kinematic model of catalog robot `name`.

    ``fk(q_deg)``: (N, 6) degrees -> (N, 4, 4) flange poses in {R}, mm;
    ``ik(T_r_f)``: (N, 4, 4) -> (N, M, 6) degrees, NaN rows where a branch does
    not exist (``M = model.max_solutions``: 8 for OPW and UR arms, up to 16 for an
    offset wrist); ``within_limits(q_deg)``; ``spec`` is the catalog entry.
    """
    Arguments("robot").text("name", name, expected=ROBOT_NAME)
    preferences.use_user_robot_folder()
    return models.model(name)


def robot_names():
    """Names of every robot a user can pick: the catalog's and the imported ones.

    In FreeCAD's GUI, each file of the user robot folder that was skipped
    (:func:`catalog.user_folder_problems`) is one warning in the report view,
    once a session; the CLI prints them itself (``cadrobot robots``)."""
    preferences.use_user_robot_folder()
    names = catalog.names()
    _report_skipped_files()
    return names


_reported = set()


def mechanism_names(kind=None):
    """Names of the catalog's tracks and positioners, sorted (``cadrobot mechanisms`` lists them).

    `kind`: ``"track"``, ``"turntable"`` or ``"tilt_turn"`` for only those;
    each name is a ``model`` of :func:`api.add_track` / :func:`api.add_positioner`."""
    from ..core.mechanisms import KINDS
    from ..robots.mechanisms import catalog as mechanism_catalog
    Arguments("mechanism_names").choice("kind", kind, KINDS, optional=True)
    return mechanism_catalog.names(kind)


def _report_skipped_files():
    import FreeCAD
    if not FreeCAD.GuiUp:
        return
    for problem in catalog.user_folder_problems():
        if problem not in _reported:
            _reported.add(problem)
            FreeCAD.Console.PrintWarning("CadRobot: %s\n" % problem)


def import_robot(path, name=None, maker=None, j23_factor=None):
    """Register the six-axis arm of a URDF file; it stays in the catalog in later sessions.

    The file's serial chain from its root link to ``tool0`` (else its last
    link) is read and its kinematics recognised (OPW or UR type); the model
    is compared with the URDF's own chain on 1000 random joint sets within
    the limits and refused when they differ by more than 1e-6 mm or 1e-9 rad.
    Joint limits and speeds come from the file (placeholder speeds are
    flagged in the robot's notes); link solids are the convex hulls of its
    collision meshes (found beside the file; simple solids otherwise).

    Parameters
    ----------
    path : str
        A ``.urdf`` file, or a ``.xacro`` file when the Python package
        ``xacro`` is installed.
    name : str, optional
        Catalog name; default from the URDF's robot name.  Importing again
        under the same name replaces the earlier import.
    maker : str, optional
        Default: guessed from the file (its robot name and mesh paths); it
        chooses the default post-processor.
    j23_factor : int, optional
        ``k`` of the controller's ``J3 = q3 + k * q2`` in the file's joints: 1 for
        a parallel-arm robot whose controller counts J3 against the base (ABB's
        J23_coupled), -1 for FANUC's J3 from the horizontal, 0 when the
        controller's joints are the file's.  Default: the maker's convention
        (``robots.catalog.makers``).

    The robot is stored in the user robot folder
    (``preferences.user_robot_folder()``: ``$CADROBOT_ROBOT_FOLDER``, else the
    ``UserRobotFolder`` preference, else ``CadRobot/robots`` in FreeCAD's user
    data folder) as ``NAME.csv`` (a row of the catalog table, editable: limits,
    speeds, payload) and ``NAME.npz`` (link hulls).

    Returns
    -------
    str
        The catalog name it registered; its ``fk``/``ik`` take the URDF's joint
        values (degrees), base = the URDF's root link, flange = ``tool0``.

    Raises
    ------
    InputError
        The file cannot be read, is not a six-axis arm, its kinematics is
        neither OPW nor UR type (the message says what it is), or `name` is a
        built-in robot's.
    """
    from ..robots.urdf import from_urdf
    args = Arguments("import_robot")
    path = args.file_path("path", path, what="the path of a .urdf file")
    args.text("name", name, optional=True, expected="None or a robot name (a str)")
    args.text("maker", maker, optional=True, expected="None or a maker's name (a str)")
    args.whole_number("j23_factor", j23_factor, optional=True, expected="None, -1, 0 or 1")
    folder = preferences.user_robot_folder()
    if not os.path.isfile(path):
        raise InputError("There is no file '%s': give the path of a .urdf file." % path)
    robot = from_urdf.read_robot(path)
    maker = from_urdf.guess_maker(robot) if maker is None else maker
    name = _checked_name(from_urdf.name_from(robot.name) if name is None else name)
    if name in catalog.builtin_names():
        raise NameTakenError("'%s' is the name of a robot that ships with CadRobot: import the "
                             "file under another name (name='MY_%s', or --name on the command "
                             "line)." % (name, name), "MY_" + name)
    default_post, maker_j23 = from_urdf.maker_defaults(maker, robot.name)
    if j23_factor is None:
        j23_factor = maker_j23
    elif j23_factor not in (-1, 0, 1):
        raise InputError("j23_factor must be -1, 0 or 1, not %r." % (j23_factor,))
    imported = from_urdf.spec_from_urdf(
        path, name, maker=maker, model=robot.name, j23_factor=j23_factor,
        payload_kg=from_urdf.payload_from_model(maker, robot.name),
        default_post=default_post, source=os.path.abspath(path), robot=robot)
    from_urdf.save_user_robot(imported, folder)
    catalog.set_user_folder(folder)
    catalog.forget_user_robots()
    return name


def _finite(values, count, what):
    """`count` finite floats of `values`; else InputError starting with `what`."""
    try:
        numbers = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        numbers = ()
    if len(numbers) != count or not all(np.isfinite(numbers)):
        raise InputError("%s needs %d finite number%s, not %r." % (what, count, "s" * (count > 1),
                                                                   values))
    return numbers


#: Names a file may not have on Windows, whatever its extension.
RESERVED_NAMES = {"CON", "PRN", "AUX", "NUL"} | {"%s%d" % (d, i) for d in ("COM", "LPT")
                                                  for i in range(1, 10)}


def _checked_name(name):
    """`name` when it can name a robot and its files; else InputError saying how."""
    from ..robots.catalog.catalog_table import MAX_NAME
    from ..robots.urdf import from_urdf
    if not isinstance(name, str) or not name.strip():
        raise InputError("Robot name %r is empty: give a name of letters, digits and _ "
                         "(name=..., or --name on the command line)." % (name,))
    shown = name if len(name) <= 40 else name[:37] + "..."
    if not re.fullmatch(r"[A-Za-z0-9_]+", name):
        raise InputError("Robot name %r: use letters, digits and _ only (e.g. '%s')."
                         % (shown, from_urdf.name_from(name)))
    if len(name) > MAX_NAME:
        raise InputError("Robot name '%s' has %d characters: give at most %d (e.g. '%s')."
                         % (shown, len(name), MAX_NAME, from_urdf.name_from(name)))
    if name.upper() in RESERVED_NAMES:
        raise InputError("Robot name '%s' is a device name on Windows, which cannot name its "
                         "files: give another (e.g. 'ROBOT_%s')." % (name, name))
    return name


def edit_robot(name, joint_min_deg=None, joint_max_deg=None, joint_speed_deg_s=None,
               payload_kg=None, j23_factor=None):
    """Change the limits, speeds, payload or J2/J3 convention of an imported robot.

    Parameters
    ----------
    name : str
        A robot imported with :func:`import_robot` (robots that ship with
        CadRobot keep their data).
    joint_min_deg, joint_max_deg, joint_speed_deg_s : sequence of 6 float, optional
        Degrees and degrees per second, in the controller's convention.
    payload_kg : float, optional
    j23_factor : int, optional
        -1, 0 or 1 (see :func:`import_robot`).

    Returns
    -------
    RobotSpec
        The robot as stored now.

    Raises
    ------
    InputError
        Not an imported robot, or a value out of range (nothing is changed).
    """
    import dataclasses

    from ..robots.catalog import catalog_table
    args = Arguments("edit_robot")
    args.text("name", name, expected=ROBOT_NAME)
    for argument, values in (("joint_min_deg", joint_min_deg), ("joint_max_deg", joint_max_deg),
                             ("joint_speed_deg_s", joint_speed_deg_s)):
        args.numbers(argument, values, optional=True, expected="None or 6 numbers")   # how many: below
    args.number("payload_kg", payload_kg, optional=True, expected="None or a mass in kg (a number)")
    args.whole_number("j23_factor", j23_factor, optional=True, expected="None, -1, 0 or 1")
    preferences.use_user_robot_folder()
    spec = catalog.get(name)
    path = os.path.join(catalog.user_folder(), name + ".csv")
    if name in catalog.builtin_names() or not os.path.isfile(path):
        raise InputError("Robot %s ships with CadRobot: its data stay as they are. Import its "
                         "URDF under another name to change them." % name)
    changes = {}
    for field, values in (("joint_min_deg", joint_min_deg), ("joint_max_deg", joint_max_deg),
                          ("joint_speed_deg_s", joint_speed_deg_s)):
        if values is not None:
            changes[field] = _finite(values, 6, "Robot %s: %s" % (name, field))
    low = changes.get("joint_min_deg", spec.joint_min_deg)
    high = changes.get("joint_max_deg", spec.joint_max_deg)
    if any(a >= b for a, b in zip(low, high)):
        raise InputError("Robot %s: every joint's minimum must be below its maximum (%s, %s)."
                         % (name, low, high))
    if any(v <= 0 for v in changes.get("joint_speed_deg_s", (1,))):
        raise InputError("Robot %s: joint speeds must be positive." % name)
    if payload_kg is not None:
        changes["payload_kg"], = _finite([payload_kg], 1, "Robot %s: payload_kg" % name)
        if changes["payload_kg"] <= 0:
            raise InputError("Robot %s: payload_kg must be above 0, not %r." % (name, payload_kg))
    if j23_factor is not None:
        if j23_factor not in (-1, 0, 1):
            raise InputError("Robot %s: j23_factor must be -1, 0 or 1, not %r." % (name, j23_factor))
        changes.update(j23_coupled=bool(j23_factor), j23_factor=j23_factor or 1)
    edited = [f for f in ("joint_speed_deg_s", "j23_factor") if f in changes]
    changes["uncertain"] = tuple(f for f in spec.uncertain if f not in edited)
    spec = dataclasses.replace(spec, **changes)
    catalog_table.write_table(path, [catalog_table.row_from_spec(spec, os.path.basename(spec.meshes))])
    catalog.forget_user_robots()
    return catalog.get(name)
