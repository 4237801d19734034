"""Lines and arcs fitted to sampled TCP paths (core/path_fitting.py).

The fitted moves are checked against geometry built here: the paths are
made of known lines and arcs, and the fitted moves are sampled densely with
circles computed here (circumcentre by a linear solve) and orientations
slerped with scipy, never with the fitter's own numbers.
"""

import numpy as np
import pytest
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation, Slerp

from CadRobotWB.core.path_fitting import ARC, LINE, fit_path
from CadRobotWB.errors import InputError

STEP_MM = 0.1


def line(p0, p1):
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    n = max(2, int(np.ceil(np.linalg.norm(p1 - p0) / STEP_MM)) + 1)
    return p0 + np.linspace(0, 1, n)[:, None] * (p1 - p0)


def arc(centre, u, v, radius, sweep_deg):
    """Points c + r (cos phi u + sin phi v), phi from 0 to sweep."""
    sweep = np.radians(sweep_deg)
    n = int(np.ceil(radius * sweep / STEP_MM)) + 1
    phi = np.linspace(0, sweep, n)
    return centre + radius * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * v)


def chain(*pieces):
    """Pieces joined end to start (each next piece's first point dropped)."""
    return np.vstack([pieces[0]] + [p[1:] for p in pieces[1:]])


def lines_and_arcs():
    """line 100 mm, tangent 90° arc r 40, line 60 mm, corner, 120° arc r 25 in a plane
    tilted 30° about the travel, corner, line 50 mm: 5 moves (3 lines, 2 arcs)."""
    x, y, z = np.eye(3)
    a = line((0, 0, 0), (100, 0, 0))
    b = arc(np.array([100, 40, 0]), -y, x, 40, 90)            # ends at (140, 40, 0), heading +y
    c = line(b[-1], b[-1] + (0, 60, 0))
    tilt = Rotation.from_euler("y", 30, degrees=True).as_matrix()
    u, v = tilt @ -x, tilt @ z                                  # plane through the travel, tilted
    d = arc(c[-1] - 25 * u, u, v, 25, 120)
    e = line(d[-1], d[-1] + (0, 0, -50))
    return chain(a, b, c, d, e), [LINE, ARC, LINE, ARC, LINE]


def circle_centre(p0, p1, p2):
    """Circumcentre of three points by a linear solve (independent of the fitter)."""
    n = np.cross(p1 - p0, p2 - p0)
    A = np.array([p1 - p0, p2 - p0, n])
    rhs = np.array([(p1 @ p1 - p0 @ p0) / 2, (p2 @ p2 - p0 @ p0) / 2, n @ p0])
    return np.linalg.solve(A, rhs)


def dense_move(p0, p1, via, step_mm=0.005):
    """Points along a fitted move every `step_mm`, and their fractions of its length."""
    if via is None:
        n = max(2, int(np.linalg.norm(p1 - p0) / step_mm) + 2)
        s = np.linspace(0, 1, n)
        return p0 + s[:, None] * (p1 - p0), s
    c = circle_centre(p0, via, p1)
    r = np.linalg.norm(p0 - c)
    u = (p0 - c) / r
    normal = np.cross(via - p0, p1 - via)
    v = np.cross(normal / np.linalg.norm(normal), u)
    sweep = np.mod(np.arctan2((p1 - c) @ v, (p1 - c) @ u), 2 * np.pi)
    n = max(3, int(r * sweep / step_mm) + 2)
    s = np.linspace(0, 1, n)
    return c + r * (np.cos(s * sweep)[:, None] * u + np.sin(s * sweep)[:, None] * v), s


def dense_path(points, quats, moves):
    """The fitted moves sampled densely: positions (M, 3) and orientations (scipy Rotation)."""
    positions, rotations = [], []
    for m in moves:
        p, s = dense_move(points[m.start], points[m.end], m.via_mm)
        ends = Rotation.from_quat(quats[[m.start, m.end]])
        positions.append(p)
        rotations.append(Slerp([0, 1], ends)(s).as_quat())
    return np.vstack(positions), Rotation.from_quat(np.vstack(rotations))


def nearest(from_points, to_points):
    """For each of `from_points`: distance to and index of the nearest of `to_points`."""
    return cKDTree(to_points).query(from_points)


def test_exact_lines_and_arcs_give_exactly_their_moves():
    points, kinds = lines_and_arcs()
    moves = fit_path(points, tolerance_mm=0.01)
    assert [m.kind for m in moves] == kinds
    assert moves[0].start == 0 and moves[-1].end == len(points) - 1
    assert all(m.start == prev.end for prev, m in zip(moves, moves[1:]))
    # the via points lie on the drawn arcs (r 40 about (100, 40, 0); r 25 in the tilted plane)
    assert np.linalg.norm(moves[1].via_mm - (100, 40, 0)) == pytest.approx(40, abs=0.01)
    assert moves[1].via_mm[2] == pytest.approx(0, abs=1e-9)


