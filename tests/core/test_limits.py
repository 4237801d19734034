"""Bounded work: every count and size a user gives has a stated limit, refused in one line
naming the option (or argument) and the range, before any work; link cycles are found
before anything follows them.

The CLI cases run its argument parsing in this process (no FreeCAD needed for it).
"""

import xml.etree.ElementTree as ElementTree

import numpy as np
import pytest

from CadRobotWB import cli, limits, sweep
from CadRobotWB.core import program as ir
from CadRobotWB.core.generate import RiskAreaSpec, generate
from CadRobotWB.core.geometry import Line
from CadRobotWB.core.trajectory import MAX_TRAJECTORY_SAMPLES, tcp_trajectory
from CadRobotWB.errors import DocumentError, InputError, RiskAreaError
from CadRobotWB.objects import links
from CadRobotWB.robots.placement import placement
from test_generate import DOWN, make_cell, make_path
from test_trajectory import move, program_of

#: (argv after the subcommand's document, words the one line must hold): each was
#: accepted (or an internal error, exit 3) before the limits.
CLI_CASES = [
    (["sweep", "--ranges", "x=0:1", "--runs", "100000"], ["--runs", "<= %d" % limits.MAX_SWEEP_RUNS]),
    (["sweep", "--ranges", "x=0:1", "--workers", "256"], ["--workers", "<= %d" % limits.cores()]),
    (["sweep", "--ranges", "x=0:1", "--workers", str(limits.cores() + 1)], ["--workers"]),
    (["sweep", "--ranges", "x=0:1", "--rate", "5e-324"], ["--rate", ">= 0.1"]),
    (["sweep", "--ranges", "x=0:1", "--seed", "2147483648"], ["--seed", "<= 2147483647"]),
    (["simulate", "--rate", "5e-324"], ["--rate", ">= 0.1"]),
    (["simulate", "--rate", "1e-300"], ["--rate", ">= 0.1"]),
    (["simulate", "--rate", "0.05"], ["--rate", ">= 0.1"]),
    (["simulate", "--seed", "99999999999"], ["--seed", "<= 2147483647"]),
    (["place", "--region", "-1e308,-1e308,1e308,1e308"], ["--region", "<= 1000000"]),
    (["place", "--region", "-1e300,-1,1e300,1"], ["--region", "<= 1000000"]),
    (["place", "--region", "0,0,1,1", "--z", "-1e308,1e308"], ["--z", "<= 1000000"]),
    (["place", "--region", "0,0,1,1", "--turn", "-1e308,1e308"], ["--turn", "<= 360"]),
    (["place", "--region", "0,0,1,1", "--turn", "0,720"], ["--turn", "<= 360"]),
    (["place", "--region", "0,0,1,1", "--count", "2147483647"], ["--count", "<= %d" % limits.MAX_PLACEMENTS]),
    (["place", "--region", "0,0,1,1", "--count", "101"], ["--count", "<= 100"]),
]


@pytest.mark.parametrize("argv, words", CLI_CASES, ids=[" ".join(a) for a, _ in CLI_CASES])
def test_every_count_option_is_refused_past_its_limit_in_one_line(argv, words):
    command, rest = argv[0], argv[1:]
    line = [command, "d.FCStd"] + (["--sensor", "laser"] if command in ("simulate", "sweep") else [])
    with pytest.raises(InputError) as caught:
        cli.build_parser().parse_args(cli._join_negative_values(line + rest))
    message = str(caught.value)
    assert "\n" not in message
    for word in words:
        assert word in message, message


def test_the_limits_are_in_the_help_of_their_options():
    text = cli.build_parser()._subparsers._group_actions[0].choices
    assert "1 to %d" % limits.MAX_SWEEP_RUNS in text["sweep"].format_help()
    assert "the %d cores of this computer (more are refused" % limits.cores() in \
        " ".join(text["sweep"].format_help().split())
    assert "1 to %d" % limits.MAX_PLACEMENTS in " ".join(text["place"].format_help().split())


def test_workers_are_the_cores_there_are_at_most():
    assert limits.cores() >= 1
    assert limits.workers(limits.cores(), "workers") == limits.cores()
    assert limits.workers(None) is None
    with pytest.raises(InputError, match=r"^The sweep's workers must be a whole number >= 1 and <= %d "
                                         r"\(the cores of this computer" % limits.cores()):
        sweep.check_settings(workers=limits.cores() + 1)


@pytest.mark.parametrize("runs", [0, limits.MAX_SWEEP_RUNS + 1, 10 ** 9, 2.5, "50"])
def test_the_sweep_api_refuses_runs_past_the_limit_before_sampling(runs):
    with pytest.raises(InputError, match="The sweep's runs must be a whole number >= 1 and <= 10000"):
        sweep.sample_deviations({"x": (-1.0, 1.0)}, runs)


