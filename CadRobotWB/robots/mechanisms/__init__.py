"""External axes without FreeCAD: the catalog of real tracks and positioners (catalog), and their values chosen per target (choose); imports core/, errors and the robots subpackages before it."""
