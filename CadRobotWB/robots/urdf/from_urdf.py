"""A catalog entry (:class:`~.catalog.RobotSpec`) built from a URDF file.

:func:`spec_from_urdf` reads the file (:mod:`.urdf`), recognises and checks
its kinematics (:mod:`.identify`) and takes the joint limits and speeds from
it; :func:`write_meshes` makes the link hulls (:mod:`.link_meshes`).  Used by
``api.import_robot`` and by ``tools/build_catalog.py``, which makes the
catalog table from the data folder.

The entry's joints are the URDF's joints (degrees), its base frame {R} the
URDF's root link and its flange {F} the URDF's ``tool0`` (else the last
link).

Pure numpy: never imports FreeCAD.
"""

import dataclasses
import os
import re
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from . import identify, link_meshes, urdf, xacro_files
from ..catalog import catalog
from ..kinematics import chain_geometry, models

#: Speed used where a URDF gives none, deg/s (flagged as uncertain).
MISSING_SPEED_DEG_S = 90.0
#: Limits and speeds are rounded to this many decimals of a degree: URDFs write
#: radians with 4 or 5 decimals (2.9671 for 170 deg reads 169.9966 deg).
LIMIT_DECIMALS = 2


@dataclass(frozen=True)
class Imported:
    """What :func:`spec_from_urdf` found.

    Attributes
    ----------
    spec : RobotSpec
    robot : urdf.UrdfRobot
    chain : urdf.Chain
    worst_mm, worst_rad : float
        Largest flange differences between the model and the URDF chain on
        the checked joint sets.
    """

    spec: catalog.RobotSpec
    robot: urdf.UrdfRobot
    chain: urdf.Chain
    worst_mm: float
    worst_rad: float


def _nested(T):
    return tuple(tuple(float(v) for v in row) for row in np.asarray(T))


def _or_none(T):
    return None if np.allclose(T, np.eye(4), rtol=0.0, atol=1e-15) else _nested(T)


def payload_from_model(maker, model):
    """The rated payload the model designation states, or None.

    Only designations whose naming rule states the payload are read: ABB
    ``irb<type>_<payload>_<reach>``, KUKA ``kr<payload>...`` (``l<payload>``
    for the L variants), Universal Robots ``ur<payload>``, Yaskawa
    ``gp/mh/hc/ms/es<payload>`` (``_<payload>`` for reduced-payload variants),
    Kawasaki ``rs<payload>n/l``, FANUC ``cr<payload>ia`` and ``crx<payload>ia``.

    Parameters
    ----------
    maker : str
        As in :mod:`.makers`.
    model : str
        The designation as ROS-Industrial's package names it, e.g. ``irb1600_6_12``.

    Returns
    -------
    float or None
        kg.
    """
    model = model.lower()
    for prefix in ("abb_", "kuka_", "fanuc_", "motoman_", "kawasaki_"):
        model = model[len(prefix):] if model.startswith(prefix) else model
    rules = {
        "ABB": r"^(?:irb\d+[a-z]*|crb\d+)_(\d+)_\d+$",
        "KUKA": r"^kr(\d+)(?:_|r|$)",
        "Universal Robots": r"^ur(\d+)e?$",
        "Yaskawa Motoman": r"^(?:gp|mh|hc|ms|es)(\d+)(?:l|r|dt.*)?$",
        "Kawasaki": r"^rs0*(\d+)[nl]$",
        "FANUC": r"^crx?(\d+)ial?$",
    }
    special = re.match(r"^kr\d+_?l(\d+)", model) or re.match(r"^(?:gp|mh|es)\d+_(\d+)$", model)
    if special and maker in ("KUKA", "Yaskawa Motoman"):
        return float(special.group(1))
    match = re.match(rules.get(maker, r"$^"), model)
    return float(match.group(1)) if match else None


