"""Pure math behind the GUI picking commands: face-normal bisectors, frames from a
face and an edge, risk-area suggestions, and a taught work frame in generate().

Expected values are worked out by hand in the comments.
"""

import math
import time

import numpy as np
import pytest

from CadRobotWB.core.generate import CellSpec, FrameSpec, PathSpec, generate
from CadRobotWB.core.geometry import Line
from CadRobotWB.core.program import ToolData
from CadRobotWB.core.risk_suggestions import RiskSuggestion, junction_jumps_deg, suggest
from CadRobotWB.core.surface_normals import bisector, frame_from_normal_and_edge
from CadRobotWB.errors import FrameError, InputError

S = 1.0 / math.sqrt(2.0)


def rz(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


# --- bisector ----------------------------------------------------------------------

def test_bisector_of_a_box_edge_is_halfway_between_its_faces():
    # -Y face and +Z face of a box edge along X: (0, -1, 1)/sqrt(2).
    assert np.allclose(bisector([[0, -1, 0], [0, 0, 1]]), [0, -S, S], atol=1e-15)


def test_bisector_counts_coplanar_faces_once():
    # Two plates either side of a gap (both tops +Z) and a fillet's vertical face +X:
    # the sum of distinct normals (0,0,1)+(1,0,0) -> 45 degrees, not biased to Z.
    assert np.allclose(bisector([[0, 0, 1], [0, 0, 2], [1, 0, 0]]), [S, 0, S], atol=1e-15)
    assert np.allclose(bisector([[0, 0, 3]]), [0, 0, 1])


def test_bisector_of_opposite_faces_is_an_error():
    with pytest.raises(InputError, match="select the face"):
        bisector([[0, 0, 1], [0, 0, -1]])
    with pytest.raises(InputError):
        bisector(np.zeros((0, 3)))


# --- frame from a face normal and an edge ---------------------------------------------

def test_frame_from_normal_and_edge_by_hand():
    # Face normal -Z, edge from (100, 50, 0) to (100, 60, 0): X = +Y, Z = -Z,
    # Y = Z x X = (0,0,-1) x (0,1,0) = (1, 0, 0).
    T = frame_from_normal_and_edge([0, 0, -2], [100, 50, 0], [100, 60, 0])
    assert np.allclose(T[:3, :3], [[0, 1, 0], [1, 0, 0], [0, 0, -1]], atol=1e-15)
    assert np.allclose(T[:3, 3], [100, 50, 0])


@pytest.mark.parametrize("normal, end, message", [
    ([0, 0, 1], [0, 0, 0], "no length"),
    ([0, 0, 0], [1, 0, 0], "no normal"),
    ([0, 0, 1], [1, 0, 1], "not parallel"),
])
def test_frame_from_normal_and_edge_rejects_bad_input(normal, end, message):
    with pytest.raises(FrameError, match=message):
        frame_from_normal_and_edge(normal, [0, 0, 0], end)


# --- risk suggestions --------------------------------------------------------------

def test_junction_jumps_are_the_angles_between_consecutive_orientations():
    R = [rz(0), rz(0), rz(90), rz(90), rz(100)]
    assert np.allclose(junction_jumps_deg(R), [0, 90, 0, 10], atol=1e-9)


def test_jumps_of_inherited_orientations():
    # One marker on segment 1, one on segment 4 (turned 50 deg about Z): segments 2-3 and 5-6
    # share their marker's array.
    first, fourth = rz(0), rz(50)
    jumps = junction_jumps_deg([first, first, first, fourth, fourth, fourth])
    assert np.allclose(jumps, [0, 0, 50, 0, 0], atol=1e-9)
    long_path = [first] * 20000 + [fourth] * 20000
    began = time.perf_counter()
    jumps = junction_jumps_deg(long_path)
    assert time.perf_counter() - began < 1.0 and np.flatnonzero(jumps).tolist() == [19999]
    assert suggest(jumps, 30.0) == [RiskSuggestion(None, 20000, 20001, pytest.approx(50.0))]


def test_suggest_one_area_per_sharp_junction():
    # Junction j joins segments j and j + 1.
    out = suggest([0, 90, 0, 45], 30.0, path="P")
    assert out == [RiskSuggestion("P", 2, 3, 90.0), RiskSuggestion("P", 4, 5, 45.0)]


def test_suggest_gives_neighbouring_sharp_junctions_one_area_each():
    # Junctions 2 and 3 are sharp: one area per junction (issue 20: each short, round its corner).
    assert suggest([5, 40, 60, 5], 30.0) == [RiskSuggestion(None, 2, 3, 40.0),
                                             RiskSuggestion(None, 3, 4, 60.0)]
    assert suggest([40, 60], 30.0) == [RiskSuggestion(None, 1, 2, 40.0),
                                       RiskSuggestion(None, 2, 3, 60.0)]   # reaching the end


def test_suggest_the_corner_where_a_closed_loop_closes():
    # 4 segments, junctions 1-3 inside; the loop closes from segment 4 to segment 1 (90 deg).
    out = suggest([0, 90, 0], 30.0, closing_jump_deg=90.0)
    assert out == [RiskSuggestion(None, 2, 3, 90.0), RiskSuggestion(None, 4, 1, 90.0)]
    assert suggest([0, 90, 0], 30.0, existing=[(4, 1, 0.0)], closing_jump_deg=90.0) == [
        RiskSuggestion(None, 2, 3, 90.0)]
    # A span area over 2..3 covers junction 2 only: junctions next to it stay open.
    assert suggest([50, 90, 50], 30.0, existing=[(2, 3, 1.0)]) == [
        RiskSuggestion(None, 1, 2, 50.0), RiskSuggestion(None, 3, 4, 50.0)]


def test_suggest_threshold_is_strict():
    assert suggest([30.0, 29.9], 30.0) == []
    assert suggest([30.1], 30.0) == [RiskSuggestion(None, 1, 2, 30.1)]


def test_suggest_leaves_out_junctions_at_existing_areas():
    # Area over 2..3 covers junction 2 and touches junctions 1 and 3 (an area
    # there would overlap it); junction 5 stays.
    assert suggest([50, 90, 50, 0, 70], 30.0, existing=[(2, 3)]) == [RiskSuggestion(None, 5, 6, 70.0)]


# --- a taught frame in generate ---------------------------------------------------------

def _cell(T_r_b):
    down = np.diag([1.0, -1.0, -1.0])
    path = PathSpec(name="P", label="P", segments=[Line([0, 0, 0], [100, 0, 0])], R_u_t=[down],
                    frame="F", approach_mm=0.0, retract_mm=0.0)
    T_u_b = np.eye(4)
    T_u_b[:3, 3] = [10, 20, 0]
    T_u_r = np.eye(4)
    T_u_r[:3, 3] = [-900, 0, -600]
    return CellSpec(name="C", label="C", robot="ABB_IRB2400", T_u_r=T_u_r,
                    tool=ToolData(name="t", T_f_t=np.eye(4)),
                    frames={"F": FrameSpec("F", "Frame", T_u_b, T_r_b=T_r_b)}, paths=[path])


def test_taught_frame_is_the_work_frame_and_targets_stay_as_drawn():
    drawn = generate(_cell(None))
    frame = next(iter(drawn.frames.values()))
    # Drawn: T_r_b = inv(T_u_r) @ T_u_b = translation (910, 20, 600).
    assert np.allclose(frame.T_r_b[:3, 3], [910, 20, 600]) and np.allclose(frame.T_r_b[:3, :3], np.eye(3))
    T_r_b = np.eye(4)
    T_r_b[:3, :3] = rz(90)
    T_r_b[:3, 3] = [885, 7, 602]
    taught = generate(_cell(T_r_b))
    assert np.allclose(next(iter(taught.frames.values())).T_r_b, T_r_b)
    for a, b in zip(drawn.moves(), taught.moves()):
        assert np.allclose(a.target.T_b_t, b.target.T_b_t)
    # First target: (0,0,0) in {U} is (-10, -20, 0) in {B}.
    assert np.allclose(taught.moves()[0].target.T_b_t[:3, 3], [-10, -20, 0])


def test_taught_frame_that_is_not_rigid_is_a_frame_error():
    with pytest.raises(FrameError, match="Frame"):
        generate(_cell(np.diag([2.0, 1.0, 1.0, 1.0])))
