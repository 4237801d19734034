# CadRobot -- GUI start-up: registers the CadRobot workbench.
#
# FreeCAD 0.20 exec()s this file inside a function: __file__ is not defined and
# names defined at the top level here are NOT visible inside the methods below
# (they only see FreeCAD's own globals). So every method imports what it uses.

import FreeCADGui


class CadRobotWorkbench(FreeCADGui.Workbench):
    """CadRobot: robot programs from CAD drawings."""

    MenuText = "CadRobot"
    ToolTip = ("Robot programs from CAD drawings: seam paths, tool markers, calibration "
               "frames, post-processors (ABB, Motoman, KUKA, UR, Fanuc) and sensor simulation")

    def __init__(self):
        self.__class__.Icon = self.resource_path("icons", "CadRobot.svg")

    @staticmethod
    def module_dir():
        """Folder that holds the CadRobotWB package (this workbench's root)."""
        import importlib.util
        import os
        try:
            spec = importlib.util.find_spec("CadRobotWB")      # does not import it
            if spec is not None and spec.submodule_search_locations:
                return os.path.dirname(list(spec.submodule_search_locations)[0])
        except (ImportError, ValueError):
            pass
        import FreeCAD
        return os.path.join(FreeCAD.getUserAppDataDir(), "Mod", "CadRobot")

    @classmethod
    def resource_path(cls, *parts):
        import os
        return os.path.join(cls.module_dir(), "CadRobotWB", "resources", *parts)

    def Initialize(self):
        """Load the commands (first activation only). A broken commands module is
        reported in the Report view and must not break FreeCAD's start-up."""
        import FreeCAD
        import FreeCADGui
        FreeCADGui.addIconPath(self.resource_path("icons"))
        try:
            from CadRobotWB import commands
        except Exception as exc:  # noqa: BLE001 -- report every failure, keep FreeCAD usable
            import traceback
            FreeCAD.Console.PrintError(
                "CadRobot: the workbench commands could not be loaded: %s: %s\n"
                % (type(exc).__name__, exc))
            FreeCAD.Console.PrintLog(traceback.format_exc())
            return
        # commands.TOOLBARS: [(title, [command names]), ...]; commands.COMMANDS: a flat list.
        toolbars = list(getattr(commands, "TOOLBARS", None) or [])
        if not toolbars and getattr(commands, "COMMANDS", None):
            toolbars = [("CadRobot", list(commands.COMMANDS))]
        for title, names in toolbars:
            self.appendToolbar(title, list(names))
            self.appendMenu("&CadRobot", list(names))

    def Activated(self):
        pass

    def Deactivated(self):
        pass

    def GetClassName(self):
        return "Gui::PythonWorkbench"


def _register_at_start_up(resources):
    """Preferences page, its icon and the translations: there before the workbench is
    first activated. A failure is reported and must not break FreeCAD's start-up."""
    import os
    import FreeCAD
    import FreeCADGui
    try:
        FreeCADGui.addIconPath(os.path.join(resources, "icons"))
        FreeCADGui.addLanguagePath(os.path.join(resources, "translations"))
        FreeCADGui.updateLocale()
        from CadRobotWB.gui import preferences_page
        preferences_page.register()
    except Exception as exc:  # noqa: BLE001 -- report every failure, keep FreeCAD usable
        import traceback
        FreeCAD.Console.PrintError("CadRobot: the preferences page could not be added: %s: %s\n"
                                   % (type(exc).__name__, exc))
        FreeCAD.Console.PrintLog(traceback.format_exc())


FreeCADGui.addWorkbench(CadRobotWorkbench())
_register_at_start_up(CadRobotWorkbench.resource_path())

