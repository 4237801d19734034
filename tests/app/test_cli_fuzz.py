"""A generated table of bad command lines and defective documents, run through the CLI.

Every case runs ``cli.main`` in this FreeCADCmd process (the launcher's own
entry, without a process start per case) with stderr captured at the file
descriptor, so a line FreeCAD writes itself counts too.  Every refusal must:

* exit 2 (never 3, the code of a bug of ours),
* write exactly one line on stderr, ``cadrobot: error: ...`` naming what is wrong,
* leave the output folder absent (or an existing file untouched),
* leave the input document byte for byte as it was.

The table: every number option of every subcommand with every kind of bad
value (NaN, infinities, overflow, words, empty, out of range), the other
options' bad values, every defective document of ``bad_documents`` under
``export`` and ``check``, every damaged file under every command that reads
one, and random command lines (fixed seed) mixing valid and bad values.
hypothesis is not installed for FreeCAD's Python, hence the table.
"""

import io
import os
import random

import pytest

import bad_documents
from conftest import sha256
from CadRobotWB import cli

SEED = 13
RANDOM_CASES = 200

#: Values no number option takes (and no option of two numbers).
NOT_NUMBERS = ["nan", "NaN", "inf", "-inf", "1e999", "abc", ""]

#: (command, option) -> bad values beyond NOT_NUMBERS (for number options) or instead of them.
BAD_VALUES = {
    ("simulate", "--rate"): NOT_NUMBERS + ["0", "-5", "1000", "1,2"],
    ("simulate", "--seed"): NOT_NUMBERS + ["-1", "1.5", "99999999999"],
    ("simulate", "--deviation"): ["1,2,3", "nan,0,0,0,0,0", "0,0,0,0,0,inf", "a,b,c,d,e,f", "",
                                  "1e999,0,0,0,0,0", "0,0,0,0,0,0,0"],
    ("simulate", "--sensor"): ["", "sonar"],
    ("simulate", "--controller"): ["", "pid"],
    ("simulate", "--cell"): ["Nope", ""],
    ("simulate", "--path"): ["Nope", ""],
    ("simulate", "--foreign"): ["Nope", ""],
    ("sweep", "--ranges"): ["x=nan:1", "x=1:0", "q=0:1", "x=-1e308:1e308", "", "x=0", "x=:",
                            "rz=-inf:0", ","],
    ("sweep", "--runs"): NOT_NUMBERS + ["0", "-3", "1.5", "1000000"],
    ("sweep", "--rate"): NOT_NUMBERS + ["0", "-1", "101"],
    ("sweep", "--tolerance"): NOT_NUMBERS + ["0", "-1"],
    ("sweep", "--workers"): NOT_NUMBERS + ["0", "-2", "1000", "2.5"],
    ("sweep", "--seed"): NOT_NUMBERS + ["-1"],
    ("sweep", "--scheduler"): ["tcp://127.0.0.1:1", "nowhere", "tcp://host:99999", "", "tcp://:80"],
    ("sweep", "--controller"): ["fuzzy"],
    ("place", "--region"): NOT_NUMBERS + ["1,2,3", "0,0,nan,1", "10,0,0,10", "0,0,0,0", "0,0,1e999,1"],
    ("place", "--z"): NOT_NUMBERS + ["5,1", "nan,1", "1", "1,2,3"],
    ("place", "--turn"): NOT_NUMBERS + ["90,-90", "a,b", "0,inf"],
    ("place", "--step"): NOT_NUMBERS + ["0", "-1"],
    ("place", "--z-step"): NOT_NUMBERS + ["0", "-1"],
    ("place", "--turn-step"): NOT_NUMBERS + ["0", "-30"],
    ("place", "--margin"): NOT_NUMBERS + ["-1", "181"],
    ("place", "--count"): NOT_NUMBERS + ["0", "-1", "2.5"],
    ("place", "--cell"): ["Nope"],
    ("export", "--post"): ["", "brand_x", " abb_rapid"],
    ("export", "--cell"): ["Nope", ""],
    ("export", "--option"): ["nonsense", "=1", ""],
    ("check", "--cell"): ["Nope", ""],
    ("robots", "--j23-factor"): NOT_NUMBERS + ["2", "-2"],
    ("robots", "--import"): ["{missing}", ""],
}

#: The word of the option an error line must hold (default: the option without dashes).
WORDS = {"--deviation": "deviation", "--ranges": "range", "--scheduler": "scheduler",
         "--foreign": "foreign", "--path": "path", "--import": "file", "--option": "key=value",
         "--z": "z"}

