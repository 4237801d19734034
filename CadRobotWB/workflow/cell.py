"""The robot cell: make it, give it its tool, stand its robot, and where the robot stands
relative to the part (taught frames).

Part of the scripting API: :mod:`CadRobotWB.api` re-exports its public names.
"""

import numpy as np

from .. import posts, preferences
from ..errors import InputError
from ..objects import base, cell as cell_module, reader, tool_body, tool_marker, validate
from ..objects.convert import placement_from_matrix, vector_from_array
from ..robots.catalog import catalog, tools
from ..robots.motion import playback
from .base_site import default_placement
from .arguments import ROBOT_NAME, TOOL_NAME, Arguments
from .common import ROBOT_BASE, as_placement


def make_cell(doc, robot="ABB_IRB2400", name="Cell", placement=None, tool=None):
    """Add a robot cell. Its ``Placement`` is the robot base {R} in {U}; its
    ``PostProcessor`` is the robot controller's language.

    Parameters
    ----------
    placement : FreeCAD.Placement or array_like (4, 4), optional
        The robot base {R} in {U}, mm.  Default: beside the work, facing it
        (:func:`default_placement`: the document's paths, else its solids,
        and the robot's reach); the origin in a document without solids.
    tool : str, optional
        A tool of the library (:func:`tool_names`); default "Straight torch".
        Its TCP, mass and centre of gravity become the cell's (change them,
        or give a document solid as the tool, with :func:`set_tool`).

    Raises UnknownNameError for a robot not in the catalog (see :func:`robots`)
    or a tool not in the library.
    """
    args = Arguments("make_cell")
    args.open_document("doc", doc)
    args.text("robot", robot, expected=ROBOT_NAME)
    args.text("name", name)
    if placement is not None:
        args.placement("placement", placement, ROBOT_BASE)
    args.text("tool", tool, optional=True, expected=TOOL_NAME)
    preferences.use_user_robot_folder()
    spec = catalog.get(robot)
    library_tool = tools.get(tools.DEFAULT if tool is None else tool)
    pl = None if placement is None else as_placement(placement, "Cell '%s'" % name,
                                                   placement=ROBOT_BASE)
    if pl is None:
        pl = default_placement(doc, spec.name)
    obj = cell_module.make(doc, robot, name)
    obj.Placement = pl
    _apply_tool(obj, library_tool.name, None, placement_from_matrix(library_tool.T_f_t),
                library_tool.mass_kg, library_tool.cog_mm)
    if spec.default_post in posts.names():   # the robot's own controller language, once we have it
        obj.PostProcessor = spec.default_post
    doc.recompute()
    return obj


def tool_names():
    """The tool library's names (e.g. "Straight torch"), for :func:`make_cell` and :func:`set_tool`."""
    return tools.names()


def _apply_tool(cell, tool_type, body, tcp, mass_kg, cog_mm):
    """Set the tool properties of `cell` (values already checked)."""
    cell.ToolType = tool_type
    cell.ToolBody = body
    cell.ToolTCP = tcp
    cell.ToolMass = float(mass_kg)
    cell.ToolCenterOfGravity = vector_from_array(np.asarray(cog_mm, dtype=float))


def _body_centre_mm(body):
    """Centre of mass (uniform density) of `body`'s solids in its own coordinates, mm (3,)."""
    solids = tool_body.own_shape(body).Solids
    volume = sum(s.Volume for s in solids)
    return sum((np.array(tuple(s.CenterOfMass)) * s.Volume for s in solids), np.zeros(3)) / volume


