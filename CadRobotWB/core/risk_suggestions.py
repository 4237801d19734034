"""Where a path needs a risk area: junctions where the tool turns sharply (pure numpy).

Junction j (1-based) joins segments j and j + 1. A junction whose tool
orientations differ by more than a threshold needs its orientation change
spread over the neighbouring segments (paper section 3.3); neighbouring
sharp junctions merge into one area.
"""

from collections import namedtuple

import numpy as np

from .rotations import rotation_angle_between

# A suggested risk area over segments first..last (1-based, inclusive) of a path;
# jump_deg is the largest orientation change at one junction inside it, degrees.
RiskSuggestion = namedtuple("RiskSuggestion", "path first_segment last_segment jump_deg")


def junction_jumps_deg(R_u_t):
    """Angles between consecutive tool orientations.

    Parameters
    ----------
    R_u_t : sequence of ndarray, shape (3, 3)
        One tool orientation per segment, in travel order.

        Segments that inherit one tool marker's orientation share one array:
        no jump between them (and nothing to compute).

    Returns
    -------
    ndarray, shape (N - 1,)
        Degrees; element j - 1 is the jump at junction j (segments j, j + 1).
    """
    return np.array([0.0 if a is b else np.degrees(rotation_angle_between(a, b))
                     for a, b in zip(R_u_t[:-1], R_u_t[1:])])


def suggest(jumps_deg, threshold_deg, existing=(), path=None):
    """Risk areas for the junctions turning by more than `threshold_deg`.

    Parameters
    ----------
    jumps_deg : array_like, shape (N - 1,)
        Orientation jump at each junction, degrees (see :func:`junction_jumps_deg`).
    threshold_deg : float
        Jumps strictly above this need an area.
    existing : sequence of (int, int)
        Risk areas already on the path, (first, last) 1-based inclusive.
        Junctions touching one of their segments are left out (already
        smoothed, or an area there would overlap it).
    path : object, optional
        Stored in each suggestion's ``path``.

    Returns
    -------
    list of RiskSuggestion
        In path order; runs of neighbouring sharp junctions j..k become one
        area over segments j..k + 1.
    """
    covered = set()
    for first, last in existing:
        covered.update(range(int(first), int(last) + 1))
    out, run = [], []
    for j, jump in enumerate(np.asarray(jumps_deg, dtype=float), start=1):
        sharp = jump > threshold_deg and j not in covered and j + 1 not in covered
        if sharp:
            run.append((j, jump))
        if run and (not sharp or j == len(jumps_deg)):
            out.append(RiskSuggestion(path, run[0][0], run[-1][0] + 1, max(a for _, a in run)))
            run = []
    return out
