# CadRobot -- App start-up (FreeCAD and FreeCADCmd).
#
# FreeCAD runs this file at every start for each folder of its Mod directories
# (tools/setup.sh links this repository as <UserAppData>/Mod/CadRobot); before
# that it has put this folder on sys.path, so `import CadRobotWB` works in
# macros, in FreeCADCmd and in documents that reference our proxies.
#
# Keep it silent and import-free: it runs in every FreeCAD process, and the
# `cadrobot` CLI and `freecadcmd -c` must keep a clean stdout.
#
# Note: FreeCAD 0.20 exec()s this file without __file__ and with its own
# locals; anything defined here is not visible from functions defined here.
