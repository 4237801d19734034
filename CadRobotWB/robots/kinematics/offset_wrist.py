"""Every inverse kinematic solution of a 6R arm with an offset wrist, by a 1D search.

The arms: FANUC CRX-10iA/L and M-430iA/2P, the Yaskawa HC10 family, ABB CRB 15000,
and the Yaskawa MPX3500.  Their axes 2 and 3 are parallel, axis 4 is perpendicular
to them and meets axis 5 (at right angles; at 60 degrees on the MPX3500's oblique
wrist), but axes 4, 5 and 6 do not meet in one point (80-162 mm apart), so neither
the OPW nor the UR closed form applies.  Such an arm has up to 16
solutions (M. Abbes, G. Poisson, "Geometric approach for inverse kinematics of the
FANUC CRX collaborative robot", Robotics 13(6) 91, 2024, mdpi.com/2218-6581/13/6/91:
up to 16 for the CRX-10iA, of which FANUC's Roboguide gives 8); a one-dimensional
search finds them, as IK-Geo does for arms with two parallel axes (A. J. Elias,
J. T. Wen, arXiv:2211.05737).

The search, with the arm in :mod:`.poe`'s parameters (``R_0i`` the rotation of link
i, ``h_i`` the axes at zero):

* the search variable is q6.  The target gives ``R_06``, so ``R_05 = R_06 rot(h6, -q6)``
  and the point P45 where axes 4 and 5 meet, which is fixed in link 5:
  ``p45 = p_T - R_06 P6 - R_05 (a6 - c45)``, ``a6`` axis 6's point and ``c45`` P45 at
  zero joint values; axis 5's direction is ``z5 = R_05 h5``;
* axes 2 and 3 are parallel, so every point of link 3 (P45 too) keeps its distance
  along ``z2 = R_01 h2`` from axis 1's point: ``z2(q1) . (p45 - a1) = h2 . (c45 - a1)``.
  That is IK-Geo's subproblem 4: two roots q1 (``SHOULDERS``);
* axis 4 is perpendicular to ``z2`` and at its fixed angle from ``z5``
  (``z4 . z5 = h4 . h5``): two signs (:func:`_axis4`; for perpendicular axes 4 and 5,
  ``z4 = +-(z2 x z5) / |z2 x z5|``), which fixes ``psi = q2 + (h2 . h3) q3``
  (``R_03 = R_01 rot(h2, psi)``) and with it link 3's vector from axis 3 to P45;
* the planar 2R of axes 2 and 3 must then join axis 2 to axis 3: the residual
  :func:`residual` is the (scaled) difference of the squared distance and the upper
  arm's squared length, zero at a solution; q2, q3, q4 and q5 then follow by
  subproblem 1 (:func:`joints`).

Each of the 4 branches (2 shoulders x 2 signs) is sampled at :data:`GRID_SAMPLES` values
of q6 over a full turn; sign changes between neighbours are brackets, refined by regula
falsi (Anderson-Bjoerck) to :data:`Q6_TOL_RAD`.  Two refinements catch what
the grid misses:

* windows (:func:`_windows`): where subproblem 4's vector or ``z2 x z5`` passes close
  to zero, their direction, and with it the residual, turns by half a turn within a
  fraction of a grid step; there the window is sampled uniformly in that direction's
  angle (:data:`WINDOW_STEPS`, :data:`WINDOW_SAMPLES`);
* dips (:func:`_dips`): between samples of one sign near zero, two roots close
  together or a double root are searched by parabolic interpolation alternating with
  golden section;
* edges (:func:`_edges`, oblique wrists only): where a branch stops existing (axis 5
  too close to axis 2 for the angle), the edge is found by bisection and sampled.

Every candidate is then checked with the forward kinematics (:data:`POSITION_TOL_MM`,
:data:`ROTATION_TOL_RAD`) and duplicates removed.  On arms whose second shoulder
mirrors the first (:func:`_mirror_symmetric`: all but the CRB 15000) the kernel
searches one shoulder and takes the other's solutions from its joints (:func:`_mirror_angles`).

Measured (tests/core/test_offset_wrist.py, bench/bench_chain_ik.py): the generating
joint set is among the solutions (1e-6 rad) for all but 2-8 of 20,000 random poses per
cobot (the compiled search alone, three seeds: CRX-10iA/L 5, 2, 3; M-430iA/2P 6, 8, 7;
HC10 and HC10DT 4, 4, 2; HC10DT B10 3, 4, 4; HC10DTP B00 4, 6, 2; CRB 15000 4, 5, 4;
poses next to a wrist singularity; MPX3500: 21, 23, 24), and on 300 poses per arm
every solution the numerical IK finds is found (MPX3500: 4 missed).  The search is not
proven complete: a pair of roots closer than the dips' search resolves can be missed.

Where the search cannot decide (axis 5 parallel to axis 2, P45 on axis 1: then q1 or
q4 is free), what is found is returned and the rest of the rows are NaN.

Where numba is installed, :func:`inverse` runs the same search compiled
(:mod:`.offset_wrist_kernel`: a window's minimum by Brent's method and an edge by
regula falsi, with the same stopping rules); :func:`inverse_numpy` is the fallback and
the reference.  Pure numpy: never imports FreeCAD.
"""

import sys
from dataclasses import dataclass

import numpy as np

from . import chain_geometry, offset_wrist_kernel, poe

KIND = "offset_wrist"
#: Rows of :func:`inverse`: a 6R arm has at most 16 solutions.
MAX_SOLUTIONS = 16

