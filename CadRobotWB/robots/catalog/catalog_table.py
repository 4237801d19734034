"""The catalog table: robots as rows of a CSV file, a few numbers each.

The arms read from URDF descriptions (``tools/build_catalog.py`` makes
``resources/robots/catalog.csv`` from the data folder; ``api.import_robot``
writes one-row files into the user robot folder) are kept as rows, not as
code.  A row holds what :class:`~.catalog.RobotSpec` needs:

============================  ===============================================
column                        content
============================  ===============================================
name, maker, model            catalog name, maker, model designation
controller, default_post      controller family; post-processor ("" = none)
payload_kg, reach_mm          rated payload ("" = unknown); reach
kind                          ``opw``, ``ur`` or ``chain``
lengths_mm                    OPW ``a1 a2 b c1 c2 c3 c4`` or UR ``d1 a2 a3 d4 d5 d6``
                              ("" for a chain)
offsets_deg, signs            6 numbers each (``q_model = q * sign - offset``; "" for
                              a chain)
chain_axes                    a chain's joint axes at zero joint values, unit
                              ``x y z`` of axis 1, then axis 2 ... 6 (18 numbers,
                              ``ChainAxes.axes``); "" for OPW and UR
chain_steps_mm                a chain's steps: base to a point of axis 1, axis i to
                              axis i + 1 (i = 1..5), axis 6 to the flange origin, each
                              ``x y z`` (21 numbers, ``ChainAxes.steps_mm``); the
                              joint values are the URDF's, unchanged
base_frame, flange_frame      ``x y z qw qx qy qz`` (mm; unit quaternion):
                              ``T_root_base`` and ``T_flange_tip`` (a chain's
                              flange rotation at zero joint values is its
                              ``flange_frame``)
joint_min_deg, joint_max_deg  6 numbers each, the controller's convention
joint_speed_deg_s             6 numbers
j23_factor                    ``k`` of the controller's ``J3 = q3 + k * q2``: 0, 1 or -1
                              (``RobotSpec.j23_coupled`` and ``j23_factor``)
uncertain                     field names, space separated
meshes                        link hulls file name beside the table ("" = none)
source, license, notes        where the numbers came from, its license, remarks
============================  ===============================================

Vectors are space-separated numbers written with ``repr`` precision, so a
row read back gives the same floats.  Pure Python + numpy: never imports
FreeCAD.
"""

import csv
import io
import math
import os
import re

import numpy as np

from ...core.rotations import matrix_from_quaternion, quaternion_from_matrix
from ...errors import InputError
from .catalog import ChainAxes, OPWParameters, RobotSpec, URParameters

COLUMNS = ("name", "maker", "model", "controller", "default_post", "payload_kg", "reach_mm",
           "kind", "lengths_mm", "offsets_deg", "signs", "chain_axes", "chain_steps_mm",
           "base_frame", "flange_frame",
           "joint_min_deg", "joint_max_deg", "joint_speed_deg_s", "j23_factor", "uncertain",
           "meshes", "source", "license", "notes")

#: Longest robot name (it is a file name in the user robot folder).
MAX_NAME = 64
#: Largest user robot file (one row, about 2 kB) read, bytes.
MAX_USER_TABLE_BYTES = 100 * 1000
#: Largest link hulls file (``NAME.npz``, about 15 kB) and array in it read, bytes.
MAX_MESHES_BYTES = 1000 * 1000
#: Most vertices of a stored hull (:data:`..urdf.link_meshes.MAX_VERTICES` is 160).
MAX_HULL_VERTICES = 10000

_OPW_LENGTHS = ("a1", "a2", "b", "c1", "c2", "c3", "c4")
_UR_LENGTHS = ("d1", "a2", "a3", "d4", "d5", "d6")


def _numbers(values):
    return " ".join(repr(float(v)) for v in values)


def _frame_text(T):
    if T is None:
        return ""
    T = np.asarray(T, dtype=float)
    return _numbers(list(T[:3, 3]) + list(quaternion_from_matrix(T[:3, :3])))


def _frame(text):
    if not text:
        return None
    values = [float(v) for v in text.split()]
    T = np.eye(4)
    T[:3, :3] = matrix_from_quaternion(np.array(values[3:7]))
    T[:3, 3] = values[:3]
    return tuple(tuple(float(v) for v in row) for row in T)