#: Valid command lines the bad values are added to ({doc}: the seam cell; {out}: a new folder).
BASE = {
    "export": ["export", "{doc}", "-o", "{out}"],
    "check": ["check", "{doc}"],
    "simulate": ["simulate", "{doc}", "--sensor", "laser", "-o", "{out}"],
    "sweep": ["sweep", "{doc}", "--sensor", "laser", "--ranges", "y=-1:1", "--runs", "2",
              "--workers", "1", "-o", "{out}"],
    "place": ["place", "{doc}", "--region", "-1500,-400,-300,400", "--count", "1"],
    "robots": ["robots"],
}

#: Valid values to mix in the random lines.
GOOD_VALUES = {
    ("simulate", "--rate"): ["5", "20", "100"], ("simulate", "--seed"): ["0", "7"],
    ("simulate", "--deviation"): ["0,5,2,0,0,1", "-1,0,0,0,0,0"],
    ("sweep", "--rate"): ["5"], ("sweep", "--tolerance"): ["0.5"], ("sweep", "--seed"): ["3"],
    ("place", "--step"): ["200"], ("place", "--margin"): ["5"], ("place", "--turn-step"): ["45"],
    ("export", "--post"): ["abb_rapid", "kuka_krl"], ("export", "--option"): ["date=2024-01-01"],
    ("check", "--no-collisions"): [None],
}


def number_option(command, option):
    return BAD_VALUES[(command, option)][: len(NOT_NUMBERS)] == NOT_NUMBERS


def word_of(option):
    return WORDS.get(option, option.lstrip("-"))


def single_cases():
    """(id, argv template, word) for every bad value of every option."""
    cases = []
    for (command, option), values in BAD_VALUES.items():
        for value in values:
            cases.append(("%s %s=%r" % (command, option, value), BASE[command] + [option, value],
                          word_of(option)))
    return cases


def random_cases(count=RANDOM_CASES, seed=SEED):
    """(id, argv template, word) of random lines: 0-2 valid options, then 1-2 bad ones."""
    rng = random.Random(seed)
    commands = sorted(BASE)
    cases = []
    for k in range(count):
        command = rng.choice(commands)
        good = [key for key in GOOD_VALUES if key[0] == command]
        bad = [key for key in BAD_VALUES if key[0] == command]
        argv = list(BASE[command])
        for key in rng.sample(good, min(len(good), rng.randint(0, 2))):
            value = rng.choice(GOOD_VALUES[key])
            argv += [key[1]] if value is None else [key[1], value]
        chosen = rng.sample(bad, min(len(bad), rng.randint(1, 2)))
        for key in chosen:
            argv += [key[1], rng.choice(BAD_VALUES[key])]
        rng.shuffle(chosen)
        cases.append(("random%03d %s" % (k, command), argv, None))
    return cases


@pytest.fixture(scope="module")
def files(seam_file, tmp_path_factory):
    """The seam document, the defective documents and the damaged files, made once."""
    folder = tmp_path_factory.mktemp("fuzz")
    made = {"doc": seam_file, "missing": str(folder / "missing.urdf")}
    for name in bad_documents.DEFECTS:
        made[name] = bad_documents.save_defect(name, folder)
    for kind in bad_documents.DAMAGED_FILES:
        made[kind] = bad_documents.write_damaged_file(kind, folder, seam_file)
    return made


def run_cli(argv, capfd):
    """(exit code, stderr lines, stdout) of cli.main(argv); stderr both Python's and fd 2's."""
    out, err = io.StringIO(), io.StringIO()
    capfd.readouterr()
    code = cli.main(argv, out=out, err=err)
    captured = capfd.readouterr()
    lines = (err.getvalue() + captured.err).splitlines()
    return code, lines, out.getvalue()


def assert_refused(argv_template, files, tmp_path, capfd, word=None):
    """Run the case; assert exit 2, one line (holding `word`), nothing written, input unchanged."""
    out = tmp_path / "out"
    argv = [a.format(out=str(out), **files) for a in argv_template]
    inputs = {p: sha256(p) for p in argv if os.path.isfile(p)}
    code, lines, _ = run_cli(argv, capfd)
    assert code == 2, (argv, code, lines)
    assert len(lines) == 1 and lines[0].startswith("cadrobot: error: "), (argv, lines)
    if word:
        assert word.lower() in lines[0].lower(), (argv, lines[0])
    assert not out.exists(), (argv, os.listdir(out))
    assert {p: sha256(p) for p in inputs} == inputs
    return lines[0]


SINGLE = single_cases()
RANDOM = random_cases()