#: Axes this close to parallel / perpendicular (|sin| or |cos|) are; as identify.py.
DIRECTION_TOL = 1e-9
#: Axes this close meet, mm; as identify.py.
DISTANCE_TOL_MM = 1e-6
#: Axes 4, 5 and 6 closer than this to one point are a spherical wrist (the KUKA files
#: that round pi/2 miss it by 2e-4 mm; the offset wrists by 80 mm or more), mm.
SPHERICAL_WRIST_TOL_MM = 1e-3

#: Samples of q6 per branch over a full turn.
GRID_SAMPLES = 64
#: A root is refined until its bracket is this narrow, rad, or its residual this small, mm,
#: in at most REFINE_STEPS steps.
Q6_TOL_RAD = 1e-13
RESIDUAL_TOL_MM = 1e-11
REFINE_STEPS = 100
#: A solution's flange is within this of the target (position, mm; rotation, the
#: largest element of the difference of the rotation matrices).
POSITION_TOL_MM = 1e-6
ROTATION_TOL_RAD = 1e-9
#: Two solutions within this on every joint (modulo a turn) are one, rad.
DEDUP_TOL_RAD = 1e-6
#: The two roots q1 of subproblem 4, and the two signs of axis 4.
SHOULDERS = (1.0, -1.0)
AXIS4_SIGNS = (1.0, -1.0)
#: Steps that search a dip of the residual between three samples (parabolic
#: interpolation and golden section alternating) ...
DIP_STEPS = 30
#: A golden-section step goes this fraction of the larger side from the middle point.
GOLDEN_STEP = (3.0 - 5.0 ** 0.5) / 2.0
#: ... tried where the middle sample is within DIP_SCALE * reach * step^2 of zero
#: (reach: the sum of the arm's lengths, mm; step: the grid's, rad).  Outside the
#: windows the residual's curvature is of the order of the reach (rad^-2); this
#: bound is measured, not proven (unverified: see the tests' counts).
DIP_SCALE = 2.0
#: A vector whose direction the search takes (subproblem 4's, z2 x z5) turns by half
#: a turn within less than this many grid steps: its window gets WINDOW_SAMPLES more
#: samples, uniform in its angle, around the minimum of its norm (found in at most
#: WINDOW_GOLDEN_STEPS golden-section steps; the kernel's Brent steps).
WINDOW_STEPS = 2.0
WINDOW_SAMPLES = 16
WINDOW_GOLDEN_STEPS = 60
#: Bisection steps that find where a branch ends (axes 4 and 5 not perpendicular; at
#: most as many regula falsi steps in the kernel), and the samples between the edge and
#: the grid sample next to it.
EDGE_STEPS = 45
EDGE_SAMPLES = 8


@dataclass(frozen=True)
class OffsetWristConstants:
    """What :func:`inverse` precomputes from the arm's :class:`poe.ChainParameters`.

    Attributes
    ----------
    params : poe.ChainParameters
        The arm (for the final check with :func:`poe.fk`).
    vector : ndarray, shape (offset_wrist_kernel.N_CONSTANTS,)
        Every constant the search uses, in the layout of :mod:`.offset_wrist_kernel`
        (unit vectors, mm).
    """

    params: poe.ChainParameters
    vector: np.ndarray

    def __getitem__(self, name):
        """A constant by its kernel name: ``k["H2"]`` (shape (3,) or scalar)."""
        start, size = offset_wrist_kernel.LAYOUT[name]
        return self.vector[start] if size == 1 else self.vector[start:start + size]


# ------------------------------------------------------------------ recognise

def _unit(v):
    return v / np.linalg.norm(v)


def _perpendicular_part(v, axis):
    return v - (v @ axis) * axis


def _require(condition, why):
    """ValueError(why) unless condition (chain_classes.classify says which class it is not)."""
    if not condition:
        raise ValueError(why)


def recognise(params):
    """The search's constants, or ValueError when the arm is not of the class.

    Parameters
    ----------
    params : poe.ChainParameters

    Returns
    -------
    OffsetWristConstants

    Raises
    ------
    ValueError
        Saying why (chain_classes.classify prefixes the class): axes 2 and 3 not
        parallel; axis 4 not perpendicular to them (a UR arm has it parallel); axes 4
        and 5 parallel or not meeting; axes 4, 5, 6 meeting in one point (a spherical
        wrist: the OPW or spherical-wrist solver); axes 1 and 2 or 5 and 6 parallel.
    """
    H, P = np.asarray(params.H, float), np.asarray(params.P, float)
    h1, h2, h3, h4, h5, h6 = H
    points = chain_geometry.axis_points(params)    # a1 .. a6, mm
    flange = points[5] + P[6]
    _require(np.linalg.norm(np.cross(h2, h3)) < DIRECTION_TOL, "axes 2 and 3 are not parallel")
    _require(np.linalg.norm(np.cross(h1, h2)) > DIRECTION_TOL, "axes 1 and 2 are parallel")
    _require(abs(h4 @ h2) < DIRECTION_TOL,
             "axis 4 is not perpendicular to axes 2 and 3 (a UR arm has it parallel to them)")
    _require(np.linalg.norm(np.cross(h4, h5)) > DIRECTION_TOL, "axes 4 and 5 are parallel")
    _require(np.linalg.norm(np.cross(h5, h6)) > DIRECTION_TOL, "axes 5 and 6 are parallel")
    c45 = chain_geometry.wrist_point(params)       # on axis 4, nearest axis 5
    d45 = np.linalg.norm(_perpendicular_part(c45 - points[4], h5))
    _require(d45 < DISTANCE_TOL_MM, "axes 4 and 5 do not meet (%.6g mm apart)" % d45)
    d6 = np.linalg.norm(np.cross(c45 - points[5], h6))
    _require(d6 > SPHERICAL_WRIST_TOL_MM,
             "axes 4, 5 and 6 meet in one point (a spherical wrist: OPW or spherical_wrist)")
    upper_arm = _perpendicular_part(points[2] - points[1], h2)
    _require(np.linalg.norm(upper_arm) > DISTANCE_TOL_MM, "axes 2 and 3 coincide")
    return OffsetWristConstants(params=params, vector=_constants_vector(
        H, points, flange, c45, upper_arm, np.asarray(params.R_6T, float)))


