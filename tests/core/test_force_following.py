"""Profile following under force control (sensors/force_following.py), paper 4.2 and 4.3.

The paper's case: a ball tool runs along a curved profile (here the top of a
cylinder, R = 150 mm, an 80-degree arc drawn as one circular move at
10 mm/s) while the real part sits 3 mm off its CAD pose.
"""

import json

import numpy as np
import pytest
import trimesh

from CadRobotWB.core import program as ir
from CadRobotWB.core.trajectory import tcp_trajectory
from CadRobotWB.errors import InputError
from CadRobotWB.sensors.force_following import simulate_force_following
from CadRobotWB.sensors.reality import Reality

R = 150.0                    # cylinder radius, mm; axis along Y through (0, 0, -R)
HALF_ARC_DEG = 40.0
SPEED = 10.0                 # mm/s
DT = 0.005
F_SET = 20.0


# ----------------------------------------------------------------- scenes

def cylinder_patch(step_mm=2.0, half_angle_deg=60.0, half_width=30.0):
    """The curved profile as a triangle sheet: the cylinder's top, grid ~step_mm."""
    n_phi = int(2 * np.radians(half_angle_deg) * R / step_mm) + 1
    phis = np.linspace(-np.radians(half_angle_deg), np.radians(half_angle_deg), n_phi)
    ys = np.linspace(-half_width, half_width, int(2 * half_width / step_mm) + 1)
    P, Y = np.meshgrid(phis, ys, indexing="ij")
    vertices = np.stack([R * np.sin(P), Y, R * np.cos(P) - R], axis=-1).reshape(-1, 3)
    n_y = len(ys)
    i, j = np.meshgrid(np.arange(n_phi - 1), np.arange(n_y - 1), indexing="ij")
    a = (i * n_y + j).ravel()
    faces = np.concatenate([np.stack([a, a + n_y, a + 1], 1),
                            np.stack([a + 1, a + n_y, a + n_y + 1], 1)])
    return trimesh.Trimesh(vertices, faces, process=False)


def on_cylinder(phi):
    """TCP on the cylinder at angle phi from the top: tool +Z into the surface, X along travel."""
    T = np.eye(4)
    z = -np.array([np.sin(phi), 0.0, np.cos(phi)])
    x = np.array([np.cos(phi), 0.0, -np.sin(phi)])
    T[:3, 0], T[:3, 1], T[:3, 2] = x, np.cross(z, x), z
    T[:3, 3] = [R * np.sin(phi), 0.0, R * np.cos(phi) - R]
    return T


def program_of(moves):
    frame = ir.WorkFrame("B", T_r_b=np.eye(4), T_u_b=np.eye(4))
    return ir.Program("Profile", "MOTOMAN_HP6", ir.ToolData("ball", np.eye(4)), {"B": frame},
                      [ir.ProgramPath("p", "p", moves)])


def arc_trajectory():
    a = np.radians(HALF_ARC_DEG)
    moves = [ir.Move(ir.JOINT, ir.Target("start", on_cylinder(-a)), 100.0, 0.0, "B"),
             ir.Move(ir.CIRCULAR, ir.Target("end", on_cylinder(a)), SPEED, 0.0, "B",
                     via=ir.Target("top", on_cylinder(0.0)))]
    return tcp_trajectory(program_of(moves), DT, first_move=1)


def tool_down(x):
    T = np.diag([1.0, -1.0, -1.0, 1.0])
    T[0, 3] = x
    return T


def line_trajectory(x0=0.0, x1=200.0):
    moves = [ir.Move(ir.JOINT, ir.Target("a", tool_down(x0)), 100.0, 0.0, "B"),
             ir.Move(ir.LINEAR, ir.Target("b", tool_down(x1)), SPEED, 0.0, "B")]
    return tcp_trajectory(program_of(moves), DT, first_move=1)


