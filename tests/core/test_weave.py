"""The woven path measured against the weave data (issue 22, test 5.3).

core/weave.woven_offsets is sampled at 1 kHz for each pattern, with and
without dwells, square to the torch and turned 30 degrees; the peak-to-peak
amplitude across the seam, the period, the dwell at each vertex and the
height of the raised legs are measured from the samples and compared with the
weave data within 1 %. The ramps bring the weave to the seam at both ends of a
weld; the TCP speed bound holds on the sampled woven path of 200 random
weaves; a weave given by its length per cycle is the one of the equivalent
frequency.
"""

import numpy as np
import pytest

from CadRobotWB.core import weave as wv
from CadRobotWB.core.welding import Weave

RATE_HZ = 1000.0
DT_S = 1.0 / RATE_HZ
TRAVEL_MM_S = 7.5
#: Dwells (s) long enough that one 1 ms sample is well under 1 % of each.
DWELLS = {"dwell_left_s": 0.2, "dwell_center_s": 0.3, "dwell_right_s": 0.25}


def _axes(angle_deg):
    """The weave's lateral axis and its raised axis (back along the tool axis) in the
    weave frame, turned by hand: a rotation about X taking Y toward Z."""
    c, s = np.cos(np.radians(angle_deg)), np.sin(np.radians(angle_deg))
    lateral = np.array([0.0, c, s])
    tool = np.array([0.0, -s, c])
    return lateral, -tool


def _sample(weave, cycles=4, lead_cycles=1):
    """Times (s) and offsets (mm) over `cycles` whole cycles of the steady part of a weld
    of ``cycles + 2 * lead_cycles`` cycles (the ramps, half a cycle, stay outside)."""
    cycle = weave.cycle_time_s(TRAVEL_MM_S)
    duration = (cycles + 2 * lead_cycles) * cycle
    k = np.arange(int(round(cycles * cycle * RATE_HZ)))
    t = lead_cycles * cycle + (k + 0.5) * DT_S       # half a sample off the knots
    return t, wv.woven_offsets(t, duration, weave, TRAVEL_MM_S), cycles


def _hold_time_s(offsets, point, cycles):
    """Time per cycle the offsets stay at `point` (within 1 nm)."""
    still = np.linalg.norm(offsets - point, axis=1) < 1e-6
    return still.sum() * DT_S / cycles


def _vertices_by_hand(pattern, a, h, lateral, raised):
    """Where the weave holds each dwell (turned), by the patterns' definition: zigzag
    C-L-C-R, l with its ends raised, triangle C-R-A-L with the apex A raised."""
    ends_up = h if pattern == "l" else 0.0
    left = -a * lateral + ends_up * raised
    right = a * lateral + ends_up * raised
    apex = h * raised
    return left, right, apex


CASES = [(p, d, angle) for p in ("zigzag", "triangle", "l") for d in (False, True)
         for angle in (0.0, 30.0)] + [("circle", False, 0.0), ("circle", False, 30.0)]


@pytest.mark.parametrize("pattern, dwells, angle", CASES,
                         ids=[f"{p}-{'dwells' if d else 'plain'}-{a:g}deg" for p, d, a in CASES])