def _mirror_symmetric(values):
    """True when the branches (shoulder, sign) and (-shoulder, -sign) have the same
    residual at every q6: subproblem 4's roots are q1 and q1 + pi (D = 0, h1 . h2 = 0),
    P1 lies along h1 and link 3's vector to P45 along h4 (``P3_H2 = P3_H24 = 0``); then
    the second shoulder's arm is the first's turned half a turn about axis 1."""
    small = [abs(values[name]) for name in ("D", "P3_H2", "P3_H24")]
    return (max(small) < DISTANCE_TOL_MM and abs(values["H1H2"]) < DIRECTION_TOL
            and np.linalg.norm(np.cross(values["P1"], values["H1"])) < DISTANCE_TOL_MM)


def _mirror_angles(h1, h2, h4, upper_arm, sigma3):
    """c2, c3 (rad) of the other shoulder's solution ``(J1 + pi, c2 - J2, c3 - J3, J4 + pi,
    J5, J6)`` on a mirror-symmetric arm (:func:`_mirror_symmetric`).

    Turned half a turn about axis 1, the arm's plane (across h2, through axis 1) is
    reflected across axis 1: a direction at angle ``t`` from h1 about h2 goes to ``-t``.
    The upper arm (angle ``u + J2``) and link 3's vector to P45 (along h4, angle
    ``w + psi``, ``psi = J2 + sigma3 J3``) so give ``J2' = -2u - J2`` and
    ``psi' = -2w - psi``, i.e. ``c2 = -2u``, ``c3 = 2 sigma3 (u - w)``.  Checked against
    the joints of both shoulders (tests/core/test_offset_wrist.py).
    """
    def angle_from_h1(v):
        return np.arctan2(h2 @ np.cross(h1, v), h1 @ _perpendicular_part(v, h2))

    u, w = angle_from_h1(upper_arm), angle_from_h1(h4)
    return wrap_rad(-2.0 * u), wrap_rad(2.0 * sigma3 * (u - w))


def _constants_vector(H, points, flange, c45, upper_arm, R_6T):
    """Pack the constants in :data:`offset_wrist_kernel.LAYOUT` order."""
    h1, h2, h3, h4, h5, h6 = H
    a1, a3, a6 = points[0], points[2], points[5]
    wrist = a6 - c45                           # P45 -> axis 6's point, fixed in link 5
    to_flange = flange - a6
    P3 = c45 - a3                              # axis 3's point -> P45, fixed in link 3
    h24 = np.cross(h2, h4)
    values = dict(
        H1=h1, H2=h2, H4=h4, H5=h5, H24=h24, A1=a1, P1=points[1] - a1,
        # z2 . x = C + A cos q1 + B sin q1 with A = H2P . x, B = H12 . x, C = h1.h2 h1.x
        H2P=_perpendicular_part(h2, h1), H12=np.cross(h1, h2), H1H2=h1 @ h2,
        D=h2 @ (c45 - a1),
        P3_H2=P3 @ h2, P3_H4=P3 @ h4, P3_H24=P3 @ h24,
        UPPER=upper_arm, UPPER_SQ=upper_arm @ upper_arm,
        INV_TWO_UPPER=0.5 / np.linalg.norm(upper_arm), SIGMA3=np.sign(h2 @ h3),
        # In the flange frame: p45 = p_T - R_0T (B0 + cos q6 B1 - sin q6 B2),
        # z5 = R_0T (Z0 + cos q6 Z1 - sin q6 Z2).
        B0=R_6T.T @ (to_flange + (wrist @ h6) * h6), B1=R_6T.T @ _perpendicular_part(wrist, h6),
        B2=R_6T.T @ np.cross(h6, wrist),
        Z0=R_6T.T @ ((h5 @ h6) * h6), Z1=R_6T.T @ _perpendicular_part(h5, h6),
        Z2=R_6T.T @ np.cross(h6, h5), T6=R_6T.T @ h6, H6P=_perpendicular_part(h6, h5),
        C45=h4 @ h5, H5P=_perpendicular_part(h5, h4),
        # R_01 P1 = P1_ALONG h1 + cos q1 P1_PERP + sin q1 H1_P1 (the kernel's residual).
        P1_ALONG=(points[1] - a1) @ h1, P1_PERP=_perpendicular_part(points[1] - a1, h1),
        H1_P1=np.cross(h1, points[1] - a1),
        REACH=np.linalg.norm(np.diff(np.vstack([points, flange]), axis=0), axis=1).sum())
    values["SYMMETRIC"] = float(_mirror_symmetric(values))
    values["MIRROR_Q2"], values["MIRROR_Q3"] = _mirror_angles(h1, h2, h4, upper_arm,
                                                               values["SIGMA3"])
    mirror = np.array([values["MIRROR_Q2"], values["MIRROR_Q3"]])
    values["MIRROR_CS"] = np.column_stack([np.cos(mirror), np.sin(mirror)]).ravel()
    vector = np.zeros(offset_wrist_kernel.N_CONSTANTS)
    for name, (start, size) in offset_wrist_kernel.LAYOUT.items():
        vector[start:start + size] = values[name]
    return vector


# ------------------------------------------------------------------ the residual

def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _cross(a, b):
    """np.cross for (..., 3) arrays, without its overhead."""
    a, b = np.broadcast_arrays(a, b)
    return np.stack([a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
                     a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]], axis=-1)