@pytest.mark.parametrize("command", sorted(BASE))
def test_the_lines_the_bad_values_go_into_run(files, tmp_path, capfd, command):
    """Without them each base line works (so a refusal above is the bad value's doing)."""
    out = tmp_path / "out"
    argv = [a.format(out=str(out), **files) for a in BASE[command]]
    before = sha256(files["doc"])
    code, lines, stdout = run_cli(argv, capfd)
    assert code in (0, 1) and not [l for l in lines if "error" in l], (code, lines)
    assert stdout and sha256(files["doc"]) == before
    if "{out}" in BASE[command]:
        assert os.listdir(out)


@pytest.mark.parametrize("case, argv, word", SINGLE, ids=[c[0] for c in SINGLE])
def test_every_bad_option_value_is_refused_alone(files, tmp_path, capfd, case, argv, word):
    assert_refused(argv, files, tmp_path, capfd, word)


@pytest.mark.parametrize("case, argv, word", RANDOM, ids=[c[0] for c in RANDOM])
def test_random_lines_with_a_bad_value_are_refused(files, tmp_path, capfd, case, argv, word):
    assert_refused(argv, files, tmp_path, capfd)


DOCUMENT_CASES = [(name, command) for name in bad_documents.DEFECTS for command in ("export", "check")
                  if command == "export" or name not in bad_documents.EXPORT_ONLY]


@pytest.mark.parametrize("defect, command", DOCUMENT_CASES, ids=["%s-%s" % c for c in DOCUMENT_CASES])
def test_every_defective_document_is_refused_naming_the_object(files, tmp_path, capfd, defect, command):
    argv = [a.replace("{doc}", "{%s}" % defect) for a in BASE[command]]
    line = assert_refused(argv, files, tmp_path, capfd)
    for word in bad_documents.DEFECTS[defect][1]:
        assert word in line, line
    assert "array(" not in line and "[" not in line     # no numpy repr


DAMAGED_CASES = [(kind, command) for kind in bad_documents.DAMAGED_FILES
                 for command in ("export", "check", "simulate", "sweep", "place")]


@pytest.mark.parametrize("kind, command", DAMAGED_CASES, ids=["%s-%s" % c for c in DAMAGED_CASES])
def test_a_damaged_file_gives_only_our_line(files, tmp_path, capfd, kind, command):
    argv = [a.replace("{doc}", "{%s}" % kind) for a in BASE[command]]
    assert_refused(argv, files, tmp_path, capfd, bad_documents.DAMAGED_FILES[kind])


def test_an_output_path_that_is_a_file_is_refused_and_kept(files, tmp_path, capfd):
    blocker = tmp_path / "taken"
    blocker.write_text("mine")
    code, lines, _ = run_cli(["export", files["doc"], "-o", str(blocker)], capfd)
    assert code == 2 and len(lines) == 1 and "Cannot create output folder" in lines[0], lines
    assert blocker.read_text() == "mine"


def test_a_document_with_a_bad_second_cell_writes_nothing_at_all(files, tmp_path, capfd):
    out = tmp_path / "out"
    code, lines, _ = run_cli(["export", files["second_cell_bad"], "-o", str(out)], capfd)
    assert code == 2 and len(lines) == 1 and "no tool marker" in lines[0], lines
    assert not out.exists()
    code, lines, stdout = run_cli(["export", files["second_cell_bad"], "--cell", "First", "-o",
                                   str(out)], capfd)
    assert code == 0, lines
    assert os.listdir(out) == ["First.mod"] and stdout == "First: wrote %s\n" % (out / "First.mod")


@pytest.mark.parametrize("option", ["path_correction=maybe", "path_corection=true"])
def test_a_bad_rapid_option_is_one_line_and_nothing_written(files, tmp_path, capfd, option):
    assert_refused(["export", "{doc}", "-o", "{out}", "--option", option], files, tmp_path, capfd,
                   option.split("=")[0])


def test_the_table_is_large_and_covers_every_number_option():
    parser_options = {(c, o) for c in ("simulate", "sweep", "place")
                      for o in ("--rate", "--seed", "--runs", "--tolerance", "--workers", "--step",
                                "--z-step", "--turn-step", "--margin", "--count")
                      if o in cli.build_parser()._subparsers._group_actions[0].choices[c]
                      ._option_string_actions}
    assert parser_options <= {k for k in BAD_VALUES if number_option(*k)}
    assert len(SINGLE) + len(RANDOM) + len(DOCUMENT_CASES) + len(DAMAGED_CASES) > 400