def name_from(text):
    """A catalog name from a file or robot name: upper case, letters, digits and ``_``,
    at most :data:`.catalog_table.MAX_NAME` characters."""
    from ..catalog.catalog_table import MAX_NAME
    return re.sub(r"[^A-Z0-9]+", "_", text.upper())[:MAX_NAME].strip("_") or "ROBOT"


def read_description(path):
    """The URDF text of a ``.urdf`` file, or of a ``.xacro`` file expanded.

    Raises
    ------
    InputError
        For a ``.xacro`` file that would read outside its folder and package
        (:func:`.xacro_files.check_includes`, checked first), declares a DTD
        or entities, when the ``xacro`` Python package is not installed, or
        when xacro fails.
    """
    if not path.lower().endswith(".xacro"):
        return path
    xacro_files.check_includes(path)
    try:
        import xacro  # noqa: F401  (PyPI 'xacro'; optional)
    except ImportError:
        raise InputError("'%s' is a xacro file and the Python package 'xacro' is not installed: "
                         "install it (pip install xacro) or expand the file first with "
                         "'xacro %s -o robot.urdf'." % (path, os.path.basename(path))) from None
    import xacro
    try:
        document = xacro.process_file(path)
    except Exception as exc:   # xacro raises many kinds; one clear line is what the user needs
        raise InputError("xacro could not expand '%s': %s" % (path, exc)) from None
    return document.toxml()


def read_robot(path):
    """The :class:`.urdf.UrdfRobot` of a ``.urdf`` (or expanded ``.xacro``) file, its
    ``path`` set so its mesh files are found beside it."""
    robot = urdf.read_urdf(read_description(path))
    return dataclasses.replace(robot, path=path)


def spec_from_urdf(path, name, maker="", model="", payload_kg=None, j23_factor=0,
                   default_post="", controller="", source="", license="", notes="",
                   samples=identify.SAMPLES, robot=None):
    """A catalog entry for the arm of a URDF file, checked against the file.

    Parameters
    ----------
    path : str
        A ``.urdf`` file (or ``.xacro``, with the ``xacro`` package).
    name : str
        Catalog name.
    maker, model, controller, source, license, notes : str
    payload_kg : float, optional
    j23_factor : int or None
        ``k`` of the controller's ``J3 = q3 + k * q2`` in the URDF's joints (0: the
        controller's joints are the URDF's; see ``RobotSpec.j23_factor`` and
        :mod:`.makers`); None when not known: then 0, and the notes say so.
    default_post : str
        Post-processor name, "" when the maker has none.
    samples : int
        Random joint sets on which model and chain are compared.
    robot : urdf.UrdfRobot, optional
        The file already read (:func:`read_robot`).

    Returns
    -------
    Imported

    Raises
    ------
    InputError
        The file cannot be read, is not a six-axis arm, or its kinematics is
        of no class CadRobot solves (:class:`.identify.KinematicsError`, saying why).
    """
    robot = read_robot(path) if robot is None else robot
    chain = urdf.serial_chain(robot)
    try:
        found = identify.identify(chain, samples)
        worst = identify.verify(found, chain, samples)
    except identify.KinematicsError as exc:
        raise identify.KinematicsError("'%s' (%s): %s." % (os.path.basename(path), robot.name,
                                                           exc)) from None
    lower, upper, speeds = (np.round(np.degrees(v), LIMIT_DECIMALS) + 0.0 for v in
                            (chain.lower_rad, chain.upper_rad, chain.velocity_rad_s))
    remarks = []
    uncertain = []
    if chain.tip != "tool0":
        remarks.append("Flange: %s." % chain.tip_note)
    if np.isnan(speeds).any():
        remarks.append("The URDF gives no speed for %s: %g deg/s assumed, edit it."
                       % (", ".join("J%d" % (i + 1) for i in np.flatnonzero(np.isnan(speeds))),
                          MISSING_SPEED_DEG_S))
        speeds = np.where(np.isnan(speeds), MISSING_SPEED_DEG_S, speeds)
        uncertain.append("joint_speed_deg_s")
    elif np.ptp(speeds) == 0.0:
        remarks.append("The URDF gives the same speed, %.4g deg/s, on every joint: most likely "
                       "a placeholder; edit the speeds from the data sheet." % speeds[0])
        uncertain.append("joint_speed_deg_s")
    linkage = j3_linkage(robot, chain)
    if j23_factor is None:
        remarks.append("How this controller counts J3 is not known (makers.j23_source): "
                       "the joint limits are read as the URDF's joints.")
        uncertain.append("j23_factor")
    if linkage and not j23_factor:
        remarks.append("The file models a linkage moved by J3 (%s): a parallel arm. If its "
                       "controller counts J3 against the base, import it with j23_factor=1."
                       % linkage)
    if notes:
        remarks.insert(0, notes)
    spec = catalog.RobotSpec(
        name=name, manufacturer=maker, model=model or robot.name, controller=controller,
        default_post=default_post, payload_kg=payload_kg,
        joint_min_deg=tuple(float(v) for v in lower), joint_max_deg=tuple(float(v) for v in upper),
        joint_speed_deg_s=tuple(float(v) for v in speeds),
        opw=found.params if found.kind == "opw" else None,
        ur=found.params if found.kind == "ur" else None,
        chain=_chain_axes(found.params) if found.kind == "chain" else None,
        j23_coupled=bool(j23_factor), j23_factor=j23_factor or 1, notes=" ".join(remarks),
        uncertain=tuple(uncertain),
        T_root_base=_or_none(found.T_root_base), T_flange_tip=_or_none(found.T_flange_tip),
        source=source, license=license)
    reach = (chain_geometry.reach_mm(found.params) if found.kind == "chain"
             else catalog.reach_mm(spec))
    spec = dataclasses.replace(spec, reach_mm=round(reach, 3))
    return Imported(spec, robot, chain, worst[0], worst[1])


