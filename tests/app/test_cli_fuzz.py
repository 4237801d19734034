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
one.

Two Hypothesis properties (tests/fuzzing.py: deterministic under ``make test``)
go beyond the table, which they hold as explicit examples:

* any value of any option (the table's bad values, then numbers of every
  size, NaN, infinities, text, unicode, paths that are files, missing or
  links) exits 0 or 1 (and then the input is unchanged), or is refused as
  above; never exit 3, never a traceback;
* any command line made of 0-2 valid options and 1-2 bad ones is refused.

Values that would make a valid run long (thousands of sweep runs, a millimetre
grid for ``place``) are left out of the generated ones: the bounds on such
counts are issue 21 item 5's (tests/app/test_bounds.py).
"""

import contextlib
import io
import math
import os
import tempfile

import pytest

import bad_documents
import fuzzing
from conftest import sha256
from CadRobotWB import cli

fuzzing.require()

from hypothesis import example, given, strategies as st  # noqa: E402

#: Longest a fuzzed command line may run, s: a value that makes the CLI work for
#: hours fails the test instead of holding up the tier.
RUN_LIMIT_S = 60

#: Values no number option takes (and no option of two numbers).
NOT_NUMBERS = ["nan", "NaN", "inf", "-inf", "1e999", "abc", ""]

#: (command, option) -> bad values beyond NOT_NUMBERS (for number options) or instead of them.
BAD_VALUES = {
    ("simulate", "--rate"): NOT_NUMBERS + ["0", "-5", "1000", "1,2", "5e-324"],
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
    ("sweep", "--runs"): NOT_NUMBERS + ["0", "-3", "1.5", "1000000", "100000"],
    ("sweep", "--rate"): NOT_NUMBERS + ["0", "-1", "101", "5e-324"],
    ("sweep", "--tolerance"): NOT_NUMBERS + ["0", "-1"],
    ("sweep", "--workers"): NOT_NUMBERS + ["0", "-2", "1000", "2.5", "256"],
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


@pytest.fixture(scope="module")
def files(seam_file, tmp_path_factory):
    """The seam document, the defective documents and the damaged files, made once."""
    folder = tmp_path_factory.mktemp("fuzz")
    made = {"doc": seam_file, "missing": str(folder / "missing.urdf"),
            "folder": str(folder), "doc_link": str(folder / "link.FCStd"),
            "dangling": str(folder / "dangling.FCStd"), "loop": str(folder / "loop.FCStd")}
    os.symlink(seam_file, made["doc_link"])
    os.symlink(str(folder / "gone.FCStd"), made["dangling"])
    os.symlink(made["loop"], made["loop"])
    for name in bad_documents.DEFECTS:
        made[name] = bad_documents.save_defect(name, folder)
    for kind in bad_documents.DAMAGED_FILES:
        made[kind] = bad_documents.write_damaged_file(kind, folder, seam_file)
    return made


def run_cli(argv, capfd):
    """(exit code, stderr lines, stdout) of cli.main(argv); stderr both Python's and fd 2's."""
    out, err = io.StringIO(), io.StringIO()
    capfd.readouterr()
    with fuzzing.time_limit(RUN_LIMIT_S):
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


#: Values of every kind beyond the table's: specials, odd spellings, unicode, paths.
SPECIAL_VALUES = ["nan", "-nan", "inf", "-Infinity", "1e308", "-1e308", "1e999", "5e-324", "-0",
                  "0", "1", "-1", "", " ", "abc", "\u0661", "\u00e9", "\U0001f600", "1_000", "0x10",
                  "+5", " 5", "5 ", "1,2", "1;2", "--", "-h", "'", '"', "\\", "\x7f", "x" * 300]
#: Paths of every kind ({...}: made by the `files` fixture; {out}: the output folder).
PATH_VALUES = ["{doc}", "{doc_link}", "{missing}", "{missing}/a/b", "{folder}", "{dangling}", "{loop}",
               "/dev/null", "/", "{doc}/x", "{out}/../out"]
#: Options whose value is a path: (command, option) -> the word a refusal names.
PATH_OPTIONS = {("export", "-o"): "output", ("simulate", "-o"): "output",
                ("robots", "--import"): "file"}
#: In-range values that make a valid run long, left out of the generated values:
#: (command, option) -> True for a number too costly for a test.
COSTLY = {("sweep", "--runs"): lambda v: v > 2, ("sweep", "--workers"): lambda v: v > 1,
          ("place", "--count"): lambda v: v > 5, ("place", "--step"): lambda v: v < 100,
          ("place", "--z-step"): lambda v: v < 100, ("place", "--turn-step"): lambda v: v < 30,
          ("simulate", "--rate"): lambda v: v > 20, ("sweep", "--rate"): lambda v: v > 20,
          ("sweep", "--tolerance"): lambda v: True, ("place", "--margin"): lambda v: True}

def number_of(value):
    """The finite number `value` spells, else None."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def costly(command, option, value):
    """True when `value` is a number in range that would make the run long."""
    number = number_of(value)
    return number is not None and COSTLY.get((command, option), lambda v: False)(number)