def profile_sheet(xs, zs, half_width=40.0):
    """A sheet z(x) through the points (xs, zs), straight across Y."""
    vertices, faces = [], []
    for x, z in zip(xs, zs):
        vertices += [[x, -half_width, z], [x, half_width, z]]
    for k in range(len(xs) - 1):
        a = 2 * k
        faces += [[a, a + 2, a + 1], [a + 1, a + 2, a + 3]]
    return trimesh.Trimesh(vertices, faces)


def flat(z, x0=-50.0, x1=250.0):
    return profile_sheet([x0, x1], [z, z])


def box(lo, hi):
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return trimesh.creation.box(hi - lo, transform=trimesh.transformations.translation_matrix(
        0.5 * (lo + hi)))


def shifted(mesh, dz):
    """The part as built, moved dz along Z of {U}, and its Reality (rough, noisy sensor)."""
    T = np.eye(4)
    T[2, 3] = dz
    real = mesh.copy()
    real.apply_transform(T)
    return real, Reality(T_u_dev=T, roughness_mm=0.02, roughness_wavelength_mm=2.0,
                         force_noise_n=0.5, seed=1)


# ----------------------------------------------------------- paper's case

AWAY, INTO = -3.0, 3.0       # the part 3 mm further from / nearer to the tool than drawn


@pytest.fixture(scope="module")
def paper_runs():
    trajectory, cad = arc_trajectory(), cylinder_patch()
    runs = {}
    for dz in (AWAY, INTO):
        real, reality = shifted(cad, dz)
        for controller in ("none", "pi", "fuzzy_pi"):
            runs[dz, controller] = simulate_force_following(
                trajectory, real, reality, force_set_n=F_SET, controller=controller)
    return runs


def test_open_loop_with_the_part_away_never_touches(paper_runs):
    run = paper_runs[AWAY, "none"]
    assert not run.aborted
    assert run.metrics["first_contact_s"] is None and run.metrics["contact_lost"]
    assert np.all(run.error_mm > 0.5)                       # the ball stays clear all the way


def test_open_loop_with_the_part_into_exceeds_the_force_limit_and_aborts(paper_runs):
    run = paper_runs[INTO, "none"]
    assert run.aborted and "limit" in run.reason
    assert run.metrics["force_limit_exceeded"] and run.metrics["max_force_n"] > 50.0
    assert run.metrics["events"][0]["kind"] == "force_limit"
    # stop point recorded, then a 50 mm retract along the tool axis
    stop = run.stop_index
    np.testing.assert_allclose(run.stop_T_u_t[:3, 3], run.actual_mm[stop])
    z = run.stop_T_u_t[:3, 2]
    np.testing.assert_allclose(run.actual_mm[-1], run.actual_mm[stop] - 50.0 * z, atol=1e-9)
    np.testing.assert_allclose(run.correction_mm[-1], run.correction_mm[stop], atol=1e-9)
    assert abs(run.force_n[-1, 2]) < 3.0                    # lifted off: only noise


@pytest.mark.parametrize("dz", [AWAY, INTO])
@pytest.mark.parametrize("controller", ["pi", "fuzzy_pi"])
def test_closed_loop_holds_the_force_within_ten_percent(paper_runs, dz, controller):
    run = paper_runs[dz, controller]
    m = run.metrics
    assert not run.aborted and m["events"] == []
    assert m["first_contact_s"] is not None and not m["contact_lost"]
    assert m["rms_force_error_pct"] < 10.0
    assert m["settling_time_s"] is not None and m["settling_time_s"] < 1.0
    assert m["overshoot_pct"] < 10.0
    assert not m["force_limit_exceeded"]
    # the correction found the part: about dz * cos(angle) along the normal, plus the preload
    T_top = on_cylinder(0.0)
    top = np.argmin(np.linalg.norm(run.nominal_mm - T_top[:3, 3], axis=1))
    along_z = run.correction_mm[top] @ T_top[:3, 2]
    assert along_z == pytest.approx(-dz + F_SET / 20.0, abs=0.25)