def _chain_axes(params):
    """The catalog's :class:`~.catalog.ChainAxes` of :class:`.poe.ChainParameters`."""
    return catalog.ChainAxes(axes=tuple(tuple(float(v) for v in h) for h in params.H),
                             steps_mm=tuple(tuple(float(v) for v in p) for p in params.P))


def write_meshes(imported, path):
    """Write the link hulls of an imported arm; the spec that uses them.

    Parameters
    ----------
    imported : Imported
    path : str
        The ``.npz`` file to write.

    Returns
    -------
    spec : RobotSpec
        ``imported.spec`` with ``meshes`` set, or unchanged when no body has
        a collision shape (then nothing is written).
    missing : list of str
        Mesh files that could not be found or read.
    """
    model = models.as_model(imported.spec)
    T_link_chain = link_meshes.chain_in_link_frames(model, imported.chain)
    hulls, missing = link_meshes.body_hulls(imported.robot, imported.chain, T_link_chain)
    if all(h is None for h in hulls):
        return imported.spec, missing
    link_meshes.save(path, hulls)
    return dataclasses.replace(imported.spec, meshes=path), missing


#: Words of a URDF's robot name or mesh paths that name its maker (first match wins).
MAKER_WORDS = (
    ("Universal Robots", ("ur_description", "universal_robot")),
    ("ABB", ("abb_", "irb")),
    ("KUKA", ("kuka", "kr_", "lbr")),
    ("FANUC", ("fanuc", "lrmate")),
    ("Yaskawa Motoman", ("motoman", "yaskawa")),
    ("Staubli", ("staubli",)),
    ("Kawasaki", ("khi_", "kawasaki")),
    ("DENSO", ("denso",)),
)


def guess_maker(robot):
    """The maker a URDF names in its robot name or mesh references, or "".

    Parameters
    ----------
    robot : urdf.UrdfRobot

    Returns
    -------
    str
        A maker as the catalog spells it (:data:`MAKER_WORDS`).
    """
    words = [robot.name.lower()] + [g.filename.lower() for shapes in robot.collisions.values()
                                    for g in shapes]
    for maker, keys in MAKER_WORDS:
        if any(key in word for word in words for key in keys):
            return maker
    return ""