def row_from_spec(spec, meshes_name=""):
    """The table row of a catalog entry.

    Parameters
    ----------
    spec : RobotSpec
        With ``opw``, ``ur`` or ``chain`` parameters.
    meshes_name : str
        File name of its link hulls beside the table, "" for none.

    Returns
    -------
    dict of str to str
    """
    return {
        "name": spec.name, "maker": spec.manufacturer, "model": spec.model,
        "controller": spec.controller, "default_post": spec.default_post or "",
        "payload_kg": "" if spec.payload_kg is None else repr(float(spec.payload_kg)),
        "reach_mm": "" if spec.reach_mm is None else repr(float(spec.reach_mm)),
        **_kinematics_columns(spec),
        "base_frame": _frame_text(spec.T_root_base), "flange_frame": _frame_text(spec.T_flange_tip),
        "joint_min_deg": _numbers(spec.joint_min_deg), "joint_max_deg": _numbers(spec.joint_max_deg),
        "joint_speed_deg_s": _numbers(spec.joint_speed_deg_s),
        "j23_factor": str(spec.j23_factor if spec.j23_coupled else 0),
        "uncertain": " ".join(spec.uncertain),
        "meshes": meshes_name, "source": spec.source, "license": spec.license, "notes": spec.notes,
    }


def _kinematics_columns(spec):
    """The columns kind, lengths_mm, offsets_deg, signs, chain_axes, chain_steps_mm of a spec."""
    if spec.chain is not None:
        return {"kind": "chain", "lengths_mm": "", "offsets_deg": "", "signs": "",
                "chain_axes": _numbers(np.ravel(spec.chain.axes)),
                "chain_steps_mm": _numbers(np.ravel(spec.chain.steps_mm))}
    kind, params, names = (("opw", spec.opw, _OPW_LENGTHS) if spec.opw is not None
                           else ("ur", spec.ur, _UR_LENGTHS))
    return {"kind": kind, "lengths_mm": _numbers(getattr(params, n) for n in names),
            "offsets_deg": _numbers(params.offsets_deg),
            "signs": " ".join(str(int(s)) for s in params.signs), "chain_axes": "", "chain_steps_mm": ""}


def _shown(value, length=40):
    """A cell's value for a one-line message: quoted, escaped, at most `length` characters."""
    text = repr(value if isinstance(value, str) else str(value))
    return text if len(text) <= length else text[:length - 4] + "...'"


def spec_from_row(row, folder, where=""):
    """The catalog entry of a table row, its values checked.

    Parameters
    ----------
    row : dict of str to str
    folder : str
        The table's folder (meshes files are beside it).
    where : str
        The file, for messages.

    Returns
    -------
    RobotSpec

    Raises
    ------
    InputError
        A missing column, a value that is not a finite number, a joint whose
        minimum is not below its maximum, a speed, payload or reach not above
        0, a sign other than +-1, a frame whose quaternion is not a unit one,
        or a meshes name that is not a ``.npz`` file inside the table's folder; the message
        names the file, row and column.
    """
    label = "%s, robot %s" % (where or "catalog table", _shown(row.get("name", "?")))

    def refuse(column, why):
        raise InputError("%s: column '%s' %s, not %s; fix the file or import the robot again."
                         % (label, column, why, _shown(row.get(column))))

    def vector(column, count, kind=float, positive=False):
        try:
            values = tuple(kind(v) for v in row[column].split())
        except (KeyError, AttributeError, ValueError):
            values = ()
        if len(values) != count or not all(math.isfinite(v) for v in values):
            refuse(column, "must hold %d finite numbers" % count)
        if positive and min(values) <= 0:
            refuse(column, "must hold numbers above 0")
        return values

    def optional(column):
        return vector(column, 1, positive=True)[0] if row.get(column) else None

    def frame(column):
        values = vector(column, 7) if row.get(column) else None
        if values is not None and abs(math.sqrt(sum(v * v for v in values[3:])) - 1.0) > 1e-6:
            refuse(column, "must end with a unit quaternion (qw qx qy qz)")
        return _frame(row.get(column))

    name = row.get("name") or ""
    if not re.fullmatch(r"[A-Za-z0-9_]{1,%d}" % MAX_NAME, name):
        refuse("name", "must be 1 to %d letters, digits or _" % MAX_NAME)
    kind = row.get("kind")
    if kind not in ("opw", "ur", "chain"):
        refuse("kind", "must be 'opw', 'ur' or 'chain'")
    if kind == "chain":
        params = _chain_parameters(vector("chain_axes", 18), vector("chain_steps_mm", 21),
                                   lambda why: refuse("chain_axes", why))
    else:
        signs = vector("signs", 6, int)
        if any(s not in (-1, 1) for s in signs):
            refuse("signs", "must hold 6 signs, each 1 or -1")
        params = (OPWParameters if kind == "opw" else URParameters)(
            *vector("lengths_mm", 7 if kind == "opw" else 6), offsets_deg=vector("offsets_deg", 6),
            signs=signs)
    low, high = vector("joint_min_deg", 6), vector("joint_max_deg", 6)
    if any(a >= b for a, b in zip(low, high)):
        refuse("joint_max_deg", "must be above joint_min_deg '%s' on every joint" % row["joint_min_deg"])
    j23_factor, = vector("j23_factor", 1, int)
    if j23_factor not in (-1, 0, 1):
        refuse("j23_factor", "must be -1, 0 or 1")
    meshes = row.get("meshes") or ""
    parts = meshes.replace("\\", "/").split("/")
    if meshes and (not meshes.endswith(".npz") or os.path.isabs(meshes) or ".." in parts
                   or re.match(r"[A-Za-z]:", meshes)):
        refuse("meshes", "must be a .npz file in the table's folder")
    return RobotSpec(
        name=name, manufacturer=row.get("maker", ""), model=row.get("model", ""),
        controller=row.get("controller", ""), default_post=row.get("default_post", ""),
        payload_kg=optional("payload_kg"), joint_min_deg=low, joint_max_deg=high,
        joint_speed_deg_s=vector("joint_speed_deg_s", 6, positive=True),
        opw=params if kind == "opw" else None, ur=params if kind == "ur" else None,
        chain=params if kind == "chain" else None,
        j23_coupled=j23_factor != 0, j23_factor=j23_factor or 1, notes=row.get("notes", ""),
        uncertain=tuple((row.get("uncertain") or "").split()),
        T_root_base=frame("base_frame"), T_flange_tip=frame("flange_frame"),
        reach_mm=optional("reach_mm"),
        meshes=os.path.join(folder, meshes) if meshes else "",
        source=row.get("source", ""), license=row.get("license", ""))


