"""The simulation player: a task panel that animates the robot in the 3D view.

``open_player(cell)`` checks the cell (``api.check``), turns its program
into joint values in time (:func:`~CadRobotWB.robots.motion.playback.joint_timeline`)
and plays them on a :class:`~.robot_view.RobotView`: play / pause, one
sample back or forward, speed 0.1x to 10x, a time slider; labels show the
time, the move and its target, and J1..J6 in degrees (the controller's
joints).  The robot draws its TCP trace as it goes and stops at the first
failing target, whose reason is shown in red.

``open_player(cell, trajectories)`` plays TCP paths handed in by a sensor
simulation instead, e.g. ``[("nominal", T_u_t, t), ("corrected", T_u_t, t)]``:
each is drawn as a polyline in its own colour, and the robot follows the
last one (:func:`~CadRobotWB.robots.motion.playback.timeline_from_tcp`); a run
of a cell with external axes (``axes``) is in the part's frame, and plays with
the positioner and the track moving as in the run.

With external axes (``program.external``), the timeline's values
(``Timeline.external``) turn the positioner with its parts and move the robot
along its track in step with the arm (:class:`~.mechanism_view.MechanismView`:
coin transforms only, restored when the player closes), and the TCP trace is
drawn on the part.

Only the view changes: nothing is written into the document.
"""

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtCore, QtGui

from .. import api
from ..core.progress import report_now, stage
from ..objects.convert import matrix_from_placement
from ..robots.motion import playback
from . import robot_display
from .mechanism_view import MechanismView
from .robot_view import RobotView
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate

#: Timer interval while playing, ms.
TICK_MS = 40
#: Sampling time of the played timeline, s.
DT_S = 0.1
#: Slowest and fastest playback speed (times real time).
SPEED_RANGE = (0.1, 10.0)

#: The open player; closing it takes its robot out of the view.
_slot = PanelSlot(before_close=lambda player: player.clean_up())


def _rgb_css(color):
    return "rgb(%d, %d, %d)" % tuple(int(round(255 * c)) for c in color)


def _base_of(cell, result=None):
    """The robot base in {U} every command uses (api.robot_base: a taught frame moves it)."""
    if result is not None and getattr(result, "base", None) is not None:
        return result.base.T_u_r
    return matrix_from_placement(api.robot_base(cell))


# --- what to play --------------------------------------------------------------------------

def _program_source(cell, result, model, dt_s):
    """Timeline and per-sample description of the cell's program, and the woven
    path of each weld run with a weave to draw."""
    program = result.program
    timeline = playback.joint_timeline(program, model, result.solution, dt_s, report=result.report,
                                       T_u_r=_base_of(cell, result))
    moves = program.moves()

    def describe(i):
        k = int(timeline.move_index[i])
        move = moves[k]
        return translate("CadRobot", "Move {0} of {1} ({2}, {3}) to {4}").format(
            k + 1, len(moves), move.kind, move.role, move.target.name)

    return timeline, describe, playback.woven_polylines(program)


def _nearest_target_joints(program, position_u):
    """Joints of the program target nearest a point in {U}, or None."""
    best, best_d = None, np.inf
    for move in program.moves():
        target = move.target
        if target.joints_deg is None:
            continue
        T_u_t = program.frames[move.frame].T_u_b @ target.T_b_t
        d = np.linalg.norm(T_u_t[:3, 3] - position_u)
        if d < best_d:
            best, best_d = np.asarray(target.joints_deg, dtype=float), d
    return best


def _part_timeline(T_p_t, times, model, axes, T_f_t, q_start):
    """The Timeline of a sensor run's TCP path given in the part's frame (``axes``:
    its ``sensors.scene.AxesAlongPath``): the path and the robot base placed in {U}
    where the external axes put them at each time, and their values to show."""
    times = np.asarray(times, dtype=float)
    values = axes.values_at(times)
    T_u_r = axes.external.T_u_r_at(values)
    timeline = playback.timeline_from_tcp(axes.T_u_part(times) @ T_p_t, times, model, T_u_r,
                                          T_f_t, q_start)
    shown = len(timeline.time_s)
    timeline.external = values[:shown]
    timeline.base_u = T_u_r[:shown] if axes.external.track is not None else None
    return timeline