def test_a_tool_turning_evenly_along_a_line_stays_one_move():
    points = line((0, 0, 0), (200, 0, 0))
    turn = Rotation.from_euler("z", np.linspace(0, 30, len(points))[:, None], degrees=True).as_matrix()
    assert [m.kind for m in fit_path(points, turn, 0.01, 0.05)] == [LINE]
    # turning unevenly (all of it in the second half) the orientation forces a second move
    uneven = Rotation.from_euler("z", np.clip(np.linspace(-30, 30, len(points)), 0, None)[:, None],
                                 degrees=True).as_matrix()
    assert len(fit_path(points, uneven, 0.01, 0.05)) >= 2


@pytest.mark.parametrize("tolerance_mm, angle_deg", [(0.05, 0.1), (0.02, 0.5)])
def test_a_noisy_path_stays_within_tolerance_by_dense_sampling(tolerance_mm, angle_deg):
    points, kinds = lines_and_arcs()
    rng = np.random.default_rng(7)
    # noise up to 0.4 tolerance from the drawn path: a line or arc through two samples
    # then stays within 0.8 tolerance of every sample between them
    noise = rng.normal(0, 0.15 * tolerance_mm, points.shape)
    size = np.linalg.norm(noise, axis=1, keepdims=True)
    noisy = points + noise * np.minimum(1, 0.4 * tolerance_mm / size)
    # the tool turns 40° about x along the path, with 0.02° of orientation noise
    angles = np.linspace(0, 40, len(points)) + rng.normal(0, 0.02, len(points))
    R = Rotation.from_euler("x", angles[:, None], degrees=True)
    moves = fit_path(noisy, R.as_matrix(), tolerance_mm, angle_deg)
    assert len(moves) <= len(kinds) + 2     # from 4,800 samples

    dense, dense_R = dense_path(noisy, R.as_quat(), moves)
    # every sample is within the tolerance of the fitted path (5 µm sampling of the moves)
    distance, index = nearest(noisy, dense)
    assert distance.max() <= tolerance_mm + 0.005
    # and the fitted path never leaves the samples' polyline by more than the tolerance
    back, _ = nearest(dense[::5], noisy)
    assert back.max() <= tolerance_mm + STEP_MM / 2
    # orientation at the nearest point of the path: within the angle tolerance, plus the
    # turn over the position slack (40° over ~480 mm)
    angle = np.degrees((dense_R[index].inv() * R).magnitude())
    assert angle.max() <= angle_deg + 40 / 480 * (tolerance_mm + 0.005) * 2


@pytest.mark.parametrize("angle_deg", [0.1, 0.5])
def test_a_tool_turning_unevenly_is_followed_within_the_angle_tolerance(angle_deg):
    points = line((0, 0, 0), (200, 0, 0))
    # the tool swings 20° one way and back along a straight line
    R = Rotation.from_euler("y", 20 * np.sin(np.linspace(0, 2 * np.pi, len(points)))[:, None],
                           degrees=True)
    moves = fit_path(points, R.as_matrix(), 0.01, angle_deg)
    assert {m.kind for m in moves} == {LINE} and len(moves) > 4
    dense, dense_R = dense_path(points, R.as_quat(), moves)
    _, index = nearest(points, dense)
    angle = np.degrees((dense_R[index].inv() * R).magnitude())
    # 20° sin(2π x / 200 mm) turns at most 20·2π/200 = 0.63°/mm; the nearest dense point is
    # within 2.5 µm of the sample
    assert angle_deg / 2 < angle.max() <= angle_deg + 0.63 * 0.0025


def test_breaks_end_moves_where_asked():
    points = line((0, 0, 0), (100, 0, 0))
    moves = fit_path(points, tolerance_mm=0.01, breaks=[300])
    assert [(m.start, m.end) for m in moves] == [(0, 300), (300, len(points) - 1)]


def test_an_arc_over_180_degrees_takes_two_moves():
    points = arc(np.zeros(3), np.eye(3)[0], np.eye(3)[1], 30, 270)
    moves = fit_path(points, tolerance_mm=0.01)
    assert [m.kind for m in moves] == [ARC, ARC]


@pytest.mark.parametrize("kwargs, word", [
    (dict(tolerance_mm=float("nan")), "tolerance_mm"), (dict(tolerance_mm=0), "tolerance_mm"),
    (dict(angle_tolerance_deg=-1), "angle_tolerance_deg"),
    (dict(angle_tolerance_deg=float("inf")), "angle_tolerance_deg")])
def test_bad_tolerances_are_refused(kwargs, word):
    with pytest.raises(InputError, match=word):
        fit_path(line((0, 0, 0), (10, 0, 0)), **kwargs)


def test_bad_points_are_refused():
    bad = line((0, 0, 0), (10, 0, 0))
    bad[3, 1] = np.nan
    with pytest.raises(InputError, match="finite"):
        fit_path(bad)
    with pytest.raises(InputError, match="at least 2 points"):
        fit_path(np.zeros((1, 3)))
    with pytest.raises(InputError, match="rotation"):
        fit_path(bad[:2] * 0, np.zeros((3, 3, 3)))