def _chain_parameters(axes, steps, refuse):
    """A chain's :class:`ChainAxes` from its 18 + 21 numbers, as written (so a row read back
    gives the same floats); `refuse(why)` when an axis is not a unit vector (to 1e-9)."""
    if np.abs(np.linalg.norm(np.reshape(axes, (6, 3)), axis=1) - 1.0).max() > 1e-9:
        refuse("must hold 6 unit vectors (x y z of each axis)")
    return ChainAxes(axes=tuple(axes[i:i + 3] for i in range(0, 18, 3)),
                     steps_mm=tuple(steps[i:i + 3] for i in range(0, 21, 3)))


def read_table(path, max_bytes=None):
    """Every entry of a table file.

    Parameters
    ----------
    path : str
    max_bytes : int, optional
        Refuse a larger file (a user robot file holds one row: :data:`MAX_USER_TABLE_BYTES`).

    Returns
    -------
    list of RobotSpec

    Raises
    ------
    InputError
        A row that :func:`spec_from_row` refuses, or a file past `max_bytes`.
    OSError, UnicodeDecodeError, csv.Error
        The file cannot be read as CSV.
    """
    if max_bytes is not None and os.path.getsize(path) > max_bytes:
        raise InputError("'%s' is larger than %d kB: a robot file holds one row; import the robot "
                         "again." % (path, max_bytes // 1000))
    with open(path, newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    folder = os.path.dirname(os.path.abspath(path))
    return [spec_from_row(row, folder, path) for row in rows]


def meshes_problem(path):
    """Why a link hulls file (``.npz``, :mod:`..urdf.link_meshes`) cannot be used, or "".

    The file must be at most :data:`MAX_MESHES_BYTES`, load without pickles and
    hold only ``vertices_0`` ... ``vertices_6``, each (V, 3) finite numbers with
    4 <= V <= :data:`MAX_HULL_VERTICES`.

    Parameters
    ----------
    path : str

    Returns
    -------
    str
        E.g. ``"cannot be read (BadZipFile: File is not a zip file)"``; "" for a good file.
    """
    try:
        if os.path.getsize(path) > MAX_MESHES_BYTES:
            return "is larger than %d kB" % (MAX_MESHES_BYTES // 1000)
        with np.load(path, allow_pickle=False) as data:
            for key in data.files:
                if not re.fullmatch(r"vertices_[0-6]", key):
                    return "holds '%s', not only vertices_0 ... vertices_6" % key
                if data.zip.getinfo(key + ".npy").file_size > MAX_MESHES_BYTES:
                    return "holds a %s larger than %d kB" % (key, MAX_MESHES_BYTES // 1000)
                vertices = data[key]
                if (vertices.ndim != 2 or vertices.shape[1] != 3 or vertices.dtype.kind != "f"
                        or not 4 <= len(vertices) <= MAX_HULL_VERTICES
                        or not np.isfinite(vertices).all()):
                    return "holds a %s that is not 4 to %d finite points" % (key, MAX_HULL_VERTICES)
    except Exception as exc:   # noqa: BLE001 -- any reason it cannot be read is said, not raised
        return "cannot be read (%s: %s)" % (type(exc).__name__, " ".join(str(exc).split()))
    return ""


def table_text(rows):
    """CSV text of table rows (dicts from :func:`row_from_spec`), header first."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow(row)
    return buffer.getvalue()


def write_table(path, rows):
    """Write table rows to `path` atomically (temp file + rename)."""
    temporary = path + ".tmp"
    try:
        with open(temporary, "w", encoding="utf-8", newline="") as stream:
            stream.write(table_text(rows))
        os.replace(temporary, path)
    except OSError:
        if os.path.exists(temporary):
            os.remove(temporary)
        raise