def _trajectory_source(cell, program, model, trajectories, axes=None):
    """Timeline of the last trajectory, and polylines of all (`axes`: the run's external
    axes, the paths then being in the part's frame)."""
    polylines = []
    for label, T_u_t, _times in trajectories:
        polylines.append((str(label), np.asarray(T_u_t, dtype=float)[:, :3, 3]))
    label, T_u_t, times = trajectories[-1]
    T_u_t = np.asarray(T_u_t, dtype=float)
    q_start = _nearest_target_joints(program, T_u_t[0, :3, 3])
    if axes is not None:
        timeline = _part_timeline(T_u_t, times, model, axes, program.tool.T_f_t, q_start)
    else:
        timeline = playback.timeline_from_tcp(T_u_t, times, model, _base_of(cell),
                                              program.tool.T_f_t, q_start)

    def describe(i):
        return translate("CadRobot", "Path '{0}', sample {1} of {2}").format(label, i + 1,
                                                                          len(times))

    return timeline, describe, polylines


# --- the panel -----------------------------------------------------------------------------

class PlayerPanel(TaskPanel):
    """Task panel playing a :class:`~CadRobotWB.robots.motion.playback.Timeline` on a robot.

    Parameters
    ----------
    title : str
    robot : RobotView
    timeline : Timeline
    describe : callable
        ``describe(sample_index) -> str``: the move and target, or the path.
    legend : list of (str, tuple of 3 float)
        Label and colour of each extra polyline drawn.
    cell : App.DocumentObject, optional
        The cell played: its own robot (:mod:`.robot_display`) is hidden
        while the panel is open, so the robot is not drawn twice.
    mechanisms : MechanismView, optional
        The external axes, shown at ``timeline.external`` (restored on close).
    program : Program, optional
        The program played (None for TCP paths).

    Attributes
    ----------
    form : QtGui.QWidget
        What FreeCAD shows in the task view.
    frame : int
        The sample shown.
    joint_labels : list of 6 QtGui.QLabel
        J1..J6 in degrees (the controller's joints).
    external_labels : list of QtGui.QLabel
        E1, E2, ... (the track in mm, the positioner's axes in degrees), one per
        external axis; empty without `mechanisms`.
    status_label : QtGui.QLabel
        Red with the reason once playback reaches the first failing target.
    """

    def __init__(self, title, robot, timeline, describe, legend=(), cell=None, mechanisms=None,
                 program=None):
        self.robot = robot
        self.program = program
        self.cell = cell
        self.mechanisms = mechanisms
        self.timeline = timeline
        self.describe = describe
        self.frame = 0
        self.clock_s = float(timeline.time_s[0])
        self.timer = QtCore.QTimer()
        self.timer.setInterval(TICK_MS)
        self.timer.timeout.connect(self._tick)
        self.form = self._build_form(title, legend)
        self.show_frame(0)
        robot_display.hold(cell, True)

    # -- widgets --
    def _build_form(self, title, legend):
        form = QtGui.QWidget()
        form.setWindowTitle(translate("CadRobot", "Simulation"))
        layout = QtGui.QVBoxLayout(form)
        heading = QtGui.QLabel("<b>%s</b>" % title)
        layout.addWidget(heading)

        style = QtGui.QApplication.style()
        buttons = QtGui.QHBoxLayout()
        self.back_button = self._button(style, QtGui.QStyle.SP_MediaSkipBackward,
                                        translate("CadRobot", "Step back"), lambda: self.step(-1))
        self.play_button = self._button(style, QtGui.QStyle.SP_MediaPlay,
                                        translate("CadRobot", "Play / pause"), self.toggle)
        self.forward_button = self._button(style, QtGui.QStyle.SP_MediaSkipForward,
                                           translate("CadRobot", "Step forward"),
                                           lambda: self.step(1))
        for button in (self.back_button, self.play_button, self.forward_button):
            buttons.addWidget(button)
        buttons.addStretch(1)
        buttons.addWidget(QtGui.QLabel(translate("CadRobot", "Speed")))
        self.speed_box = QtGui.QDoubleSpinBox()
        self.speed_box.setRange(*SPEED_RANGE)
        self.speed_box.setDecimals(1)
        self.speed_box.setSingleStep(0.5)
        self.speed_box.setSuffix(" x")
        self.speed_box.setValue(1.0)
        self.speed_box.setToolTip(translate("CadRobot", "Playback speed, times real time"))
        buttons.addWidget(self.speed_box)
        layout.addLayout(buttons)

        self.slider = QtGui.QSlider(QtCore.Qt.Horizontal)
        self.slider.setRange(0, len(self.timeline) - 1)
        self.slider.setToolTip(translate("CadRobot", "Time"))
        self.slider.valueChanged.connect(self._slider_moved)
        layout.addWidget(self.slider)

        self.time_label = QtGui.QLabel()
        self.move_label = QtGui.QLabel()
        self.move_label.setWordWrap(True)
        layout.addWidget(self.time_label)
        layout.addWidget(self.move_label)

        grid = QtGui.QGridLayout()
        self.joint_labels = []
        for j in range(6):
            name = QtGui.QLabel("J%d" % (j + 1))
            value = QtGui.QLabel()
            value.setAlignment(QtCore.Qt.AlignRight | QtCore.Qt.AlignVCenter)
            grid.addWidget(name, j % 3, 2 * (j // 3))
            grid.addWidget(value, j % 3, 2 * (j // 3) + 1)
            self.joint_labels.append(value)
        layout.addLayout(grid)
        layout.addLayout(self._external_grid())

        for label, color in legend:
            swatch = QtGui.QLabel("\u25a0 %s" % label)
            swatch.setStyleSheet("color: %s;" % _rgb_css(color))
            layout.addWidget(swatch)

        self.status_label = QtGui.QLabel()
        self.status_label.setWordWrap(True)
        layout.addWidget(self.status_label)
        layout.addStretch(1)
        return form

    def _external_grid(self):
        """A row per external axis: "E1 Positioner tilt" and its value (``external_labels``)."""
        grid = QtGui.QGridLayout()
        self.external_labels, self._external_units = [], []
        if self.mechanisms is None:
            return grid
        external = self.mechanisms.external
        for k, (name, (mechanism, axis)) in enumerate(zip(external.axis_names(), external.axes())):
            value = QtGui.QLabel()
            value.setAlignment(QtCore.Qt.AlignRight | QtCore.Qt.AlignVCenter)
            grid.addWidget(QtGui.QLabel("%s %s %s" % (name, mechanism.label, axis.name)), k, 0)
            grid.addWidget(value, k, 1)
            self.external_labels.append(value)
            self._external_units.append(" mm" if axis.unit == "mm" else "\u00b0")
        return grid

    def _button(self, style, icon, tip, slot):
        button = QtGui.QToolButton()
        button.setIcon(style.standardIcon(icon))
        button.setToolTip(tip)
        button.clicked.connect(slot)
        return button

    # -- playback --
    @property
    def playing(self):
        """bool: the timer is running."""
        return self.timer.isActive()

    @property
    def last_frame(self):
        return len(self.timeline) - 1

    def play(self):
        """Play from the current sample (from the start when at the end)."""
        if self.frame >= self.last_frame:
            self.show_frame(0)
        self.clock_s = float(self.timeline.time_s[self.frame])
        self.timer.start()
        self.play_button.setIcon(QtGui.QApplication.style().standardIcon(QtGui.QStyle.SP_MediaPause))
        self._show_status()

    def pause(self):
        """Stop the timer; the robot stays where it is."""
        self.timer.stop()
        self.play_button.setIcon(QtGui.QApplication.style().standardIcon(QtGui.QStyle.SP_MediaPlay))
        self._show_status()

    def toggle(self):
        """Play or pause."""
        if self.playing:
            self.pause()
        else:
            self.play()

    def step(self, n):
        """Pause and go `n` samples forward (negative: back)."""
        self.pause()
        self.show_frame(self.frame + int(n))

    def set_speed(self, factor):
        """Playback speed, times real time (clamped to 0.1..10)."""
        self.speed_box.setValue(float(factor))

    def _tick(self):
        self.clock_s += TICK_MS / 1000.0 * self.speed_box.value()
        frame = self.timeline.sample_at(self.clock_s)
        if frame >= self.last_frame:
            self.timer.stop()
            self.play_button.setIcon(QtGui.QApplication.style().standardIcon(QtGui.QStyle.SP_MediaPlay))
        self.show_frame(frame)

    def _slider_moved(self, value):
        if value != self.frame:
            self.show_frame(value)

    def show_frame(self, i):
        """Show sample `i` (clamped): robot pose, trace, labels."""
        i = min(max(int(i), 0), self.last_frame)
        self.frame = i
        timeline = self.timeline
        self.robot.set_joints(timeline.q_deg[i])
        self._show_external(i)
        if self.slider.value() != i:
            self.slider.blockSignals(True)
            self.slider.setValue(i)
            self.slider.blockSignals(False)
        self.time_label.setText(translate("CadRobot", "t = {0:.2f} s of {1:.2f} s").format(
            timeline.time_s[i], timeline.time_s[-1]))
        self.move_label.setText(self.describe(i))
        q = self.robot.model.controller_joints(timeline.q_deg[i])
        for label, value in zip(self.joint_labels, q):
            label.setText("%.1f\u00b0" % value)
        self._show_status()

    def _show_external(self, i):
        """The mechanisms, the robot base and the TCP trace at sample `i`."""
        trace = self.timeline.tcp_u[:i + 1]
        if self.mechanisms is not None:
            values = self.timeline.external
            self.mechanisms.show(values[i])
            for label, unit, value in zip(self.external_labels, self._external_units, values[i]):
                label.setText("%.1f%s" % (value, unit))
            if self.timeline.base_u is not None:      # the robot on its track
                self.robot.set_base(self.timeline.base_u[i])
            trace = self.mechanisms.on_part(trace, values[:i + 1])
        self.robot.set_trace(trace)

    def _show_status(self):
        failure = self.timeline.failure
        if failure is not None and self.frame == failure.sample:
            self.pause_timer_only()
            text = translate("CadRobot", "Stopped: {0}").format(failure.reason)
            self.status_label.setStyleSheet("color: red;")
        else:
            self.status_label.setStyleSheet("")
            if self.frame == self.last_frame:
                text = translate("CadRobot", "Finished: every move can be run.")
            elif self.playing:
                text = translate("CadRobot", "Playing")
            else:
                text = translate("CadRobot", "Paused")
        self.status_label.setText(text)

    def pause_timer_only(self):
        if self.timer.isActive():
            self.timer.stop()
            self.play_button.setIcon(QtGui.QApplication.style().standardIcon(QtGui.QStyle.SP_MediaPlay))

    # -- task dialog --
    BUTTONS = ("Close",)

    def ok(self):
        """Nothing to do: (a Close button only) the player closes."""
        return True

    def close_panel(self):
        close_player()

    def clean_up(self):
        """Stop playing, take the robot out of the view and show the cell's own again."""
        self.timer.stop()
        self.robot.remove()
        if self.mechanisms is not None:
            self.mechanisms.restore()
        robot_display.hold(self.cell, False)


# --- opening and closing -------------------------------------------------------------------

def open_player(cell, trajectories=None, dt_s=DT_S, progress=None, axes=None):
    """Open the player on `cell` in the task view.

    Parameters
    ----------
    cell : App.DocumentObject
        A CadRobot cell; its program is checked with ``api.check``.
    trajectories : list of (str, array_like (N, 4, 4), array_like (N,)), optional
        TCP paths to play instead of the program: ``(label, T_u_t, time_s)``
        (poses in {U}, mm; times in s).  All are drawn; the robot follows
        the last.
    dt_s : float
        Sampling time of the program's timeline, s.
    progress : callable, optional
        ``progress(fraction, text)`` of the preparation (``core.progress``);
        returning False raises ``Cancelled`` before anything is shown.
    axes : sensors.scene.AxesAlongPath, optional
        A sensor run's external axes (``scene.robot.axes``): `trajectories` are then
        in the part's frame, and the player turns the positioner (moves the track)
        as the run did.

    Returns
    -------
    PlayerPanel

    Raises
    ------
    CadRobotError
        When the cell cannot be read (``api.check``), or another task
        panel is open.
    """

    def make_player():
        result = api.check(cell, progress=stage(progress, 0.0, 0.9))
        report_now(progress, 0.9, "preparing the player")
        program = result.program
        model = api.robot(program.robot)
        if trajectories:
            timeline, describe, polylines = _trajectory_source(cell, program, model, trajectories,
                                                               axes)
        else:
            timeline, describe, polylines = _program_source(cell, result, model, dt_s)
        report_now(progress, 1.0, "preparing the player")     # the last chance to cancel
        view = FreeCADGui.getDocument(cell.Document.Name).activeView()
        robot = RobotView(view, model, _base_of(cell, result), program.tool.T_f_t)
        legend = [(label, robot.add_polyline(points)) for label, points in polylines]
        mechanisms = None
        if program.external is not None and timeline.external is not None:
            mechanisms = MechanismView(view, program.external, cell)
        return PlayerPanel(cell.Label, robot, timeline, describe, legend, cell, mechanisms,
                           None if trajectories else program)

    return _slot.open(make_player,
                      "Another task panel is open; close it before starting the simulation.")


def active_player():
    """The open PlayerPanel, or None."""
    return _slot.panel


def close_player():
    """Close the player, if open, and remove its robot from the view."""
    _slot.close()
