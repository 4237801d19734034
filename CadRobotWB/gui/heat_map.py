"""The placement search drawn on the floor of the 3D view: one square per grid position.

Colour of a square (the best base of its heights and turns,
``robots.placement.placement_search.HeatMap``):

* the score, from dark blue (lowest of the search) through green to yellow
  (highest): a base there passes the full check;
* the same colour washed out towards white: passes the reach screen, not
  checked in full (the search stopped once it had found enough);
* red: the bases there pass the screen but fail the full check (collision,
  joint speed ...);
* grey: no base there passes the screen (out of reach, joint limits,
  singularity, no single arm configuration).

Scene graph (added to the view's root, nothing added to the document)::

    SoSeparator "CadRobotPlacementHeatMap"
    +-- SoPickStyle UNPICKABLE, SoLightModel BASE_COLOR
    +-- SoMaterial (one colour per square), SoMaterialBinding PER_FACE
    +-- SoCoordinate3, SoFaceSet
"""

import numpy as np
from pivy import coin

from ..robots.placement import placement_search as ps
from .robot_view import remove_from_scene

#: Colours, RGB 0..1.
FAIL_SCREEN_COLOR = (0.62, 0.62, 0.62)
FAIL_CHECK_COLOR = (0.86, 0.12, 0.10)
_SCORE_STOPS = np.array([[0.19, 0.23, 0.62], [0.12, 0.62, 0.45], [0.99, 0.88, 0.14]])
#: How much a square not checked in full is washed out towards white.
NOT_CHECKED_WASH = 0.45
#: Squares fill this fraction of the grid step (a gap shows the grid).
FILL = 0.92
#: Drawn this far above the searched floor, mm (above a floor face).
LIFT_MM = 2.0


def score_color(fraction):
    """RGB (..., 3) of score fractions (...) in [0, 1]: blue, green, yellow."""
    f = np.clip(np.asarray(fraction, dtype=float), 0.0, 1.0) * (len(_SCORE_STOPS) - 1)
    low = np.minimum(f.astype(int), len(_SCORE_STOPS) - 2)
    t = (f - low)[..., None]
    return (1.0 - t) * _SCORE_STOPS[low] + t * _SCORE_STOPS[low + 1]


def square_colors(heat):
    """Colours of the squares.

    Parameters
    ----------
    heat : robots.placement.placement_search.HeatMap

    Returns
    -------
    ndarray, shape (ny, nx, 3)
        RGB; NaN for positions outside the searched face.
    """
    score = heat.score
    finite = np.isfinite(score)
    lo, hi = (np.min(score[finite]), np.max(score[finite])) if finite.any() else (0.0, 1.0)
    span = hi - lo if hi > lo else 1.0
    colors = score_color(np.where(finite, (score - lo) / span, 1.0))
    colors[heat.state == ps.NOT_CHECKED] = (
        (1.0 - NOT_CHECKED_WASH) * colors[heat.state == ps.NOT_CHECKED] + NOT_CHECKED_WASH)
    colors[heat.state == ps.FAILS_CHECK] = FAIL_CHECK_COLOR
    colors[heat.state == ps.FAILS_SCREEN] = FAIL_SCREEN_COLOR
    colors[heat.state < 0] = np.nan
    return colors


def _half_steps(values):
    """Half the grid step around each grid line (the squares' half widths), shape (n,)."""
    if len(values) < 2:
        return np.full(len(values), 50.0)
    gaps = np.diff(values)
    return 0.5 * np.minimum(np.r_[gaps[0], gaps], np.r_[gaps, gaps[-1]])


class HeatMapView:
    """The heat map of one search in a 3D view.

    Parameters
    ----------
    view : Gui.View3DInventor
    heat : robots.placement.placement_search.HeatMap

    Attributes
    ----------
    root : coin.SoSeparator
    colors : ndarray, shape (K, 3)
        The colour of each square drawn, in the order of the face set.
    """

    def __init__(self, view, heat):
        self.scene = view.getSceneGraph()
        self.root = coin.SoSeparator()
        self.root.setName("CadRobotPlacementHeatMap")
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        colors = square_colors(heat)
        hx, hy = FILL * _half_steps(heat.x_mm), FILL * _half_steps(heat.y_mm)
        corners, drawn = [], []
        z = heat.z_mm + LIFT_MM
        for iy, y in enumerate(heat.y_mm):
            for ix, x in enumerate(heat.x_mm):
                if np.isnan(colors[iy, ix]).any():
                    continue
                corners += [(x - hx[ix], y - hy[iy], z), (x + hx[ix], y - hy[iy], z),
                            (x + hx[ix], y + hy[iy], z), (x - hx[ix], y + hy[iy], z)]
                drawn.append(colors[iy, ix])
        self.colors = np.array(drawn).reshape(-1, 3)
        material = coin.SoMaterial()
        material.diffuseColor.setValues(0, len(drawn), [tuple(float(v) for v in c) for c in drawn])
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_FACE
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(corners), [tuple(float(v) for v in p) for p in corners])
        faces = coin.SoFaceSet()
        faces.numVertices.setValues(0, len(drawn), [4] * len(drawn))
        for node in (pick, light, material, binding, coords, faces):
            self.root.addChild(node)
        self.scene.addChild(self.root)

    def remove(self):
        """Take the heat map out of the view (safe to call twice, or after the view closed)."""
        if self.scene is not None:
            remove_from_scene(self.scene, self.root)
        self.scene = None
