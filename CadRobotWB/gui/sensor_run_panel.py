"""The sensor run panel: a task panel that runs a cell's path with a sensor in the loop.

``open_panel(cell)`` shows the set-up (sensor, controller, correction rate,
the rigid deviation of the real part, the noise seed), a Run button that
calls :func:`~CadRobotWB.simulation.simulate_cell` with the chosen
controller and the ones it is compared with, the results (completed or
aborted and why, the key metrics), the plots of
:mod:`~CadRobotWB.report_plots`, and a "Play in 3D" button that hands the
nominal and the corrected path to the simulation player.

Only the view changes: nothing is written into the document.
"""

import traceback

import FreeCAD
import FreeCADGui
import numpy as np
from PySide import QtCore, QtGui

from .. import dependencies, limits, report_plots, simulation
from ..errors import CadRobotError, InputError
from ..objects import base, joint_faces, reader
from ..sensors import run as sensor_run
from ..sensors.joint_detection import not_offered_note
from . import progress as gui_progress
from . import simulation_player
from .task_panels import PanelSlot, TaskPanel

translate = FreeCAD.Qt.translate
QT_TRANSLATE_NOOP = FreeCAD.Qt.QT_TRANSLATE_NOOP

#: (sensor, label) as offered.
SENSORS = (("laser", QT_TRANSLATE_NOOP("CadRobot", "Laser seam tracking")),
           ("force", QT_TRANSLATE_NOOP("CadRobot", "Force profile following")),
           ("arc", QT_TRANSLATE_NOOP("CadRobot", "Through-arc seam tracking")))
#: (controller, label) as offered.
CONTROLLERS = (("pi", QT_TRANSLATE_NOOP("CadRobot", "PI")),
               ("fuzzy_pi", QT_TRANSLATE_NOOP("CadRobot", "Fuzzy-PI")),
               ("none", QT_TRANSLATE_NOOP("CadRobot", "None (open loop)")))
#: Default correction rate per sensor, Hz (the paper's 5 Hz laser, 20 Hz force loop; the arc
#: corrects once per weave cycle: no rate to set).
DEFAULT_RATE_HZ = {"laser": 5.0, "force": 20.0}
#: Controllers a sensor does not run (the arc's law is its own per-cycle one).
NOT_FOR_SENSOR = {"arc": ("fuzzy_pi",)}
#: Deviation spin boxes: (name, unit suffix, range).
DEVIATION_AXES = (("x", " mm", 500.0), ("y", " mm", 500.0), ("z", " mm", 500.0),
                  ("rx", " \u00b0", 180.0), ("ry", " \u00b0", 180.0), ("rz", " \u00b0", 180.0))

_slot = PanelSlot(before_close=lambda panel: panel.stop())


# --- what to run ---------------------------------------------------------------------------

def default_sensor(cell, detection=None):
    """The sensor the panel preselects: the one `detection` (the path's
    :class:`~CadRobotWB.sensors.joint_detection.JointDetection`) calls for;
    without one, ``"force"`` when a tool marker of `cell` is a ball tool,
    else ``"laser"``."""
    if detection is not None and detection.sensor is not None:
        return detection.sensor
    for obj in reader.cell_members(cell):
        if base.type_of(obj) == "ToolMarker" and getattr(obj, "ToolShape", "") == "Ball":
            return "force"
    return "laser"


def detect_path(cell):
    """(detection or None, note): the cell's first path classified for its sensor,
    or None and why it could not be read."""
    try:
        return simulation.path_fit_or_raise(cell), ""
    except CadRobotError as exc:
        return None, translate("CadRobot", "The faces along the path could not be read ({0}); "
                                           "both sensors are offered.").format(exc)


def controllers_to_run(sensor, controller):
    """The controllers run together: the chosen one first, then its comparisons.

    Force following compares PI with Fuzzy-PI (paper Figure 14), and every
    closed loop is compared with the open loop ``"none"``.
    """
    if controller == "none":
        return ["none"]
    if sensor == "force":
        other = "fuzzy_pi" if controller == "pi" else "pi"
        return [controller, other, "none"]
    return [controller, "none"]


def corrected_poses(trajectory, run):
    """TCP poses of a run: the nominal orientation nearest in time, the run's positions.

    Parameters
    ----------
    trajectory : core.trajectory.Trajectory
        The nominal path (``time_s`` (M,), ``T_u_t`` (M, 4, 4)).
    run : SensorRun
        ``time_s`` (N,), ``actual_mm`` (N, 3).

    Returns
    -------
    ndarray, shape (N, 4, 4)
    """
    samples = np.arange(len(trajectory.time_s))
    nearest = np.rint(np.interp(run.time_s, trajectory.time_s, samples)).astype(int)
    poses = np.array(trajectory.T_u_t[nearest], dtype=float)
    poses[:, :3, 3] = run.actual_mm
    return poses