def set_tool(cell, tool=None, body=None, tcp=None, mass_kg=None, cog_mm=None):
    """Give `cell` its tool: one of the library, or a solid of the document.

    With `tool`, the library tool's body, TCP, mass and centre of gravity
    (`tcp`, `mass_kg`, `cog_mm` override its numbers, e.g. a longer wire
    stick-out; the body drawn stays the library's).

    With `body`, the solid is the tool (``ToolType`` "Custom body"), read in
    its own coordinates: the robot's flange {F} is the solid's own origin
    (its shape with its placement taken off; draw the tool with the flange
    face at the origin, its axis along +Z), and `tcp` is the TCP in those
    coordinates: its origin at the tool's tip, its +Z the approach direction
    (out of the tool, into the work).  `mass_kg` defaults to the cell's
    present ToolMass, `cog_mm` to the solid's centre of volume.  The solid
    is no longer an obstacle of the collision check.

    With neither, only the numbers given change.

    Tool markers drawing the cell's tool follow (recompute).

    Parameters
    ----------
    cell : Cell
    tool : str, optional
        A name of :func:`tool_names`.
    body : App.DocumentObject, optional
        A document object with a solid Shape.
    tcp : FreeCAD.Placement or array_like (4, 4), optional
        TCP {T} in the flange frame {F}, mm (needed with `body`).
    mass_kg : float, optional
        Tool mass, kg (> 0).
    cog_mm : sequence of 3 float, optional
        Centre of gravity in {F}, mm.

    Returns
    -------
    Cell

    Raises
    ------
    InputError
        Both `tool` and `body`; an unknown tool name; a body without a
        solid; `body` without `tcp`; a TCP that is not a rigid placement; a
        mass that is not a positive finite number; a centre of gravity that
        is not three finite numbers.  The cell is then unchanged.
    """
    args = Arguments("set_tool")
    args.cell(cell)
    args.text("tool", tool, optional=True, expected=TOOL_NAME)
    args.shape_object("body", body, optional=True)
    if tcp is not None:
        args.placement("tcp", tcp, "tool's TCP")
    args.number("mass_kg", mass_kg, optional=True, expected="a mass in kg (a number)")
    args.numbers("cog_mm", cog_mm, 3, optional=True, expected="3 numbers (x, y, z, mm)")
    what = "Cell %s" % base.describe(cell)
    if tool is not None and body is not None:
        raise InputError("%s: give either a library tool (tool=) or a document solid (body=), not "
                         "both." % what, cell.Name)
    if tool is not None:
        library_tool = tools.get(tool)
        tool_type, tool_solid = library_tool.name, None
        defaults = (placement_from_matrix(library_tool.T_f_t), library_tool.mass_kg,
                    library_tool.cog_mm)
    elif body is not None:
        tool_body.check_body(cell, body)
        if tcp is None:
            raise InputError("%s: give the TCP of the tool body %s (tcp=, its placement in the "
                             "body's own coordinates: origin at the tip, +Z into the work)."
                             % (what, base.describe(body)), cell.Name)
        tool_type, tool_solid = tools.CUSTOM, body
        defaults = (None, float(cell.ToolMass), _body_centre_mm(body))
    else:
        tool_type, tool_solid = cell.ToolType, cell.ToolBody
        defaults = (cell.ToolTCP, float(cell.ToolMass),
                    np.array(tuple(cell.ToolCenterOfGravity), dtype=float))
    new_tcp = defaults[0] if tcp is None else as_placement(tcp, what, obj_name=cell.Name,
                                                         placement="tool's TCP (tcp)")
    mass = defaults[1] if mass_kg is None else mass_kg
    mass = validate.number_in_range(mass, "%s: the tool mass (mass_kg, kg)" % what, 0.0,
                                    low_open=True)
    cog = defaults[2] if cog_mm is None else cog_mm
    try:
        cog = np.asarray(cog, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise InputError("%s: the tool's centre of gravity (cog_mm) must be 3 numbers (x, y, z "
                         "in mm in the flange frame), not %r." % (what, cog_mm), cell.Name) from None
    validate.finite_values(cog, "%s: the tool's centre of gravity (cog_mm)" % what,
                           obj_name=cell.Name)
    _apply_tool(cell, tool_type, tool_solid, new_tcp, mass, cog)
    for marker in tool_marker.cell_markers(cell):
        marker.touch()
    cell.Document.recompute()
    return cell


def set_robot_placement(cell, placement):
    """Stand `cell`'s robot at `placement` (e.g. ``place_robot(cell, ...)[0].placement``).

    Parameters
    ----------
    placement : FreeCAD.Placement or array_like (4, 4)
        The robot base {R} in {U}, mm.

    Returns
    -------
    FreeCAD.Placement
        The cell's new Placement.
    """
    args = Arguments("set_robot_placement")
    args.cell(cell)
    args.placement("placement", placement, ROBOT_BASE)
    cell.Placement = as_placement(placement, "Cell %s" % base.describe(cell), obj_name=cell.Name,
                                placement=ROBOT_BASE)
    cell.Document.recompute()
    return cell.Placement


def find_cells(doc):
    """The robot cells of `doc`, in document order."""
    Arguments("find_cells").open_document("doc", doc)
    return base.objects_of_type(doc, "Cell")


def _cell_frames(cell):
    """The calibration frames `cell`'s paths use, in path order (the cell's own frame
    when it has no paths), read as reader.read_cell reads them (FrameSpec)."""
    own = getattr(cell, "CalibrationFrame", None)
    frames = [getattr(p, "CalibrationFrame", None) or own for p in reader.cell_paths(cell)] or [own]
    out, seen = [], set()
    for frame in frames:
        if frame is not None and frame.Name not in seen:
            seen.add(frame.Name)
            out.append(reader.frame_spec(frame))
    return out


def _robot_base(cell):
    """playback.RobotBase of `cell`: its Placement and its frames, no paths read."""
    return playback.effective_base(reader.object_pose(cell),
                                   [(f.label, f.T_u_b, f.T_r_b) for f in _cell_frames(cell)])


def robot_base(cell):
    """Where `cell`'s robot stands relative to its part, as every command sees it.

    Without a taught calibration frame: the cell's Placement.  With one
    (UseTaught): ``T_u_b @ inv(T_r_b)`` of the frame as drawn and as taught
    (the part is where the robot measured it, so the robot stands there
    relative to the drawn part, wherever the cell's Placement puts it).
    Several taught frames: the first in path order decides
    (``robots.motion.playback.effective_base``).  Check, Simulate, Sensor run, the
    sweep, the simulation player and the 3D view all use this.

    Returns
    -------
    FreeCAD.Placement
        The robot base {R} in {U}.
    """
    Arguments("robot_base").cell(cell)
    return placement_from_matrix(_robot_base(cell).T_u_r)


def taught_frame_labels(cell):
    """Labels of `cell`'s calibration frames in use that are taught (UseTaught), in path order."""
    Arguments("taught_frame_labels").cell(cell)
    return [f.label for f in _cell_frames(cell) if f.T_r_b is not None]


def taught_frame_note(cell, frame_label):
    """What a taught frame means for moving `cell`'s robot, and how to plan with the drawn frame."""
    args = Arguments("taught_frame_note")
    args.cell(cell)
    args.text("frame_label", frame_label)
    return cell_module.taught_frame_note(cell.Label, frame_label)
