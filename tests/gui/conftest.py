"""GUI-tier fixtures: these tests run inside the real FreeCAD main window (Xvfb)."""

import os
import sys

import pytest

import FreeCAD
import FreeCADGui
from PySide import QtGui

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "examples"))


from CadRobotWB import compat

# Camera moves are instant, so a picture taken after viewTop()/fitAll() shows the
# final camera (FreeCAD 1.x animates them by default; see compat.no_camera_animation).
compat.no_camera_animation()


def process_events():
    QtGui.QApplication.processEvents()


@pytest.fixture
def gui_doc():
    assert FreeCAD.GuiUp, "the GUI tier must run inside the FreeCAD GUI"
    document = FreeCAD.newDocument("CadRobotGui")
    FreeCADGui.setActiveDocument(document.Name)
    compat.no_camera_animation(FreeCADGui.getDocument(document.Name).activeView())
    process_events()
    name = document.Name
    yield document
    if name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(name)
    process_events()


def render(view, path, width=640, height=480):
    """Save the 3D view as a PNG on a white background; returns a QImage of it.

    Enough waiting: camera moves are instant (``no_camera_animation`` above), the
    event loop runs once so queued work (``gui/soon.call_soon``) is done, and the view
    is drawn on screen first (``compat.draw_now``), so the picture shows the scene as
    the test left it.
    """
    process_events()
    compat.draw_now(view)
    process_events()
    view.saveImage(str(path), width, height, "White")
    image = QtGui.QImage(str(path))
    assert not image.isNull(), "saveImage wrote no readable PNG"
    return image


def non_white_pixels(image):
    """How many pixels differ from the white background."""
    white = QtGui.QColor("white").rgb()
    return sum(1 for y in range(image.height()) for x in range(image.width())
               if image.pixel(x, y) != white)


def close_panels():
    """Close every CadRobot task panel and message box (tests start and end clean)."""
    from CadRobotWB.commands import base as command_base
    from CadRobotWB.gui import calibration_panel, generate_panel, new_cell_panel, risk_area_panel
    for module in (new_cell_panel, calibration_panel, risk_area_panel, generate_panel):
        module.close_panel()
    if FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.closeDialog()
    if command_base._message_box is not None:
        command_base._message_box.close()
        command_base._message_box = None
    process_events()
