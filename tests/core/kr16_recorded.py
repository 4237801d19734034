"""FreeCAD 0.20.2's KUKA KR 16 flange poses, recorded (see data/freecad_kr16_tcp.csv)."""

import os

import numpy as np

RECORDED_CSV = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data",
                            "freecad_kr16_tcp.csv")


def recorded_kr16_tcp():
    """Axis sets and FreeCAD's Tcp for them.

    Returns
    -------
    q_deg : ndarray, shape (N, 6)
    T : ndarray, shape (N, 4, 4)
        Flange poses in the robot base frame, mm.
    """
    table = np.loadtxt(RECORDED_CSV, delimiter=",", comments="#", skiprows=6)
    T = np.zeros((len(table), 4, 4))
    T[:, :3, :] = table[:, 6:].reshape(-1, 3, 4)
    T[:, 3, 3] = 1.0
    return table[:, :6], T