@pytest.mark.parametrize("region, kwargs, word", [
    ((-1e308, -1e308, 1e308, 1e308), {"step_mm": 1e307}, "grid step"),
    ((0, 0, 1000, 1000), {"step_mm": 1e-320}, "grid step"),
    ((0, 0, 1000, 1000), {"turn_deg": (-1e308, 1e308), "turn_step_deg": 1e307}, "turn step"),
    ((0, 0, 1000, 1000), {"z_mm": (-1e308, 1e308), "z_step_mm": 1e307}, "height step"),
])
def test_a_grid_too_fine_for_floats_is_refused_not_an_overflow(region, kwargs, word):
    with pytest.raises(InputError, match="a %s of .* more than the 250000 bases" % word):
        placement.make_space(region, np.eye(4), **kwargs)


def test_a_risk_area_step_too_small_for_floats_is_refused_naming_the_area():
    path = make_path([Line((0, 0, 0), (10, 0, 0))], [DOWN],
                     risk_areas=[RiskAreaSpec("Risk", "Corner", 1, 1, step_mm=1e-320)])
    with pytest.raises(RiskAreaError, match=r"Risk area 'Corner' on path 'Weld seam' would need inf "
                                            r"points .* \(at most 100000\)"):
        generate(make_cell([path]))


@pytest.mark.parametrize("speed", [1e-6, 5e-324])
def test_sampling_a_crawling_move_is_refused_before_it_fills_the_memory(speed):
    program = program_of([move(ir.JOINT, (0, 0, 0), 100), move(ir.LINEAR, (0, 100, 0), speed)])
    with pytest.raises(InputError, match=r"Program 'P': .* more than %d: raise the path's Speed"
                                         % MAX_TRAJECTORY_SAMPLES):
        tcp_trajectory(program, 0.01)


@pytest.mark.parametrize("graph, cycle", [
    ({"A": ["B"], "B": ["A"]}, ["A", "B", "A"]),
    ({"A": ["A"]}, ["A", "A"]),
    ({"S": ["A"], "A": ["B"], "B": ["C"], "C": ["A"]}, ["A", "B", "C", "A"]),
    ({"A": ["B", "C"], "B": ["C"], "C": []}, None),
    ({"A": ["B"]}, None),
    ({}, None),
])
def test_find_cycle(graph, cycle):
    assert links.find_cycle(graph) == cycle


def _document_xml(objects):
    """A Document.xml with `objects` = {name: (label, {property: [linked names]})}."""
    parts = ["<Document><ObjectData>"]
    for name, (label, props) in objects.items():
        parts.append('<Object name="%s"><Properties><Property name="Label"><String value="%s"/>'
                     '</Property>' % (name, label))
        for prop, targets in props.items():
            values = "".join('<XLink file="" name="%s"/>' % t if prop == "LinkedObject"
                             else '<Link value="%s"/>' % t for t in targets)
            parts.append('<Property name="%s">%s</Property>' % (prop, values))
        parts.append("</Properties></Object>")
    return ElementTree.fromstring("".join(parts) + "</ObjectData></Document>")


def test_a_link_cycle_in_a_saved_document_is_refused_naming_its_objects():
    root = _document_xml({"LinkA": ("Left", {"LinkedObject": ["LinkB"]}),
                          "LinkB": ("LinkB", {"LinkedObject": ["Grp"]}),
                          "Grp": ("Group", {"Group": ["LinkA"]})})
    with pytest.raises(DocumentError) as caught:
        links.refuse_cycle_in_document_xml(root, "cell.FCStd")
    assert str(caught.value) == (
        "Document 'cell.FCStd': the links of 'Left' (LinkA) -> 'LinkB' -> 'Group' (Grp) -> 'Left' "
        "(LinkA) form a cycle, which FreeCAD cannot follow. Open it in FreeCAD and point one of "
        "these links at another object.")


def test_back_links_freecad_does_not_follow_are_no_cycle():
    """A PartDesign body and its features link to each other (BaseFeature, a sketch's
    support): valid documents, never refused."""
    root = _document_xml({"Body": ("Body", {"Group": ["Pad", "Sketch"], "Tip": ["Pad"]}),
                          "Pad": ("Pad", {"BaseFeature": ["Body"], "Profile": ["Sketch"]}),
                          "Sketch": ("Sketch", {"Support": ["Body"]})})
    links.refuse_cycle_in_document_xml(root, "part.FCStd")