def test_the_report_compares_pi_and_fuzzy_pi(paper_runs):
    for dz in (AWAY, INTO):
        pi, fuzzy = paper_runs[dz, "pi"].metrics, paper_runs[dz, "fuzzy_pi"].metrics
        for key in ("settling_time_s", "overshoot_pct", "rms_force_error_pct", "first_contact_s"):
            assert isinstance(pi[key], float) and isinstance(fuzzy[key], float)
        assert paper_runs[dz, "pi"].controller == "pi"
        assert paper_runs[dz, "fuzzy_pi"].controller == "fuzzy_pi"
        assert json.dumps(paper_runs[dz, "fuzzy_pi"].to_dict(every=20))


def test_the_part_nearer_is_found_sooner_than_the_part_away(paper_runs):
    nearer, away = paper_runs[INTO, "pi"].metrics, paper_runs[AWAY, "pi"].metrics
    assert nearer["first_contact_s"] < away["first_contact_s"]


# -------------------------------------------------- force at steady state

def test_smooth_surface_and_no_noise_give_a_constant_force():
    run = simulate_force_following(line_trajectory(), flat(-3.0), Reality(force_noise_n=0.0),
                                   controller="pi")
    late = run.time_s > 10.0
    np.testing.assert_allclose(run.force_n[late, 2], F_SET, atol=1e-6)
    np.testing.assert_allclose(run.force_n[late][:, [0, 1, 3, 4, 5]], 0.0, atol=1e-9)
    np.testing.assert_allclose(run.error_mm[late], -F_SET / 20.0, atol=1e-7)


def test_roughness_makes_the_force_fluctuate():
    rough = Reality(force_noise_n=0.0, roughness_mm=0.02, roughness_wavelength_mm=2.0, seed=3)
    run = simulate_force_following(line_trajectory(), flat(-3.0), rough, controller="fuzzy_pi")
    late = run.time_s > 10.0
    assert run.force_n[late, 2].std() > 0.1
    assert abs(run.force_n[late, 2].mean() - F_SET) < 0.5


def test_sensor_noise_makes_the_reading_fluctuate_by_its_rms():
    run = simulate_force_following(line_trajectory(), flat(-3.0), Reality(force_noise_n=0.5),
                                   controller="pi")
    late = run.time_s > 10.0
    assert run.force_n[late, 0].std() == pytest.approx(0.5, rel=0.1)   # Fx: the noise alone
    assert run.metrics["rms_force_error_settled_pct"] < 5.0


def test_same_seed_same_run():
    real, reality = shifted(flat(0.0), -3.0)
    first = simulate_force_following(line_trajectory(), real, reality, controller="fuzzy_pi")
    second = simulate_force_following(line_trajectory(), real, reality, controller="fuzzy_pi")
    np.testing.assert_array_equal(first.force_n, second.force_n)
    np.testing.assert_array_equal(first.actual_mm, second.actual_mm)


# ----------------------------------------------------------------- failures

def test_a_foreign_object_on_the_path_aborts_and_retracts():
    clamp = box([100, -20, -3], [120, 20, 10])
    for on_failure in ("abort", "reactive"):                 # no reactive task gets through a solid
        run = simulate_force_following(line_trajectory(), flat(-3.0),
                                       Reality(foreign_objects=[("Clamp", clamp)]),
                                       on_failure=on_failure)
        assert run.aborted and "Clamp" in run.reason
        stop_x = run.actual_mm[run.stop_index, 0]
        assert 100.0 - 5.0 - 0.1 <= stop_x < 100.0              # the ball's front touches x = 100
        assert run.actual_mm[-1, 2] == pytest.approx(run.actual_mm[run.stop_index, 2] + 50.0)
        assert run.metrics["stop_s_mm"] == pytest.approx(stop_x, abs=1e-6)