def j3_linkage(robot, chain):
    """Joints off the arm's chain that copy J3 (a parallel arm's levers), as text.

    Parameters
    ----------
    robot : urdf.UrdfRobot
    chain : urdf.Chain

    Returns
    -------
    str
        E.g. ``"joint_lever_a mimics joint_3"``; "" when there are none.
    """
    j3 = chain.joint_names[2]
    return ", ".join("%s mimics %s" % (j.name, j3) for j in robot.joints.values()
                     if j.mimic is not None and j.mimic[0] == j3 and j.name not in chain.joint_names)


def maker_defaults(maker, model):
    """The default post and J2/J3 factor of a maker's model (:mod:`.makers`).

    Parameters
    ----------
    maker, model : str

    Returns
    -------
    default_post : str
        "" when CadRobot has no post for the maker (or does not know it).
    j23_factor : int or None
        0 for a maker CadRobot does not know (its joints taken as the URDF's).
    """
    from ...errors import UnknownNameError
    from ..catalog import makers
    try:
        convention = makers.convention(maker)
    except UnknownNameError:
        return "", 0
    return convention.default_post or "", makers.j23_factor(maker, model)


def save_user_robot(imported, folder):
    """Store an imported arm in a user robot folder: ``<NAME>.csv`` (one table row)
    and ``<NAME>.npz`` (link hulls, when it has collision shapes).

    Both files are written under temporary names first and renamed only when
    both are complete, so a failure (a read-only or full folder) leaves the
    folder as it was.

    Parameters
    ----------
    imported : Imported
    folder : str
        Made when missing.

    Returns
    -------
    spec : RobotSpec
        As stored (``meshes`` set when hulls were written).
    missing : list of str
        Mesh files that could not be found or read (those bodies keep simple solids).

    Raises
    ------
    InputError
        The folder cannot be made or written (one line naming it; nothing written).
    """
    from ..catalog import catalog_table
    name = imported.spec.name
    meshes_path, table_path = (os.path.join(folder, name + ext) for ext in (".npz", ".csv"))
    staged = []
    try:
        os.makedirs(folder, exist_ok=True)
        spec, missing = write_meshes(imported, _staged(meshes_path, staged))
        if spec.meshes:
            spec = dataclasses.replace(spec, meshes=meshes_path)
        else:
            staged.clear()
        spec = _with_mesh_remark(spec, missing)
        row = catalog_table.row_from_spec(spec, os.path.basename(meshes_path) if spec.meshes else "")
        catalog_table.write_table(_staged(table_path, staged), [row])
        for temporary, final in staged:
            os.replace(temporary, final)
    except OSError as exc:
        for temporary, _ in staged:
            if os.path.exists(temporary):
                os.remove(temporary)
        raise InputError("Cannot write robot %s into the robot folder '%s' (%s): nothing was "
                         "written; make the folder writable or free space, or choose another "
                         "one ($CADROBOT_ROBOT_FOLDER or the UserRobotFolder preference)."
                         % (name, folder, exc.strerror or exc)) from None
    return spec, missing


def _staged(path, staged):
    """A temporary name beside `path` (not ``*.csv``: the catalog does not read it),
    recorded in `staged` as ``(temporary, path)``."""
    temporary = os.path.join(os.path.dirname(path), ".%s.%d.tmp" % (os.path.basename(path),
                                                                    os.getpid()))
    staged.append((temporary, path))
    return temporary


def _with_mesh_remark(spec, missing):
    """`spec` with a note saying which links are drawn with simple solids, and why."""
    if not missing and spec.meshes:
        return spec
    files = sorted({os.path.basename(m) for m in missing if m})
    remark = ("Link solids: the mesh files %s could not be found beside the URDF or read "
              "(.dae needs pycollada); those links are drawn as simple solids."
              % ", ".join(files)) if files else ("Link solids: the file has no collision "
                                                 "shapes; the links are drawn as simple solids.")
    return dataclasses.replace(spec, notes=(spec.notes + " " + remark).strip())
