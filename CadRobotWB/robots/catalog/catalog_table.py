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
kind                          ``opw`` or ``ur``
lengths_mm                    OPW ``a1 a2 b c1 c2 c3 c4`` or UR ``d1 a2 a3 d4 d5 d6``
offsets_deg, signs            6 numbers each (``q_model = q * sign - offset``)
base_frame, flange_frame      ``x y z qw qx qy qz`` (mm; unit quaternion):
                              ``T_root_base`` and ``T_flange_tip``
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
import os

import numpy as np

from ...core.rotations import matrix_from_quaternion, quaternion_from_matrix
from ...errors import InputError
from .catalog import OPWParameters, RobotSpec, URParameters

COLUMNS = ("name", "maker", "model", "controller", "default_post", "payload_kg", "reach_mm",
           "kind", "lengths_mm", "offsets_deg", "signs", "base_frame", "flange_frame",
           "joint_min_deg", "joint_max_deg", "joint_speed_deg_s", "j23_factor", "uncertain",
           "meshes", "source", "license", "notes")

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
        With ``opw`` or ``ur`` parameters.
    meshes_name : str
        File name of its link hulls beside the table, "" for none.

    Returns
    -------
    dict of str to str
    """
    kind, params, names = (("opw", spec.opw, _OPW_LENGTHS) if spec.opw is not None
                           else ("ur", spec.ur, _UR_LENGTHS))
    return {
        "name": spec.name, "maker": spec.manufacturer, "model": spec.model,
        "controller": spec.controller, "default_post": spec.default_post or "",
        "payload_kg": "" if spec.payload_kg is None else repr(float(spec.payload_kg)),
        "reach_mm": "" if spec.reach_mm is None else repr(float(spec.reach_mm)),
        "kind": kind, "lengths_mm": _numbers(getattr(params, n) for n in names),
        "offsets_deg": _numbers(params.offsets_deg), "signs": " ".join(str(int(s)) for s in params.signs),
        "base_frame": _frame_text(spec.T_root_base), "flange_frame": _frame_text(spec.T_flange_tip),
        "joint_min_deg": _numbers(spec.joint_min_deg), "joint_max_deg": _numbers(spec.joint_max_deg),
        "joint_speed_deg_s": _numbers(spec.joint_speed_deg_s),
        "j23_factor": str(spec.j23_factor if spec.j23_coupled else 0),
        "uncertain": " ".join(spec.uncertain),
        "meshes": meshes_name, "source": spec.source, "license": spec.license, "notes": spec.notes,
    }


def spec_from_row(row, folder, where=""):
    """The catalog entry of a table row.

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
        A missing column or a value that is not a number, naming the file, row and column.
    """
    label = "%s, robot '%s'" % (where or "catalog table", row.get("name", "?"))

    def vector(column, count, kind=float):
        try:
            values = tuple(kind(v) for v in row[column].split())
        except (KeyError, AttributeError, ValueError):
            values = ()
        if len(values) != count:
            raise InputError("%s: column '%s' must hold %d numbers, not '%s'; fix the file or "
                             "import the robot again." % (label, column, count, row.get(column)))
        return values

    kind = row.get("kind")
    if kind == "opw":
        params = OPWParameters(*vector("lengths_mm", 7), offsets_deg=vector("offsets_deg", 6),
                               signs=vector("signs", 6, int))
    elif kind == "ur":
        params = URParameters(*vector("lengths_mm", 6), offsets_deg=vector("offsets_deg", 6),
                              signs=vector("signs", 6, int))
    else:
        raise InputError("%s: kind must be 'opw' or 'ur', not '%s'." % (label, kind))
    meshes = row.get("meshes") or ""
    j23_factor, = vector("j23_factor", 1, int)
    return RobotSpec(
        name=row["name"], manufacturer=row.get("maker", ""), model=row.get("model", ""),
        controller=row.get("controller", ""), default_post=row.get("default_post", ""),
        payload_kg=float(row["payload_kg"]) if row.get("payload_kg") else None,
        joint_min_deg=vector("joint_min_deg", 6), joint_max_deg=vector("joint_max_deg", 6),
        joint_speed_deg_s=vector("joint_speed_deg_s", 6),
        opw=params if kind == "opw" else None, ur=params if kind == "ur" else None,
        j23_coupled=j23_factor != 0, j23_factor=j23_factor or 1, notes=row.get("notes", ""),
        uncertain=tuple((row.get("uncertain") or "").split()),
        T_root_base=_frame(row.get("base_frame")), T_flange_tip=_frame(row.get("flange_frame")),
        reach_mm=float(row["reach_mm"]) if row.get("reach_mm") else None,
        meshes=os.path.join(folder, meshes) if meshes else "",
        source=row.get("source", ""), license=row.get("license", ""))


def read_table(path):
    """Every entry of a table file.

    Parameters
    ----------
    path : str

    Returns
    -------
    list of RobotSpec
    """
    with open(path, newline="", encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    folder = os.path.dirname(os.path.abspath(path))
    return [spec_from_row(row, folder, path) for row in rows]


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
    with open(temporary, "w", encoding="utf-8", newline="") as stream:
        stream.write(table_text(rows))
    os.replace(temporary, path)
