"""A mechanism drawn in the 3D view before it is added: the Add positioner / Add track preview.

:class:`MechanismPreview` draws the catalog's solids of a kind and model
(``catalog.solids``, what the document's Positioner or Track draws after OK)
at its axes' zero values, which a new object shows (``objects.mechanism.zeros``),
under one ``SoTransform`` holding its base in {U}::

    CadRobotMechanismPreview (SoSeparator)
    +-- SoPickStyle UNPICKABLE
    +-- base (SoTransform)            the base typed in the panel, {U}
    +-- one mesh per body             built with the base at the identity

Moving the base sets the transform only; the meshes are built again only for
another kind, model or track travel. Nothing is added to the document.
"""

from types import SimpleNamespace

import numpy as np
from pivy import coin

from ..robots.mechanisms import catalog
from . import mechanism_view, robot_view

_NODE_NAME = "CadRobotMechanismPreview"


class MechanismPreview:
    """The solids of one mechanism, in a view's scene graph, at a base that can move.

    Parameters
    ----------
    view : Gui.View3DInventor
    kind : str
        ``"track"``, ``"turntable"`` or ``"tilt_turn"``.
    model : str or None
        Catalog name; None: the generic mechanism.
    length_mm : float or None
        A track's travel.

    Attributes
    ----------
    key : tuple
        (kind, model, length_mm): what the meshes were built for.
    base : coin.SoTransform
        The base in {U}.

    Raises
    ------
    CadRobotError
        What ``catalog.build`` refuses (e.g. a travel longer than the model's).
    """

    def __init__(self, view, kind, model, length_mm=None):
        self.key = (kind, model, length_mm)
        mechanism = catalog.build(kind, model, length_mm=length_mm)
        self.scene = view.getSceneGraph()
        self.root = coin.SoSeparator()
        self.root.setName(_NODE_NAME)
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        self.root.addChild(pick)
        self.base = coin.SoTransform()
        self.root.addChild(self.base)
        for k, (vertices, faces) in enumerate(catalog.solids(mechanism)):
            color = mechanism_view.BASE_COLOR if k == 0 else mechanism_view.BODY_COLOR
            self.root.addChild(robot_view.mesh_node(SimpleNamespace(vertices=vertices, faces=faces),
                                                    color))
        self.scene.addChild(self.root)

    def set_base(self, T_u_base):
        """Put the base at `T_u_base` (4x4, {U}, mm)."""
        robot_view.set_transform(self.base, np.asarray(T_u_base, dtype=float))

    @property
    def shown(self):
        """bool: the nodes are in the view's scene graph."""
        return self.scene is not None and self.scene.findChild(self.root) >= 0

    def remove(self):
        """Take the nodes out of the view (safe to call twice, or after the view closed)."""
        if self.scene is not None:
            robot_view.remove_from_scene(self.scene, self.root)
        self.scene = None
