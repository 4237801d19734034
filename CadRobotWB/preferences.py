"""CadRobot's user preferences, kept in FreeCAD's parameter tree (App level, no GUI).

The GUI's preferences page edits the same parameters; API functions keep
their explicit defaults, and GUI commands pass the preference values
explicitly in their journaled calls, so a recorded macro replays the same.

``DefaultPost`` "" means the robot's own language; ``OutputFolder`` "" means
the document's folder; ``PostFolder`` is searched for user posts;
``UserRobotFolder`` keeps the robots imported from URDF files ("" means
``CadRobot/robots`` in FreeCAD's user data folder); ``WeldScheduleFolder`` keeps
the user's weld schedules ("" means ``CadRobot/weld_schedules`` beside it).
"""

import os

import FreeCAD

from .robots.catalog import catalog

PATH = "User parameter:BaseApp/Preferences/Mod/CadRobot"

DEFAULTS = {
    "DefaultRobot": "ABB_IRB2400",
    "DefaultPost": "",
    "OutputFolder": "",
    "ApproachDistance": 50.0,     # mm
    "InterpolationStep": 0.0,     # mm; 0 = speed x sample time
    "RiskThreshold": 30.0,        # degrees between consecutive segment orientations
    "PostFolder": "",
    "UserRobotFolder": "",        # "" = <FreeCAD user data>/CadRobot/robots
    "WeldScheduleFolder": "",     # "" = <FreeCAD user data>/CadRobot/weld_schedules
}


def _default(name):
    try:
        return DEFAULTS[name]
    except KeyError:
        raise KeyError("CadRobot has no preference '%s'; known: %s."
                       % (name, ", ".join(sorted(DEFAULTS)))) from None


def get(name):
    """The value of preference `name`: str, or float for the numeric ones."""
    default = _default(name)
    group = FreeCAD.ParamGet(PATH)
    if isinstance(default, float):
        return float(group.GetFloat(name, default))
    return group.GetString(name, default)


def set(name, value):  # noqa: A001  (the contract's name)
    """Store preference `name` (converted to the default's type)."""
    default = _default(name)
    group = FreeCAD.ParamGet(PATH)
    if isinstance(default, float):
        group.SetFloat(name, float(value))
    else:
        group.SetString(name, str(value))


#: Environment variable that overrides the ``UserRobotFolder`` preference (a team's
#: shared robot folder, a CI run).
ROBOT_FOLDER_VARIABLE = "CADROBOT_ROBOT_FOLDER"


def user_robot_folder():
    """str: the folder imported robots are kept in: ``$CADROBOT_ROBOT_FOLDER``, else the
    ``UserRobotFolder`` preference, else ``CadRobot/robots`` in FreeCAD's user data folder."""
    return (os.environ.get(ROBOT_FOLDER_VARIABLE) or get("UserRobotFolder")
            or os.path.join(FreeCAD.getUserAppDataDir(), "CadRobot", "robots"))


def use_user_robot_folder():
    """Make the catalog list the robots of the user robot folder."""
    catalog.set_user_folder(user_robot_folder())


#: Environment variable that overrides the ``WeldScheduleFolder`` preference.
WELD_SCHEDULE_FOLDER_VARIABLE = "CADROBOT_WELD_SCHEDULE_FOLDER"


def weld_schedule_folder():
    """str: the folder the user's weld schedules are kept in (beside the user robot
    folder): ``$CADROBOT_WELD_SCHEDULE_FOLDER``, else the ``WeldScheduleFolder``
    preference, else ``CadRobot/weld_schedules`` in FreeCAD's user data folder."""
    return (os.environ.get(WELD_SCHEDULE_FOLDER_VARIABLE) or get("WeldScheduleFolder")
            or os.path.join(FreeCAD.getUserAppDataDir(), "CadRobot", "weld_schedules"))
