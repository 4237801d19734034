"""The world as built: how the real cell differs from the CAD (paper 4, 4.3)."""

from dataclasses import dataclass, field
from typing import List, Tuple

import numpy as np


@dataclass
class Reality:
    """Deviations of the real cell from the drawing.

    Attributes
    ----------
    T_u_dev : ndarray, shape (4, 4)
        Rigid displacement of the real workpiece in {U}:
        ``p_real = T_u_dev @ p_cad`` (mm). Identity = placed as drawn.
    bend_mm : float
        Non-rigid bend of the workpiece along the path: real points move by
        ``bend_mm * sin(pi * s / L)`` along ``bend_direction`` (s = distance
        along the path, L its length): 0 at both ends, largest in the middle.
    bend_direction : ndarray, shape (3,)
        Unit direction of the bend in {U}.
    roughness_mm : float
        RMS height of the surface roughness (force following), mm.
    roughness_wavelength_mm : float
        Typical distance between roughness peaks, mm.
    laser_noise_mm : float
        RMS noise of each laser profile point, mm.
    force_noise_n : float
        RMS noise of each force component, N.
    arc_current_noise_a : float
        RMS noise of each sample of the welding current (through-arc
        tracking), A (5 A: an assumption, plan issue 22 d.1 [unverified]).
    foreign_objects : list of (str, trimesh.Trimesh)
        Objects in the real cell that the drawing does not have, in {U}.
    seed : int
        Seed of every random number used, so a run can be repeated.
    """

    T_u_dev: np.ndarray = field(default_factory=lambda: np.eye(4))
    bend_mm: float = 0.0
    bend_direction: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    roughness_mm: float = 0.0
    roughness_wavelength_mm: float = 2.0
    laser_noise_mm: float = 0.02
    force_noise_n: float = 0.5
    foreign_objects: List[Tuple[str, object]] = field(default_factory=list)
    seed: int = 0
    arc_current_noise_a: float = 5.0

    def rng(self):
        """A numpy random Generator seeded with :attr:`seed`."""
        return np.random.default_rng(self.seed)

    def rigid_points(self, points_mm):
        """Apply the rigid deviation to CAD points (N, 3) -> real points (N, 3), mm."""
        points = np.asarray(points_mm, dtype=float)
        return points @ self.T_u_dev[:3, :3].T + self.T_u_dev[:3, 3]