def _rotate_back(axis, cos_q, sin_q, v):
    """``rot(axis, -q) v`` for unit `axis` (3,), angles broadcast against v (..., 3)."""
    along = _dot(v, axis)[..., None] * axis
    return along + cos_q[..., None] * (v - along) - sin_q[..., None] * _cross(axis, v)


def _pose_terms(k, T):
    """Per pose: p_T - a1 - R_0T B0 and R_0T times B1, B2, Z0, Z1, Z2, T6 (axis 6).

    Returns
    -------
    tuple of 7 ndarrays, shape (N, 3)
    """
    R, p = T[:, :3, :3], T[:, :3, 3]
    rotated = [R @ k[name] for name in ("B0", "B1", "B2", "Z0", "Z1", "Z2", "T6")]
    return (p - k["A1"] - rotated[0],) + tuple(rotated[1:])


def _wrist_line(terms, q6):
    """p45 - a1 and z5 at q6, arrays (..., 3); `terms` broadcast against q6[..., None]."""
    x0, b1, b2, z0, z1, z2 = terms[:6]
    c, s = np.cos(q6)[..., None], np.sin(q6)[..., None]
    return x0 - c * b1 + s * b2, z0 + c * z1 - s * z2


def _shoulder(k, x, shoulder):
    """cos q1, sin q1 of the root `shoulder` (+-1) of ``z2(q1) . x = D`` (subproblem 4)."""
    a, b = _dot(k["H2P"], x), _dot(k["H12"], x)
    c = k["H1H2"] * _dot(k["H1"], x)
    rho = np.hypot(a, b)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_alpha = (k["D"] - c) / rho
        sin_alpha = shoulder * np.sqrt(1.0 - cos_alpha * cos_alpha)
        cos_phi, sin_phi = a / rho, b / rho
    return cos_phi * cos_alpha - sin_phi * sin_alpha, sin_phi * cos_alpha + cos_phi * sin_alpha


def _axis4(k, n, axis4_sign):
    """Axis 4 in link 1's frame: the unit vector perpendicular to h2 at the fixed angle
    from axis 5 (``U . Z5 = h4 . h5``), on the side `axis4_sign`; ``n = h2 x Z5``.

    With ``e2 = n / |n|``, ``e1 = e2 x h2`` (axis 5 across h2, normalised) and
    ``c = h4 . h5 / |n|``: ``U = c e1 +- sqrt(1 - c^2) e2`` (NaN where |c| > 1: axis 5
    too close to h2 for the angle).  For perpendicular axes 4 and 5, ``U = +-e2``.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        e2 = n / np.linalg.norm(n, axis=-1)[..., None]
        c = k["C45"] / np.linalg.norm(n, axis=-1)
        along = np.sqrt(1.0 - c * c)
    e1 = _cross(e2, k["H2"])
    return c[..., None] * e1 + (axis4_sign * along)[..., None] * e2


def _link1_terms(k, x, z5, shoulder, axis4_sign):
    """q1 and, in link 1's frame, axis 4 (U), axis 5 (Z5) and axis 2 -> axis 3 (W)."""
    cos1, sin1 = _shoulder(k, x, shoulder)
    X = _rotate_back(k["H1"], cos1, sin1, x)
    Z5 = _rotate_back(k["H1"], cos1, sin1, z5)
    U = _axis4(k, _cross(k["H2"], Z5), axis4_sign)
    link3 = (k["P3_H2"] * k["H2"] + k["P3_H4"] * U
             + k["P3_H24"] * _cross(k["H2"], U))
    W = X - k["P1"] - link3
    return np.arctan2(sin1, cos1), U, Z5, W


def residual(k, terms, q6, shoulder, axis4_sign):
    """The search's residual: zero where q6 is a solution of the branch.

    Parameters
    ----------
    k : OffsetWristConstants
    terms : tuple of 6 ndarrays, shape (..., 3)
        :func:`_pose_terms`, broadcast against `q6`.
    q6 : ndarray, any shape
        rad.
    shoulder, axis4_sign : float
        +1 or -1: the branch.

    Returns
    -------
    f : ndarray, shape of q6
        ``(|W_perp|^2 - |upper arm|^2) / (2 |upper arm|)``, mm: to first order the
        distance of axis 3 from where the upper arm puts it.  NaN where the branch
        does not exist (subproblem 4 without a root, axis 5 parallel to axis 2).
    """
    x, z5 = _wrist_line(terms, q6)
    W = _link1_terms(k, x, z5, shoulder, axis4_sign)[3]
    along = _dot(W, k["H2"])
    return (_dot(W, W) - along * along - k["UPPER_SQ"]) * k["INV_TWO_UPPER"]


def joints(k, terms, q6, shoulder, axis4_sign):
    """The joint values of the branch at q6 (meant at a root of :func:`residual`).

    Returns
    -------
    q_rad : ndarray, shape q6.shape + (6,)
        Not wrapped: q6 as given, the others in [-pi, pi].
    """
    h2, h4, h5, h24 = k["H2"], k["H4"], k["H5"], k["H24"]
    x, z5 = _wrist_line(terms, q6)
    q1, U, Z5, W = _link1_terms(k, x, z5, shoulder, axis4_sign)
    W_perp = W - _dot(W, h2)[..., None] * h2
    q2 = np.arctan2(_dot(_cross(k["UPPER"], W_perp), h2), _dot(k["UPPER"], W_perp))
    psi = np.arctan2(_dot(_cross(h4, U), h2), _dot(h4, U))
    q3 = k["SIGMA3"] * (psi - q2)
    h2_U = _cross(h2, U)

    def to_link3(v):
        """rot(h2, -psi) v: U -> h4, h2 x U -> h2 x h4."""
        return (_dot(v, h2)[..., None] * h2 + _dot(v, U)[..., None] * h4
                + _dot(v, h2_U)[..., None] * h24)

    V = to_link3(Z5)                        # rot(h4, q4) h5 = V
    h5p = k["H5P"]                          # h5 across h4
    q4 = np.arctan2(_dot(_cross(h5p, V), h4), _dot(h5p, V))
    cos1, sin1 = np.cos(q1), np.sin(q1)
    Z6 = _rotate_back(k["H1"], cos1, sin1, np.broadcast_to(terms[6], V.shape))
    Y = _rotate_back(h4, np.cos(q4), np.sin(q4), to_link3(Z6))   # rot(h5, q5) h6 = Y
    h6p = k["H6P"]
    q5 = np.arctan2(_dot(_cross(h6p, Y), h5), _dot(h6p, Y))
    return np.stack([q1, q2, q3, q4, q5, q6], axis=-1)