def test_the_sampled_weave_has_the_amplitude_period_and_dwells_of_its_data(pattern, dwells, angle):
    weave = Weave(pattern, width_mm=4.0, frequency_hz=1.0 if dwells else 2.0, angle_deg=angle,
                  height_mm=1.5, **(DWELLS if dwells else {})).validated()
    t, offsets, cycles = _sample(weave)
    lateral, raised = _axes(angle)
    across = offsets @ lateral

    # peak to peak across the seam: the full width; the period, from one rise a cycle
    measured = wv.measure(t, across)
    assert across.max() - across.min() == pytest.approx(weave.width_mm, rel=0.01)
    assert measured.width_mm == pytest.approx(weave.width_mm, rel=0.01)
    assert measured.cycles == cycles
    assert measured.period_s == pytest.approx(1.0 / weave.frequency_hz, rel=0.01)
    # the weave stays in its plane: nothing along the travel but the circle's
    if pattern != "circle":
        assert np.abs(offsets[:, 0]).max() < 1e-9
        assert np.abs(offsets @ np.cross(lateral, raised)).max() < 1e-9
    else:
        assert np.ptp(offsets[:, 0]) == pytest.approx(weave.width_mm, rel=0.01)
        assert np.abs(offsets @ raised).max() < 1e-9
    # the ends and the apex where the turned pattern puts them, held for their dwells
    left, right, apex = _vertices_by_hand(pattern, 2.0, 1.5, lateral, raised)
    if pattern in ("triangle", "l"):
        assert (offsets @ raised).max() == pytest.approx(1.5, rel=0.01)
    if dwells:
        assert _hold_time_s(offsets, left, cycles) == pytest.approx(0.2, rel=0.01)
        assert _hold_time_s(offsets, right, cycles) == pytest.approx(0.25, rel=0.01)
        centre = apex if pattern == "triangle" else np.zeros(3)
        assert _hold_time_s(offsets, centre, cycles) == pytest.approx(0.3, rel=0.01)
    elif pattern != "circle":
        nearest = np.linalg.norm(offsets - right, axis=1).min()
        assert nearest < 0.01 * weave.width_mm     # the right end is reached, not cut short


def test_the_angle_turns_the_weave_plane_from_the_lateral_toward_the_tool_axis():
    square = Weave("zigzag", width_mm=4.0, frequency_hz=2.0, dwell_right_s=0.1).validated()
    turned = Weave("zigzag", width_mm=4.0, frequency_hz=2.0, dwell_right_s=0.1,
                   angle_deg=30.0).validated()
    _, flat, _ = _sample(square)
    _, tilted, _ = _sample(turned)
    # the right end: (0, 2, 0) square to the torch; turned 30 deg: (0, 2 cos 30, 2 sin 30)
    assert flat[np.argmax(flat[:, 1])] == pytest.approx([0.0, 2.0, 0.0], abs=1e-9)
    assert tilted[np.argmax(tilted[:, 1])] == pytest.approx([0.0, np.sqrt(3.0), 1.0], abs=1e-9)


@pytest.mark.parametrize("pattern", ["zigzag", "triangle", "l", "circle"])
def test_the_ramps_bring_the_weave_to_the_seam_at_both_ends(pattern):
    weave = Weave(pattern, width_mm=5.0, frequency_hz=2.0, angle_deg=20.0).validated()
    for duration in (3.0, 0.3):          # six cycles, and a weld shorter than one cycle
        t = np.linspace(0.0, duration, int(duration * RATE_HZ) + 1)
        offsets = wv.woven_offsets(t, duration, weave, TRAVEL_MM_S)
        size = np.linalg.norm(offsets, axis=1)
        assert size[0] == 0.0 and size[-1] == 0.0
        ramp = min(0.25, duration / 2)     # half a cycle, at most half the weld
        largest = np.linalg.norm(wv.weave_offsets(t, weave, TRAVEL_MM_S), axis=1).max()
        # within the ramps the weave grows and shrinks no faster than linearly
        from_end = np.minimum(t, duration - t)
        assert np.all(size <= largest * np.clip(from_end / ramp, 0, 1) + 1e-9)
        # ... and reaches its full width in the middle, even on the short weld
        middle = np.array([duration / 2])
        assert wv.woven_offsets(middle, duration, weave, TRAVEL_MM_S) == \
            pytest.approx(wv.weave_offsets(middle, weave, TRAVEL_MM_S), abs=1e-12)
    steady = t[(t > 0.25) & (t < 2.75)]
    assert np.allclose(wv.woven_offsets(steady, 3.0, weave, TRAVEL_MM_S),
                       wv.weave_offsets(steady, weave, TRAVEL_MM_S))