def test_force_beyond_the_limit_aborts_or_backs_off():
    ramp = profile_sheet([-50.0, 100.0, 110.0, 250.0], [-3.0, -3.0, 2.0, 2.0])   # 5 up over 10
    aborted = simulate_force_following(line_trajectory(), ramp, Reality(), max_force_n=30.0)
    assert aborted.aborted and aborted.reason.startswith("force")
    assert 100.0 <= aborted.metrics["stop_s_mm"] <= 110.0
    reactive = simulate_force_following(line_trajectory(), ramp, Reality(), max_force_n=30.0,
                                        on_failure="reactive")
    assert not reactive.aborted
    events = reactive.metrics["events"]
    assert events and {e["kind"] for e in events} == {"force_limit"}
    assert {e["action"] for e in events} == {"back off"}
    assert reactive.metrics["max_force_n"] < 35.0            # backed off at once
    assert reactive.time_s[-1] == pytest.approx(20.0)        # and finished the path


def test_a_wall_the_back_off_cannot_climb_still_aborts_in_reactive_mode():
    wall = trimesh.util.concatenate([flat(-3.0), box([100, -40, -3], [250, 40, 0])])
    run = simulate_force_following(line_trajectory(), wall, Reality(), on_failure="reactive")
    assert run.aborted and "twice" in run.reason
    assert run.metrics["events"][-1]["kind"] == "force_hard_limit"


def test_a_part_out_of_reach_of_the_correction_aborts():
    run = simulate_force_following(line_trajectory(), flat(-20.0), Reality())
    assert run.aborted and "correction" in run.reason
    assert run.metrics["first_contact_s"] is None
    held = simulate_force_following(line_trajectory(), flat(-20.0), Reality(),
                                    on_failure="reactive")
    assert not held.aborted and held.metrics["events"][0]["action"] == "hold at limit"
    assert np.abs(held.correction_mm).max() <= 15.0 + 1e-9


def test_contact_lost_past_the_end_of_the_part():
    short = flat(-3.0, x1=100.0)
    run = simulate_force_following(line_trajectory(), short, Reality())
    assert run.aborted and run.reason.startswith("contact lost")
    assert 105.0 < run.metrics["stop_s_mm"] < 115.0         # the ball leaves the edge at ~x = 100
    go_on = simulate_force_following(line_trajectory(), short, Reality(), on_failure="reactive")
    assert not go_on.aborted and go_on.metrics["events"][0]["kind"] == "contact_lost"
    assert go_on.metrics["contact_lost_s"] > 5.0


def test_an_unreachable_corrected_target_aborts_or_is_held():
    def past_150(T, _time_s=None):
        return "outside the work area" if T[0, 3] > 150.0 else None

    run = simulate_force_following(line_trajectory(), flat(-3.0), Reality(), reach_check=past_150)
    assert run.aborted and "outside the work area" in run.reason
    assert run.metrics["stop_s_mm"] == pytest.approx(150.0, abs=0.5)
    # holding the last offset cannot help when the program's own pose is out of reach
    react = simulate_force_following(line_trajectory(), flat(-3.0), Reality(), reach_check=past_150,
                                     on_failure="reactive")
    assert react.aborted

    def too_deep(T, _time_s=None):
        return "wrist singularity" if T[2, 3] < -4.5 else None

    held = simulate_force_following(line_trajectory(), flat(-6.0), Reality(), reach_check=too_deep,
                                    on_failure="reactive")
    assert not held.aborted and held.metrics["events"][0]["action"] == "hold offset"
    assert held.actual_mm[:, 2].min() >= -4.5 - 1e-9


def test_bad_options_are_refused():
    trajectory = line_trajectory()
    with pytest.raises(InputError):
        simulate_force_following(trajectory, flat(-3.0), Reality(), rate_hz=500.0)
    with pytest.raises(InputError):
        simulate_force_following(trajectory, flat(-3.0), Reality(), on_failure="ignore")
    with pytest.raises(InputError):
        simulate_force_following(trajectory, flat(-3.0), Reality(), controller="pid")