# ------------------------------------------------------------------ the search

BRANCHES = tuple((shoulder, sign) for shoulder in SHOULDERS for sign in AXIS4_SIGNS)


def grid_rad():
    """The q6 samples of every branch: a full turn, the ends half a step from +-pi.

    Returns
    -------
    ndarray, shape (GRID_SAMPLES,)
    """
    step = 2.0 * np.pi / GRID_SAMPLES
    return -np.pi + step * (np.arange(GRID_SAMPLES) + 0.5)


def wrap_rad(q):
    """Angles wrapped into (-pi, pi]."""
    return q - 2.0 * np.pi * np.ceil((q - np.pi) / (2.0 * np.pi))


def _sign_changes(t, f):
    """Brackets [t[:, j], t[:, j + 1]] where f changes sign: (row, lo, hi)."""
    with np.errstate(invalid="ignore"):
        row, j = np.nonzero(f[:, :-1] * f[:, 1:] <= 0.0)
    return row, t[row, j], t[row, j + 1]


def _candidates_of_branch(k, terms, windows, shoulder, sign):
    """q6 candidates of one branch for every pose: (pose index (M,), q6 (M,)).

    `windows` (pose (W,), samples (W, S)): extra samples where an angle of the search
    turns fast (:func:`_windows`).
    """
    n = len(terms[0])
    t = grid_rad()
    f = residual(k, tuple(v[:, None, :] for v in terms), t[None, :], shoulder, sign)
    # The grid closed into a loop, one sample repeated at each end.
    loop_t = np.broadcast_to(np.concatenate([[t[-1] - 2.0 * np.pi], t, [t[0] + 2.0 * np.pi]]),
                             (n, GRID_SAMPLES + 2))
    loop_f = np.concatenate([f[:, -1:], f, f[:, :1]], axis=1)
    window_pose, window_t = windows
    window_f = residual(k, tuple(v[window_pose][:, None, :] for v in terms), window_t,
                        shoulder, sign)
    pose, lo, hi, touch_pose, touch_q6 = [], [], [], [], []
    edges = _edges(k, terms, loop_t[:, 1:], loop_f[:, 1:], shoulder, sign)
    # The loop's first interval repeats its last one: a root found twice is one.
    for rows, samples, values in ((np.arange(n), loop_t, loop_f),
                                  (window_pose, window_t, window_f), edges):
        row, b_lo, b_hi = _sign_changes(samples, values)
        dips = _dips(k, terms, rows, samples, values, shoulder, sign)
        pose += [rows[row], dips[0]]
        lo += [b_lo, dips[1]]
        hi += [b_hi, dips[2]]
        touch_pose += [dips[3]]
        touch_q6 += [dips[4]]
    pose = np.concatenate(pose)
    roots = _refine(k, terms, pose, np.concatenate(lo), np.concatenate(hi), shoulder, sign)
    return np.concatenate([pose] + touch_pose), np.concatenate([roots] + touch_q6)


def _edges(k, terms, t, f, shoulder, sign):
    """Where the branch ends between two grid samples (axis 5 too close to h2 for the
    angle between axes 4 and 5: only where they are not perpendicular), the last q6
    where it exists, found by bisection on ``|z2 x z5|^2 - (h4 . h5)^2``: there both
    signs of axis 4 meet, so a root can lie between the last sample and the edge.

    Returns
    -------
    pose : ndarray, shape (E,)
    t_edge, f_edge : ndarray, shape (E, EDGE_SAMPLES + 1)
        From the edge to the sample that exists (sorted), with the branch's residuals.
    """
    with np.errstate(invalid="ignore"):
        row, j = np.nonzero(np.isnan(f[:, :-1]) != np.isnan(f[:, 1:]))
    inside = np.where(np.isnan(f[row, j]), t[row, j + 1], t[row, j])
    outside = np.where(np.isnan(f[row, j]), t[row, j], t[row, j + 1])

    def exists(q6):
        x, z5 = _wrist_line(tuple(v[row] for v in terms), q6)
        cos1, sin1 = _shoulder(k, x, shoulder)
        n = _cross(k["H2"], _rotate_back(k["H1"], cos1, sin1, z5))
        return _dot(n, n) >= k["C45"] ** 2

    for _ in range(EDGE_STEPS):
        middle = 0.5 * (inside + outside)
        ok = exists(middle)
        inside, outside = np.where(ok, middle, inside), np.where(ok, outside, middle)
    sample_t = np.where(np.isnan(f[row, j]), t[row, j + 1], t[row, j])
    # Near the edge the residual goes like the root of the distance to it: samples
    # spaced as the squares of 0, 1/S, ..., 1 see it as a straight line.
    u = (np.arange(EDGE_SAMPLES + 1) / EDGE_SAMPLES) ** 2
    samples = np.sort(inside[:, None] + (sample_t - inside)[:, None] * u, axis=1)
    values = residual(k, tuple(v[row][:, None, :] for v in terms), samples, shoulder, sign)
    return row, samples, values