def test_a_weave_by_length_is_the_weave_of_the_equivalent_frequency():
    t = np.arange(0.0, 2.0, DT_S)
    for pattern in ("zigzag", "triangle", "l", "circle"):
        dwells = {} if pattern == "circle" else {"dwell_left_s": 0.05, "dwell_right_s": 0.1}
        by_length = Weave(pattern, length_mm=3.75, **dwells).validated()     # 7.5 mm/s: 0.5 s
        by_frequency = Weave(pattern, frequency_hz=2.0, **dwells).validated()
        assert np.allclose(wv.woven_offsets(t, 2.0, by_length, TRAVEL_MM_S),
                           wv.woven_offsets(t, 2.0, by_frequency, TRAVEL_MM_S), atol=1e-12)


def test_the_peak_speed_of_a_zigzag_is_the_travel_and_the_crossing_speed_together():
    """Plan (e.2): |v| = sqrt(v_travel^2 + (2 W / (T - dwells))^2); 4 mm at 2 Hz with 0.1 s at
    each end, 7.5 mm/s: sqrt(7.5^2 + (8 / 0.3)^2) = 27.70 mm/s."""
    weave = Weave("zigzag", width_mm=4.0, frequency_hz=2.0, dwell_left_s=0.1,
                  dwell_right_s=0.1).validated()
    t, offsets, _ = _sample(weave)
    path = offsets + np.outer(t, [TRAVEL_MM_S, 0.0, 0.0])
    measured = np.linalg.norm(np.diff(path, axis=0), axis=1).max() / DT_S
    assert measured == pytest.approx(np.hypot(7.5, 8.0 / 0.3), rel=0.01)
    assert wv.weave_speed_mm_s(weave, TRAVEL_MM_S) == pytest.approx(8.0 / 0.3)


def _random_weave(rng):
    pattern = rng.choice(["zigzag", "triangle", "l", "circle"])
    travel = rng.uniform(2.0, 20.0)
    by_length = rng.random() < 0.5
    size = {"length_mm": rng.uniform(1.0, 10.0)} if by_length else \
        {"frequency_hz": rng.uniform(0.5, 5.0)}
    cycle = size["length_mm"] / travel if by_length else 1.0 / size["frequency_hz"]
    dwells = {}
    if pattern != "circle":
        shares = rng.dirichlet([1.0, 1.0, 1.0]) * rng.uniform(0.0, 0.8) * min(cycle, 2.0)
        dwells = dict(zip(("dwell_left_s", "dwell_center_s", "dwell_right_s"), shares))
    weave = Weave(str(pattern), width_mm=rng.uniform(0.5, 12.0), angle_deg=rng.uniform(-90, 90),
                  height_mm=None if rng.random() < 0.3 else rng.uniform(0.0, 8.0),
                  **size, **dwells).validated()
    return weave, travel


def test_the_speed_bound_holds_on_the_sampled_woven_path_of_200_random_weaves():
    rng = np.random.default_rng(22)
    tightest = np.inf
    for _ in range(200):
        weave, travel = _random_weave(rng)
        duration = 2.5 * weave.cycle_time_s(travel)
        t = np.arange(0.0, duration, DT_S)
        path = wv.woven_offsets(t, duration, weave, travel) + np.outer(t, [travel, 0.0, 0.0])
        measured = np.linalg.norm(np.diff(path, axis=0), axis=1).max() / DT_S
        bound = wv.peak_tcp_speed_mm_s(weave, travel)
        assert measured <= bound * (1 + 1e-9), (weave, travel, measured, bound)
        tightest = min(tightest, bound / measured)
    assert tightest < 1.2            # a bound, not a wild overestimate


def test_measure_finds_width_and_period_of_a_sampled_sine_by_hand():
    """3 mm peak to peak at 2.5 Hz around a 0.4 mm offset: width 3, period 0.4 s, 5 rises in
    2 s sampled at 1 kHz; a signal that never rises has no period."""
    t = np.arange(0.0, 2.0, DT_S)
    measured = wv.measure(t, 0.4 + 1.5 * np.sin(2 * np.pi * 2.5 * t))
    assert measured.width_mm == pytest.approx(3.0, rel=1e-4)
    assert measured.period_s == pytest.approx(0.4, rel=1e-4) and measured.cycles == 5
    assert np.isnan(wv.measure(t, -t).period_s)