def number_values():
    return st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr),
                     st.integers(-2 ** 70, 2 ** 70).map(str))


def any_value(command, option):
    """Any value for one option (not only bad ones): (argv template, word, must be refused)."""
    if (command, option) in PATH_OPTIONS:
        values = st.sampled_from(PATH_VALUES + SPECIAL_VALUES)
    elif number_option(command, option):
        values = st.one_of(st.sampled_from(SPECIAL_VALUES), number_values())
    else:
        values = st.one_of(st.sampled_from(SPECIAL_VALUES), st.text(max_size=30))
    word = PATH_OPTIONS.get((command, option)) or word_of(option)
    return values.filter(lambda value: not costly(command, option, value)).map(
        lambda value: (BASE[command] + [option, value], word, False))


def table_value(command, option):
    """One of the table's bad values for one option: it must be refused."""
    return st.sampled_from(BAD_VALUES[(command, option)]).map(
        lambda value: (BASE[command] + [option, value], word_of(option), True))


OPTIONS = sorted(set(BAD_VALUES) | set(PATH_OPTIONS))
one_option_lines = st.sampled_from(OPTIONS).flatmap(
    lambda key: st.one_of(any_value(*key), table_value(*key)) if key in BAD_VALUES
    else any_value(*key))


def fresh_folder(tmp_path):
    """A new folder under the test's tmp_path (one per Hypothesis example)."""
    return tempfile.mkdtemp(dir=str(tmp_path))


@contextlib.contextmanager
def working_directory(folder):
    """Run the block in `folder` (an output path like ' ' or '5e-324' is relative to it)."""
    previous = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(previous)


def assert_promises_kept(case, files, tmp_path, capfd):
    """Exit 0/1 with the input unchanged, or a refusal as `assert_refused` states; never 3."""
    argv_template, word, must_refuse = case
    folder = fresh_folder(tmp_path)
    out = os.path.join(folder, "out")
    argv = [a.format(out=out, **files) for a in argv_template]
    inputs = {p: sha256(p) for p in argv if os.path.isfile(p)}
    with working_directory(folder):
        code, lines, _ = run_cli(argv, capfd)
    assert code in ((2,) if must_refuse else (0, 1, 2)), (argv, code, lines)
    assert not [line for line in lines if "Traceback" in line or "internal error" in line], lines
    if code == 2:
        assert len(lines) == 1 and lines[0].startswith("cadrobot: error: "), (argv, lines)
        assert word.lower() in lines[0].lower(), (argv, lines[0])
        assert not os.path.exists(out), (argv, os.listdir(out))
    assert {p: sha256(p) for p in inputs} == inputs


def with_table_examples(test):
    """`test` with every bad value of the table as an explicit example."""
    for _, argv, word in SINGLE:
        test = example(case=(argv, word, True))(test)
    return test


@with_table_examples
@given(case=one_option_lines)
@fuzzing.examples(40, shared_fixtures=True)
def test_any_value_of_any_option_is_run_or_refused_in_one_line(files, tmp_path, capfd, case):
    assert_promises_kept(case, files, tmp_path, capfd)


def bad_lines(command):
    """0-2 valid options, then 1-2 of the table's bad ones, of one command."""
    good = [key for key in GOOD_VALUES if key[0] == command]
    bad = [key for key in BAD_VALUES if key[0] == command]

    def words(key, value):
        return [key[1]] if value is None else [key[1], value]

    good_keys = st.lists(st.sampled_from(good), max_size=2, unique=True) if good else st.just([])
    goods = good_keys.flatmap(
        lambda keys: st.tuples(*[st.sampled_from(GOOD_VALUES[k]).map(lambda v, k=k: words(k, v))
                                 for k in keys]))
    bads = st.lists(st.sampled_from(bad), min_size=1, max_size=2, unique=True).flatmap(
        lambda keys: st.tuples(*[st.sampled_from(BAD_VALUES[k]).map(lambda v, k=k: words(k, v))
                                 for k in keys]))
    # the bad ones last: a later valid value of the same option would replace a bad one
    return st.tuples(goods, bads).map(lambda gb: (BASE[command] + sum(gb[0] + gb[1], []), "", True))


@given(case=st.sampled_from(sorted(BASE)).flatmap(bad_lines))
@fuzzing.examples(100, shared_fixtures=True)
def test_lines_with_a_bad_value_among_good_ones_are_refused(files, tmp_path, capfd, case):
    assert_promises_kept(case, files, tmp_path, capfd)


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
    assert len(SINGLE) + len(DOCUMENT_CASES) + len(DAMAGED_CASES) > 250