def _dips(k, terms, rows, t, f, shoulder, sign):
    """Two roots close together, or a double root, hidden between samples of one sign
    near zero (within DIP_SCALE * reach * step^2).  Searched from two kinds of triples
    of points: a sample nearer zero than its two neighbours, with them; an interval
    between two samples, with its middle (evaluated).  Where the middle has the other
    sign, or the minimum of ``sign(f) f`` searched from the triple
    (:func:`_parabolic_minimum`) goes below zero, the triple gives two brackets;
    where the search stays above zero, its point is a candidate (a touch, kept if the
    FK check passes).

    Parameters
    ----------
    rows : ndarray, shape (M,)
        Pose of each row of t, f.
    t, f : ndarray, shape (M, S)
        Samples (sorted) and residuals.

    Returns
    -------
    dip_pose, dip_lo, dip_hi : ndarray, shape (2D,)
        The brackets.
    touch_pose, touch_q6 : ndarray, shape (L,)
    """
    limit = DIP_SCALE * k["REACH"] * (2.0 * np.pi / GRID_SAMPLES) ** 2
    f_prev, f_mid, f_next = f[:, :-2], f[:, 1:-1], f[:, 2:]
    with np.errstate(invalid="ignore"):
        local = ((f_mid * f_prev > 0.0) & (f_mid * f_next > 0.0) & (np.abs(f_mid) <= limit)
                 & (np.abs(f_mid) <= np.abs(f_prev)) & (np.abs(f_mid) <= np.abs(f_next)))
        interval = (f[:, :-1] * f[:, 1:] > 0.0) & (
            np.minimum(np.abs(f[:, :-1]), np.abs(f[:, 1:])) <= limit)
    row, j = np.nonzero(local)
    triples = [(rows[row], t[row, j], t[row, j + 1], t[row, j + 2], f[row, j], f[row, j + 1],
                f[row, j + 2])]
    row, j = np.nonzero(interval)
    middle = 0.5 * (t[row, j] + t[row, j + 1])
    triples.append((rows[row], t[row, j], middle, t[row, j + 1], f[row, j],
                    _residual_at(k, terms, rows[row], middle, shoulder, sign), f[row, j + 1]))
    pose, left, middle, right, f_left, f_middle, f_right = (
        np.concatenate(column) for column in zip(*triples))
    s = np.sign(f_left)
    f_left, f_middle, f_right = s * f_left, s * f_middle, s * f_right
    searched = (f_middle >= 0.0) & (f_middle <= np.minimum(f_left, f_right))
    low = _parabolic_minimum(
        lambda q6: s[searched] * _residual_at(k, terms, pose[searched], q6, shoulder, sign),
        (left[searched], middle[searched], right[searched]),
        (f_left[searched], f_middle[searched], f_right[searched]))
    middle[searched], f_middle[searched] = low
    split = f_middle < 0.0
    touch = searched & ~split & (f_middle <= POSITION_TOL_MM)   # else FK cannot pass
    dip_pose = np.concatenate([pose[split], pose[split]])
    dip_lo = np.concatenate([left[split], middle[split]])
    dip_hi = np.concatenate([middle[split], right[split]])
    return dip_pose, dip_lo, dip_hi, pose[touch], middle[touch]


def _parabolic_minimum(function, t, f):
    """Parabolic interpolation alternating with golden section (vectorised) from three
    points a < m < b with f(m) <= f(a), f(b) (f >= 0); stops where f goes below zero.
    As the kernel's.

    Returns
    -------
    t_min, f_min : ndarray, shape (M,)
        The best point and its value (< 0 where the dip crosses zero).
    """
    a, m, b = (np.array(v, dtype=float) for v in t)
    fa, fm, fb = (np.array(v, dtype=float) for v in f)
    for step in range(DIP_STEPS):
        active = (fm >= 0.0) & (b - a > Q6_TOL_RAD)
        u = _parabola_step(a, m, b, fa, fm, fb, step % 2 == 1)
        fu = np.where(active, function(u), np.inf)
        better = fu < fm
        left = u < m
        a, fa = (np.where(better & ~left, m, np.where(~better & left, u, a)),
                 np.where(better & ~left, fm, np.where(~better & left, fu, fa)))
        b, fb = (np.where(better & left, m, np.where(~better & ~left & active, u, b)),
                 np.where(better & left, fm, np.where(~better & ~left & active, fu, fb)))
        m, fm = np.where(better, u, m), np.where(better, fu, fm)
    return m, fm


def _parabola_step(a, m, b, fa, fm, fb, golden):
    """The vertex of the parabola through three points, or (on `golden` steps, or where
    the vertex falls outside (a, b) or onto m) a golden-section step into the larger
    side: parabolic steps alone can creep towards the minimum when one end is steep."""
    with np.errstate(invalid="ignore", divide="ignore"):     # inf where a search is done
        p = (m - a) ** 2 * (fm - fb) - (m - b) ** 2 * (fm - fa)
        q = (m - a) * (fm - fb) - (m - b) * (fm - fa)
        u = m - 0.5 * p / q
    fallback = m + GOLDEN_STEP * (np.where(m - a > b - m, a, b) - m)
    ok = (u > a) & (u < b) & (np.abs(u - m) > 1e-3 * (b - a)) & (not golden)
    return np.where(ok, u, fallback)


def _golden_minimum(function, lo, hi, steps):
    """Golden-section minimum of function(t) (vectorised) on [lo, hi] (M,): its argument."""
    golden = (np.sqrt(5.0) - 1.0) / 2.0
    for _ in range(steps):
        a, b = hi - golden * (hi - lo), lo + golden * (hi - lo)
        lower = function(a) < function(b)
        hi, lo = np.where(lower, b, hi), np.where(lower, lo, a)
    return 0.5 * (lo + hi)


