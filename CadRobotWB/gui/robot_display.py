"""The robot of a cell, standing in the 3D view at its base in its start pose.

The cell's view provider draws it (view property ``ShowRobot``): the link
solids and the tool of :class:`~.robot_view.RobotView` with the base {R}
where the programs put it (``api.robot_base``): the cell's Placement, or -
when a taught calibration frame fixes the part relative to the robot -
where the teaching puts the robot relative to the drawn part; then a
dashed triad titled "drawn base" marks the cell's Placement.  It is posed at the cell's StartJoints (six model joints, as
the joint solver reads them) or else at
:func:`~CadRobotWB.robots.motion.configuration.reference_joints`, where the solver
starts when StartJoints is empty.  While the simulation player animates the
cell, :func:`hold` hides it, so the robot is not drawn twice.  The New cell
panel previews a robot with :func:`robot_at` before the cell exists.

Scene graph (under the cell view provider's root, so the robot goes with
the cell's document and views; nothing is added to the document)::

    SoSwitch "CadRobotCellRobot"   on: Visibility, ShowRobot and not held
    +-- SoSeparator
        +-- SoPickStyle UNPICKABLE
        +-- CadRobotRobotView      robot_view.RobotView (its traces stay empty)
        +-- SoSwitch "CadRobotDrawnBase"  on while a taught frame moves the robot
            +-- SoSeparator: SoTransform (the cell's Placement), dashed triad
"""

import numpy as np

from pivy import coin

from .. import api
from ..errors import CadRobotError
from ..objects.convert import matrix_from_placement
from ..robots.motion import configuration
from . import triad_display
from .robot_view import RobotView


def start_joints(cell, model):
    """The joints the cell's robot is drawn in.

    Parameters
    ----------
    cell : App.DocumentObject
        A CadRobot cell.
    model : RobotModel
        Its robot's model.

    Returns
    -------
    ndarray, shape (6,)
        Model joints, degrees: StartJoints when it holds 6 values, else the
        start the joint solver takes without them.
    """
    values = list(cell.StartJoints or [])
    return np.array(values, dtype=float) if len(values) == 6 else configuration.reference_joints(model)


def robot_at(robot, T_u_r, T_f_t=None, q_deg=None, view=None, parent=None):
    """A :class:`RobotView` of catalog robot `robot`, or None for a name not in the catalog.

    Parameters
    ----------
    robot : str
        Catalog name.
    T_u_r : array_like, shape (4, 4)
        Robot base {R} in {U}, mm.
    T_f_t : array_like, shape (4, 4), optional
        TCP in the flange frame (the tool); None: no tool.
    q_deg : array_like, shape (6,), optional
        Model joints, degrees; None: :func:`~CadRobotWB.robots.motion.configuration.reference_joints`.
    view, parent
        Where to draw, as for :class:`RobotView`.
    """
    try:
        model = api.robot(robot)
    except CadRobotError:
        return None
    drawn = RobotView(view, model, T_u_r, T_f_t, parent=parent)
    drawn.set_joints(configuration.reference_joints(model) if q_deg is None else q_deg)
    return drawn


def effective_base(cell):
    """(T_u_r (4, 4), moved): where the cell's robot is drawn, and whether a taught frame
    moves it from the cell's Placement (``api.robot_base``; the Placement while the cell
    cannot be read)."""
    drawn = matrix_from_placement(cell.Placement)
    try:
        T_u_r = matrix_from_placement(api.robot_base(cell))
    except CadRobotError:
        return drawn, False
    moved = (np.linalg.norm(T_u_r[:3, 3] - drawn[:3, 3]) > 1e-6
             or np.abs(T_u_r[:3, :3] - drawn[:3, :3]).max() > 1e-9)
    return T_u_r, bool(moved)


class CellRobotDisplay:
    """The robot of one cell, under the cell view provider's root.

    Parameters
    ----------
    root : coin.SoGroup
        The view provider's root node; the display adds its switch to it.

    Attributes
    ----------
    switch : coin.SoSwitch
        On while the cell is visible, ShowRobot is on and no player holds it.
    robot : RobotView or None
        None while the cell's Robot is not in the catalog.
    """

    def __init__(self, root):
        self.switch, self._group = triad_display.overlay(root, "CadRobotCellRobot")
        self.robot = None
        self._drawn = None              # (robot name, T_f_t bytes) the solids were made for
        self._visible = self._show_robot = True
        self._held = False
        self.base_switch = triad_display.switch_node(False)
        self.base_switch.setName("CadRobotDrawnBase")
        self._base_sep = coin.SoSeparator()
        self._base_transform = triad_display.transform_node(np.eye(4))
        self._base_sep.addChild(self._base_transform)
        self._base_sep.addChild(triad_display.triad_node(
            300.0, "drawn base (taught frame in use)", pattern=0xF0F0, line_width=2.0))
        self.base_switch.addChild(self._base_sep)
        self._group.addChild(self.base_switch)
        #: ndarray (4, 4): where the robot is drawn (the effective base).
        self.T_u_r = np.eye(4)

    def update(self, cell):
        """Redraw from the cell's Robot, ToolTCP, Placement and StartJoints."""
        T_f_t = matrix_from_placement(cell.ToolTCP)
        drawn = (str(cell.Robot), T_f_t.tobytes())
        if drawn != self._drawn:        # new solids only for another robot or tool
            if self.robot is not None:
                self.robot.remove()
            self.robot = robot_at(cell.Robot, np.eye(4), T_f_t, parent=self._group)
            self._drawn = drawn
        T_u_r_drawn = matrix_from_placement(cell.Placement)
        self.T_u_r, moved = effective_base(cell)
        triad_display.set_transform(self._base_transform, T_u_r_drawn)
        triad_display.set_visible(self.base_switch, moved)
        if self.robot is not None:
            self.robot.set_base(self.T_u_r)
            self.robot.set_joints(start_joints(cell, self.robot.model))

    def set_visible(self, visible):
        """Follow the cell's Visibility."""
        self._visible = bool(visible)
        self._switch()

    def show_robot(self, shown):
        """Follow the cell's view property ShowRobot."""
        self._show_robot = bool(shown)
        self._switch()

    def hold(self, held):
        """Hide the robot while another one (the player's) stands in for it."""
        self._held = bool(held)
        self._switch()

    @property
    def shown(self):
        """bool: a robot is drawn and switched on."""
        return self.robot is not None and self.switch.whichChild.getValue() == 0

    def _switch(self):
        triad_display.set_visible(self.switch, self._visible and self._show_robot and not self._held)


def display_of(cell):
    """The :class:`CellRobotDisplay` of `cell`, or None (no view, deleted cell)."""
    try:
        proxy = getattr(getattr(cell, "ViewObject", None), "Proxy", None)
    except ReferenceError:          # the cell was deleted meanwhile
        return None
    return getattr(proxy, "robot_display", None)


def hold(cell, held):
    """Hide (`held` True) or show again the static robot of `cell`, if it has one."""
    display = display_of(cell)
    if display is not None:
        display.hold(held)