def player_trajectories(scene, run):
    """``[("nominal", T_u_t, time_s), ("corrected", T_u_t, time_s)]`` for the player."""
    trajectory = scene.trajectory
    return [("nominal", np.asarray(trajectory.T_u_t), np.asarray(trajectory.time_s)),
            ("corrected", corrected_poses(trajectory, run), np.asarray(run.time_s))]


def controller_label(controller):
    """How a controller is named in the results."""
    if controller == "none":
        return translate("CadRobot", "Open loop")
    return translate("CadRobot", dict(CONTROLLERS)[controller])


def run_summary(run):
    """One line of HTML: how `run` ended (the reason in red when it aborted) and its
    key numbers, each a number or a sentence saying why there is none."""
    if run.aborted:
        state = '<span style="color:red;">%s</span>' % translate(
            "CadRobot", "aborted: {0}").format(_escaped(run.reason))
    else:
        state = translate("CadRobot", "completed")
    phrases = [p[:1].upper() + p[1:] for p in sensor_run.metric_phrases(run, with_notes=False)]
    return "<b>%s</b>: %s. %s." % (controller_label(run.controller), state,
                                  ". ".join(_escaped(p) for p in phrases))


def results_html(runs):
    """HTML for the results label: one line per run, then the runs' notes once."""
    lines = [run_summary(run) for run in runs]
    notes = []
    for run in runs:
        notes += [n for n in run.notes if n not in notes]
    lines += ['<span style="color:#a60;">%s</span>' % _escaped(n) for n in notes]
    return "<br>".join(lines)


def _escaped(text):
    return str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


# --- the panel -----------------------------------------------------------------------------

def _set_item_enabled(combo, index, enabled):
    """Enable or disable one item of a combo box (it stays listed, greyed out)."""
    item = combo.model().item(index) if hasattr(combo.model(), "item") else None
    if item is not None:
        item.setEnabled(enabled)


def is_item_enabled(combo, index):
    """Whether item `index` of `combo` can be chosen."""
    return bool(combo.model().flags(combo.model().index(index, 0)) & QtCore.Qt.ItemIsEnabled)


def pixmap_from_png(png):
    """A QPixmap of PNG bytes."""
    pixmap = QtGui.QPixmap()
    pixmap.loadFromData(png, "PNG")
    return pixmap


class PlotLabel(QtGui.QLabel):
    """A label showing a PNG scaled to the label's width (never enlarged).

    It takes the width the panel gives it rather than asking for the PNG's,
    so a wide plot does not widen the task view.

    Attributes
    ----------
    full : QtGui.QPixmap
        The PNG at its own size (null when there is none).
    """

    def __init__(self):
        super().__init__()
        self.full = QtGui.QPixmap()
        self.setAlignment(QtCore.Qt.AlignCenter)
        self.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)

    def set_png(self, png):
        """Show PNG bytes (None: nothing)."""
        self.full = pixmap_from_png(png) if png else QtGui.QPixmap()
        self._fit(force=True)

    def resizeEvent(self, event):
        super().resizeEvent(event)
        self._fit()

    def _fit(self, force=False):
        if self.full.isNull():
            self.clear()
            return
        width = max(1, min(self.width(), self.full.width()))
        shown = self.pixmap()
        if force or shown is None or shown.isNull() or shown.width() != width:
            scaled = self.full.scaledToWidth(width, QtCore.Qt.SmoothTransformation)
            self.setPixmap(scaled)
            self.setFixedHeight(scaled.height())