def _windows(norm_sq_at, norm_sq):
    """Where a vector the search takes the direction of (its norm squared sampled on the
    grid, `norm_sq` (N, GRID_SAMPLES)) passes close to zero, its direction turns by
    about half a turn within ``w = |v|min / |v'|``, maybe far less than a grid step,
    and so may the residual.  There the minimum t* is found by golden section and the
    window sampled uniformly in the direction's angle: ``t* + w tan(theta)``.

    Parameters
    ----------
    norm_sq_at : callable (pose (M,), t (M,)) -> (M,)
    norm_sq : ndarray, shape (N, GRID_SAMPLES)

    Returns
    -------
    pose : ndarray, shape (W,)
    t : ndarray, shape (W, WINDOW_SAMPLES + 2)
        Sorted, from one grid sample before t* to one after.
    """
    step = 2.0 * np.pi / GRID_SAMPLES
    before, after = np.roll(norm_sq, 1, axis=1), np.roll(norm_sq, -1, axis=1)
    curvature = (before - 2.0 * norm_sq + after) / (2.0 * step * step)     # ~|v'|^2
    with np.errstate(invalid="ignore", divide="ignore"):
        vertex = norm_sq - (before - after) ** 2 / (16.0 * step * step * curvature)
        narrow = ((norm_sq <= before) & (norm_sq < after) & (curvature > 0.0)
                  & (np.maximum(vertex, 0.0) < (WINDOW_STEPS * step) ** 2 * curvature))
    pose, j = np.nonzero(narrow)
    centre = grid_rad()[j]
    t_min = _golden_minimum(lambda t: norm_sq_at(pose, t), centre - step, centre + step,
                            WINDOW_GOLDEN_STEPS)
    width = np.sqrt(np.maximum(norm_sq_at(pose, t_min), 0.0) / curvature[pose, j])
    theta = np.pi * ((np.arange(WINDOW_SAMPLES) + 0.5) / WINDOW_SAMPLES - 0.5)
    inside = np.clip(t_min[:, None] + width[:, None] * np.tan(theta), (centre - step)[:, None],
                     (centre + step)[:, None])
    return pose, np.column_stack([centre - step, inside, centre + step])


def _shoulder_windows(k, terms, shoulder):
    """:func:`_windows` of subproblem 4's vector (both shoulders) and of z2 x z5 (this
    shoulder's), merged."""
    t = grid_rad()
    grid_terms = tuple(v[:, None, :] for v in terms)

    def sp4_sq(x):
        return _dot(k["H2P"], x) ** 2 + _dot(k["H12"], x) ** 2

    def axis4_sq(x, z5):
        cos1, sin1 = _shoulder(k, x, shoulder)
        n = _cross(k["H2"], _rotate_back(k["H1"], cos1, sin1, z5))
        return _dot(n, n)

    def at(function):
        return lambda pose, q6: function(*_wrist_line(tuple(v[pose] for v in terms), q6))

    x, z5 = _wrist_line(grid_terms, t[None, :])
    first = _windows(at(lambda x, z5: sp4_sq(x)), sp4_sq(x))
    second = _windows(at(axis4_sq), axis4_sq(x, z5))
    return np.concatenate([first[0], second[0]]), np.concatenate([first[1], second[1]])


def _residual_at(k, terms, pose, q6, shoulder, sign):
    return residual(k, tuple(v[pose] for v in terms), q6, shoulder, sign)


def _refine(k, terms, pose, lo, hi, shoulder, sign):
    """Roots of the residual in brackets [lo, hi] (M,) where it changes sign: regula falsi
    with the Anderson-Bjoerck scaling of the end that stays (as the kernel), to
    Q6_TOL_RAD or a residual below RESIDUAL_TOL_MM, in at most REFINE_STEPS steps; each
    root the point evaluated nearest zero (on a steep residual the last one can be the
    worse end of the closed bracket)."""
    a, b = lo.copy(), hi.copy()                  # a: the end kept, b: the last point
    fa = _residual_at(k, terms, pose, a, shoulder, sign)
    fb = _residual_at(k, terms, pose, b, shoulder, sign)
    root = np.where(np.abs(fa) < np.abs(fb), a, b)
    f_root = np.minimum(np.abs(fa), np.abs(fb))
    active = (fa != 0.0) & (fb != 0.0)
    for _ in range(REFINE_STEPS):
        i = np.nonzero(active)[0]
        if not len(i):
            break
        with np.errstate(invalid="ignore", divide="ignore"):
            middle = (a[i] * fb[i] - b[i] * fa[i]) / (fb[i] - fa[i])
        inside = (middle > np.minimum(a[i], b[i])) & (middle < np.maximum(a[i], b[i]))
        middle = np.where(inside, middle, 0.5 * (a[i] + b[i]))
        f_middle = _residual_at(k, terms, pose[i], middle, shoulder, sign)
        closer = (np.abs(f_middle) < f_root[i]) | (np.abs(f_middle) < RESIDUAL_TOL_MM)
        root[i] = np.where(closer, middle, root[i])
        f_root[i] = np.where(closer, np.abs(f_middle), f_root[i])
        crossed = f_middle * fb[i] < 0.0
        with np.errstate(invalid="ignore", divide="ignore"):
            m = 1.0 - f_middle / fb[i]
        a[i] = np.where(crossed, b[i], a[i])
        fa[i] = np.where(crossed, fb[i], fa[i] * np.where(m > 0.0, m, 0.5))
        b[i], fb[i] = middle, f_middle
        done = ((np.abs(f_middle) < RESIDUAL_TOL_MM) | np.isnan(f_middle)
                | (np.abs(b[i] - a[i]) < Q6_TOL_RAD))
        active[i[done]] = False
    return root


def _reproduces(params, q, T):
    """True where FK of q (M, 6) is T (M, 4, 4) within the tolerances."""
    T_q = poe.fk(params, q)
    with np.errstate(invalid="ignore"):
        return ((np.abs(T_q[:, :3, 3] - T[:, :3, 3]).max(axis=1) <= POSITION_TOL_MM)
                & (np.abs(T_q[:, :3, :3] - T[:, :3, :3]).max(axis=(1, 2)) <= ROTATION_TOL_RAD))


def _distinct_sorted(n, pose, q):
    """Per pose, the distinct solutions (within DEDUP_TOL_RAD) sorted by joint values.

    Parameters
    ----------
    n : int
        Poses.
    pose : ndarray, shape (M,)
    q : ndarray, shape (M, 6)
        Wrapped joint values, rad.

    Returns
    -------
    ndarray, shape (n, MAX_SOLUTIONS, 6), NaN rows last.
    """
    order = np.lexsort(tuple(q[:, j] for j in range(5, -1, -1)) + (pose,))
    pose, q = pose[order], q[order]
    rank = np.arange(len(pose)) - np.searchsorted(pose, pose)
    width = int(rank.max()) + 1 if len(pose) else 1
    padded = np.full((n, width, 6), np.nan)
    padded[pose, rank] = q
    difference = np.abs(wrap_rad(padded[:, :, None, :] - padded[:, None, :, :])).max(axis=3)
    with np.errstate(invalid="ignore"):
        same = np.tril(difference <= DEDUP_TOL_RAD, k=-1).any(axis=2)
    padded[same] = np.nan
    out = np.full((n, MAX_SOLUTIONS, 6), np.nan)
    for i in range(n) if width > 0 else ():
        kept = padded[i][~np.isnan(padded[i, :, 0])]
        out[i, :min(len(kept), MAX_SOLUTIONS)] = kept[:MAX_SOLUTIONS]
    return out


def inverse_numpy(k, T_0T):
    """:func:`inverse` in numpy: the reference and the fallback without numba."""
    T = np.asarray(T_0T, dtype=float).reshape(-1, 4, 4)
    terms = _pose_terms(k, T)
    poses, solutions = [], []
    windows = {shoulder: _shoulder_windows(k, terms, shoulder) for shoulder in SHOULDERS}
    for shoulder, sign in BRANCHES:
        pose, q6 = _candidates_of_branch(k, terms, windows[shoulder], shoulder, sign)
        q = joints(k, tuple(v[pose] for v in terms), q6, shoulder, sign)
        poses.append(pose)
        solutions.append(wrap_rad(q))
    pose, q = np.concatenate(poses), np.concatenate(solutions)
    good = _reproduces(k.params, q, T[pose])
    return _distinct_sorted(len(T), pose[good], q[good])


def inverse(k, T_0T):
    """Every inverse kinematic solution of an offset-wrist arm.

    Parameters
    ----------
    k : OffsetWristConstants
        :func:`recognise` of the arm.
    T_0T : array_like, shape (N, 4, 4) or (4, 4)
        Flange poses in the base frame of :mod:`.poe`'s parameters, mm.

    Returns
    -------
    q_rad : ndarray, shape (N, MAX_SOLUTIONS, 6)
        The URDF's joint values, rad, each wrapped into (-pi, pi]; per pose the distinct
        solutions sorted by joint values (joint 1 first), then NaN rows.  Each reproduces
        the pose by :func:`poe.fk` within POSITION_TOL_MM and ROTATION_TOL_RAD; joint
        limits are not applied.  All NaN for a pose out of reach.
    """
    T = np.ascontiguousarray(np.asarray(T_0T, dtype=float).reshape(-1, 4, 4))
    if not offset_wrist_kernel.available():
        return inverse_numpy(k, T)
    out = np.empty((len(T), MAX_SOLUTIONS, 6))
    offset_wrist_kernel.inverse_into(k.vector, _SETTINGS, k.params, T, grid_rad(), out)
    return out


def inverse_screened(k, T_0T, screen):
    """:func:`inverse` and offset_wrist_polish's screening of each pose in one compiled pass.

    Parameters
    ----------
    k : OffsetWristConstants
    T_0T : ndarray, shape (N, 4, 4)
        Flange poses, mm.
    screen : ndarray, shape (offset_wrist_kernel.N_SCREEN,)
        offset_wrist_polish.screen_vector of the arm.

    Returns
    -------
    None
        Without the compiled kernel (the caller screens in numpy).
    q_rad : ndarray, shape (N, MAX_SOLUTIONS, 6)
        As :func:`inverse`; all NaN on poses upright to rounding where the closed forms
        hold every solution (not searched).
    upright : ndarray of bool, shape (N,)
        offset_wrist_polish.upright.
    suspects : ndarray of int, shape (S,)
        The poses offset_wrist_polish.suspect flags, neither upright nor beyond reach.
    """
    if not offset_wrist_kernel.available():
        return None
    T = np.ascontiguousarray(T_0T, dtype=float)
    out = np.empty((len(T), MAX_SOLUTIONS, 6))
    flags = np.empty(len(T), dtype=np.int8)
    offset_wrist_kernel.inverse_into(k.vector, _SETTINGS, k.params, T, grid_rad(), out, screen,
                                     flags)
    return (out, flags == offset_wrist_kernel.UPRIGHT,
            np.flatnonzero(flags == offset_wrist_kernel.SUSPECT))


_SETTINGS = offset_wrist_kernel.settings_vector(sys.modules[__name__])