class SensorRunPanel(TaskPanel):
    """Task panel: set up, run and review a sensor simulation of one cell.

    Parameters
    ----------
    cell : App.DocumentObject
    settings : dict, optional
        Initial values, as returned by :meth:`settings`.

    Attributes
    ----------
    form : QtGui.QWidget
        What FreeCAD shows in the task view.
    scene, reality, runs
        The last run's :func:`~CadRobotWB.simulation.simulate_cell` result
        (None before a run); ``runs[0]`` is the chosen controller's.
    plots : list of (str, bytes)
        Title and PNG of each plot of the last run.
    results_label : QtGui.QLabel
        How the runs ended (red when aborted or on an error).
    plot_label : PlotLabel
        The plot chosen in ``plot_box``, as wide as the panel.
    full_size_window : QtGui.QDialog or None
        The last plot opened at full size (``full_size_button``).
    """

    ACTION_BUTTONS = ('run_button',)

    def __init__(self, cell, settings=None):
        self.cell = cell
        self.closed = False
        self.scene = self.reality = self.runs = None
        self.plots = []
        self.full_size_window = None
        self.detection, unread = detect_path(cell)
        self.form = self._build_form()
        self._offer_sensors(unread)
        sensor = default_sensor(cell, self.detection)
        self.set_settings(dict({"sensor": sensor, "controller": "pi",
                                "rate_hz": DEFAULT_RATE_HZ.get(sensor),
                                "deviation": (0.0,) * 6, "seed": 0}, **(settings or {})))
        self._show_tool_note()
        self.sensor_box.currentIndexChanged.connect(self._sensor_changed)

    # -- widgets --
    def _build_form(self):
        form = QtGui.QWidget()
        form.setWindowTitle(translate("CadRobot", "Sensor run"))
        layout = QtGui.QVBoxLayout(form)
        layout.addWidget(QtGui.QLabel("<b>%s</b>" % self.cell.Label))
        # Set-up, then Run: in view in FreeCAD 1.1's task overlay (about 350 px tall at 1366x768).
        layout.addWidget(self._setup_group())
        layout.addWidget(self._deviation_group())

        self.run_button = QtGui.QPushButton(translate("CadRobot", "Run"))
        self.run_button.setToolTip(translate(
            "CadRobot", "Simulate the path with the sensor correcting it in the deviated part"))
        self.run_button.clicked.connect(self.run)
        layout.addWidget(self.run_button)
        progress_row = QtGui.QHBoxLayout()      # the run reports here; the window stays live
        self.progress_bar = QtGui.QProgressBar()
        progress_row.addWidget(self.progress_bar, 1)
        self.cancel_button = QtGui.QPushButton(translate("CadRobot", "Cancel"))
        self.cancel_button.setToolTip(translate("CadRobot", "Stop the simulation"))
        progress_row.addWidget(self.cancel_button)
        layout.addLayout(progress_row)
        self.runner = gui_progress.ProgressRunner(self.progress_bar, self.cancel_button,
                                                  "CadRobot_SensorRun")
        # Why a sensor is not offered, and what the tool lacks: full width, under Run.
        self.fit_label, self.tool_label = QtGui.QLabel(), QtGui.QLabel()
        for label in (self.fit_label, self.tool_label):
            label.setWordWrap(True)
            label.setStyleSheet("color: #a60;")
            layout.addWidget(label)

        self.results_label = QtGui.QLabel(translate("CadRobot", "Set up the run and press Run."))
        self.results_label.setWordWrap(True)
        self.results_label.setTextFormat(QtCore.Qt.RichText)
        layout.addWidget(self.results_label)

        self.plot_row = QtGui.QWidget()
        row = QtGui.QHBoxLayout(self.plot_row)
        row.setContentsMargins(0, 0, 0, 0)
        self.plot_box = QtGui.QComboBox()
        self.plot_box.setToolTip(translate("CadRobot", "Plot to show"))
        self.plot_box.currentIndexChanged.connect(self.show_plot)
        row.addWidget(self.plot_box, 1)
        self.full_size_button = QtGui.QPushButton(translate("CadRobot", "Full size"))
        self.full_size_button.setToolTip(translate("CadRobot", "Open the plot in its own window"))
        self.full_size_button.clicked.connect(self.show_full_size)
        row.addWidget(self.full_size_button)
        layout.addWidget(self.plot_row)
        self.plot_label = PlotLabel()
        layout.addWidget(self.plot_label)

        self.play_button = QtGui.QPushButton(translate("CadRobot", "Play in 3D"))
        self.play_button.setToolTip(translate(
            "CadRobot", "Close this panel and play the nominal and the corrected path with the "
            "robot in the 3D view"))
        self.play_button.clicked.connect(self._play_later)
        layout.addWidget(self.play_button)
        layout.addStretch(1)
        self._show_results_widgets(False)
        return form

    def _setup_group(self):
        group = QtGui.QGroupBox(translate("CadRobot", "Sensor"))
        grid = QtGui.QFormLayout(group)
        grid.setContentsMargins(4, 4, 4, 4)      # fits FreeCAD's default panel width
        grid.setRowWrapPolicy(QtGui.QFormLayout.WrapLongRows)
        self.sensor_box = QtGui.QComboBox()
        for key, label in SENSORS:
            self.sensor_box.addItem(translate("CadRobot", label), key)
        self.controller_box = QtGui.QComboBox()
        for key, label in CONTROLLERS:
            self.controller_box.addItem(translate("CadRobot", label), key)
        self.controller_box.setToolTip(translate(
            "CadRobot", "Controller of the correction; it is compared with the open loop (and, "
            "for force, PI with Fuzzy-PI)"))
        self.rate_box = QtGui.QDoubleSpinBox()
        self.rate_box.setRange(limits.MIN_RATE_HZ, 1000.0)
        self.rate_box.setDecimals(1)
        self.rate_box.setSuffix(" Hz")
        self.rate_box.setToolTip(translate("CadRobot", "How often the robot's path is corrected"))
        self.seed_box = QtGui.QSpinBox()
        self.seed_box.setRange(0, 2 ** 31 - 1)
        self.seed_box.setToolTip(translate("CadRobot", "Seed of the sensor noise and roughness"))
        for box in (self.sensor_box, self.controller_box):    # fits FreeCAD's default panel width
            box.setSizeAdjustPolicy(QtGui.QComboBox.AdjustToMinimumContentsLengthWithIcon)
            box.setMinimumContentsLength(5)
        grid.addRow(translate("CadRobot", "Sensor"), self.sensor_box)
        grid.addRow(translate("CadRobot", "Controller"), self.controller_box)
        for box in (self.rate_box, self.seed_box):
            box.setSizePolicy(QtGui.QSizePolicy.Ignored, QtGui.QSizePolicy.Fixed)
            box.setMinimumWidth(50)
        numbers = QtGui.QHBoxLayout()          # rate and seed on one row: a short panel
        numbers.addWidget(self.rate_box, 1)
        numbers.addWidget(QtGui.QLabel(translate("CadRobot", "Seed")))
        numbers.addWidget(self.seed_box, 1)
        grid.addRow(translate("CadRobot", "Rate"), numbers)
        return group

    def _offer_sensors(self, unread=""):
        """Enable the sensors that suit the path; the other is disabled with its
        reason as tooltip and as a one-line note under the combo box."""
        notes = [unread] if unread else []
        detection = self.detection
        for index in range(self.sensor_box.count()):
            key = self.sensor_box.itemData(index)
            if key == "arc":
                why = simulation.arc_why_not(self.cell, detection)
            else:
                why = "" if detection is None or detection.sensor is None else detection.why_not(key)
            _set_item_enabled(self.sensor_box, index, not why)
            if why:
                tip = translate("CadRobot", "Not offered: {0}. (api.simulate(cell, sensor='{1}') "
                                            "in the Python console still runs it.)").format(why, key)
                notes.append(not_offered_note(key, why))
            elif detection is not None:
                tip = detection.reason
            else:
                tip = ""
            self.sensor_box.setItemData(index, tip, QtCore.Qt.ToolTipRole)
        if detection is not None and detection.sensor is None:
            notes.append(detection.reason)
        self.fit_label.setText(_escaped(" ".join(notes)))
        self.fit_label.setToolTip(detection.reason if detection is not None else "")
        self.fit_label.setVisible(bool(notes))

    def _show_tool_note(self):
        """Say, under the combo box, when force following lacks the ball tool."""
        text = " ".join(joint_faces.tool_notes(self.cell, self.settings()["sensor"]))
        self.tool_label.setText(_escaped(text))
        self.tool_label.setVisible(bool(text))

    def _deviation_group(self):
        group = QtGui.QGroupBox(translate("CadRobot", "Deviation of the real part"))
        group.setToolTip(translate(
            "CadRobot", "Where the real part is against the drawing: moved along X, Y, Z of the "
            "assembly and turned about them (about the path's start)"))
        grid = QtGui.QGridLayout(group)
        grid.setContentsMargins(4, 4, 4, 4)
        self.deviation_boxes = []
        for i, (name, suffix, limit) in enumerate(DEVIATION_AXES):
            box = QtGui.QDoubleSpinBox()
            box.setRange(-limit, limit)
            box.setDecimals(2)
            box.setSingleStep(0.5)
            box.setSuffix(suffix)
            box.setButtonSymbols(QtGui.QAbstractSpinBox.NoButtons)   # two columns in ~250 px
            column, row = divmod(i, 3)         # x, y, z left; rx, ry, rz right
            grid.addWidget(QtGui.QLabel(name), row, 2 * column)
            grid.addWidget(box, row, 2 * column + 1)
            self.deviation_boxes.append(box)
        return group

    def _show_results_widgets(self, shown):
        for widget in (self.plot_row, self.plot_label, self.play_button):
            widget.setVisible(shown)

    # -- settings --
    def settings(self):
        """The set-up as a dict: ``sensor``, ``controller``, ``rate_hz`` (None for the
        arc: once per weave cycle), ``deviation`` (x, y, z mm, rx, ry, rz degrees),
        ``seed``."""
        sensor = self.sensor_box.itemData(self.sensor_box.currentIndex())
        return {"sensor": sensor,
                "controller": self.controller_box.itemData(self.controller_box.currentIndex()),
                "rate_hz": self.rate_box.value() if sensor in DEFAULT_RATE_HZ else None,
                "deviation": tuple(box.value() for box in self.deviation_boxes),
                "seed": self.seed_box.value()}

    def set_settings(self, settings):
        """Set the widgets from a dict like :meth:`settings` returns (missing keys kept)."""
        if "sensor" in settings:
            self.sensor_box.setCurrentIndex(self.sensor_box.findData(settings["sensor"]))
        if "controller" in settings:
            self.controller_box.setCurrentIndex(self.controller_box.findData(settings["controller"]))
        if settings.get("rate_hz") is not None:
            self.rate_box.setValue(float(settings["rate_hz"]))
        self._fit_to_sensor()
        if "deviation" in settings:
            for box, value in zip(self.deviation_boxes, settings["deviation"]):
                box.setValue(float(value))
        if "seed" in settings:
            self.seed_box.setValue(int(settings["seed"]))

    def _sensor_changed(self, _index):
        sensor = self.settings()["sensor"]
        if sensor in DEFAULT_RATE_HZ:
            self.rate_box.setValue(DEFAULT_RATE_HZ[sensor])
        self._fit_to_sensor()
        self._show_tool_note()

    def _fit_to_sensor(self):
        """The rate only for sensors that have one; controllers the sensor does not run
        greyed out (the chosen one moved to PI)."""
        sensor = self.sensor_box.itemData(self.sensor_box.currentIndex())
        self.rate_box.setEnabled(sensor in DEFAULT_RATE_HZ)
        excluded = NOT_FOR_SENSOR.get(sensor, ())
        for index in range(self.controller_box.count()):
            _set_item_enabled(self.controller_box, index,
                              self.controller_box.itemData(index) not in excluded)
        if self.controller_box.itemData(self.controller_box.currentIndex()) in excluded:
            self.controller_box.setCurrentIndex(self.controller_box.findData("pi"))

    # -- running --
    def run(self):
        """Run the simulation with the panel's settings and show the results.

        Returns
        -------
        bool
            True when the simulation ran (its runs may still have aborted),
            False on an error (shown in red).
        """
        if self.runner.running or gui_progress.busy():
            return False          # a second click while running (through processEvents)
        s = self.settings()
        self._show_results_widgets(False)
        self.results_label.setStyleSheet("")
        self.results_label.setText(translate("CadRobot", "Running..."))
        self.run_button.setEnabled(False)
        try:
            # Results live in the panel only: a cancelled run leaves the document and the
            # last results as they were.
            scene, reality, runs = self.runner.run(
                simulation.simulate_cell, self.cell, s["sensor"],
                controllers_to_run(s["sensor"], s["controller"]), s["deviation"], s["rate_hz"],
                seed=s["seed"], detection=self.detection)
            if self.closed:
                return False
            self.scene, self.reality, self.runs = scene, reality, runs
            self.plots = self._make_plots()
        except gui_progress.Cancelled:
            if not self.closed:
                self.results_label.setText(translate("CadRobot", "Cancelled: nothing was changed."))
            return False
        except CadRobotError as exc:
            if not self.closed:
                self.show_error(exc)
            return False
        except Exception as exc:  # noqa: BLE001 -- a bug: say so in the panel, trace in the log
            FreeCAD.Console.PrintError(traceback.format_exc())
            self.show_error(InputError(translate("CadRobot", "The simulation failed: {0}: {1} "
                                                 "(details in the Report view).").format(
                type(exc).__name__, exc)))
            return False
        finally:
            if not self.closed:
                self.run_button.setEnabled(True)
        self.results_label.setText(results_html(self.runs))
        self.plot_box.blockSignals(True)
        self.plot_box.clear()
        self.plot_box.addItems([title for title, _ in self.plots])
        self.plot_box.blockSignals(False)
        self.show_plot(0)
        self._show_results_widgets(True)
        return True

    def _make_plots(self):
        from ..sensors.scene import real_seam
        if not report_plots.is_available():
            dependencies.warn_missing(report_plots.PACKAGE)   # Report view, once per session
            return []
        if self.scene.sensor in ("laser", "arc"):
            first = (translate("CadRobot", "Seam corrections"),
                     report_plots.plot_corrections(self.runs, self.scene.trajectory))
        else:
            force_set_n = self.scene.options.get("force_set_n", 20.0)
            first = (translate("CadRobot", "Contact force"),
                     report_plots.plot_forces(self.runs, force_set_n))
        paths = (translate("CadRobot", "Paths"),
                 report_plots.plot_paths(self.runs[0], real_seam(self.scene, self.reality)))
        return [first, paths]

    def show_plot(self, index):
        """Show plot `index` of :attr:`plots` (and select it in ``plot_box``)."""
        if not 0 <= index < len(self.plots):
            self.plot_label.set_png(None)
            return
        if self.plot_box.currentIndex() != index:
            self.plot_box.setCurrentIndex(index)     # comes back here
            return
        title, png = self.plots[index]
        self.plot_label.set_png(png)
        self.plot_label.setToolTip(title)

    def show_full_size(self):
        """Open the plot shown in a window of its own, at full size (scrolling if needed)."""
        title, png = self.plots[self.plot_box.currentIndex()]
        pixmap = pixmap_from_png(png)
        label = QtGui.QLabel()
        label.setPixmap(pixmap)
        area = QtGui.QScrollArea()
        area.setWidget(label)
        window = QtGui.QDialog(FreeCADGui.getMainWindow())
        window.setWindowTitle("%s: %s" % (self.cell.Label, title))
        QtGui.QVBoxLayout(window).addWidget(area)
        window.resize(min(pixmap.width() + 40, 1200), min(pixmap.height() + 40, 900))
        window.setAttribute(QtCore.Qt.WA_DeleteOnClose)
        window.show()
        self.full_size_window = window
        return window

    def show_error(self, exc):
        """Show a CadRobotError in red and select the object at fault, if it names one."""
        FreeCAD.Console.PrintError("%s\n" % exc)
        self._show_results_widgets(False)
        self.results_label.setStyleSheet("color: red;")
        self.results_label.setText(_escaped(exc))
        obj = self.cell.Document.getObject(exc.obj_name) if getattr(exc, "obj_name", None) else None
        if obj is not None:
            FreeCADGui.Selection.clearSelection()
            FreeCADGui.Selection.addSelection(obj)

    # -- playing --
    def _play_later(self):
        # The button's own panel is deleted when the dialog closes: not inside its signal.
        QtCore.QTimer.singleShot(0, self.play)

    def play(self):
        """Close the panel and play the nominal and the corrected path in the 3D view.

        Returns
        -------
        PlayerPanel or None
            None when the player could not open (the panel then opens again
            with the error).
        """
        if not self.runs:
            return None
        trajectories = player_trajectories(self.scene, self.runs[0])
        cell, settings = self.cell, self.settings()
        close_panel()
        try:
            return simulation_player.open_player(cell, trajectories, axes=self.scene.robot.axes)
        except CadRobotError as exc:
            open_panel(cell, settings).show_error(exc)
            return None

    # -- task dialog --
    BUTTONS = ("Close",)

    def ok(self):
        """Nothing to do: (a Close button only) the panel closes."""
        return True

    def close_panel(self):
        close_panel()

    def stop(self):
        """The panel closes: cancel a running simulation (it stops at its next report)."""
        self.closed = True
        self.runner.cancel()


# --- opening and closing -------------------------------------------------------------------

def open_panel(cell, settings=None):
    """Open the sensor run panel on `cell` in the task view.

    Parameters
    ----------
    cell : App.DocumentObject
        A CadRobot cell.
    settings : dict, optional
        Initial set-up (see :meth:`SensorRunPanel.settings`).

    Returns
    -------
    SensorRunPanel

    Raises
    ------
    CadRobotError
        When another task panel is open.
    """
    return _slot.open(lambda: SensorRunPanel(cell, settings),
                      "Another task panel is open; close it before starting a sensor run.")


def active_panel():
    """The open SensorRunPanel, or None."""
    return _slot.panel


def close_panel():
    """Close the panel, if open."""
    _slot.close()
