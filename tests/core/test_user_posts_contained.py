"""User posts are contained and every post's output is checked (issue 21, item 4).

Each hostile post runs through ``posts.get`` and ``posts.run``, as an export
runs it: the refusal is one PostError naming the post and its file, what it
returned and what a post must return. The built-in posts, fed labels a user may
type, write safe file names and text. ``tests/app/test_user_posts_contained.py``
runs a few of these through the CLI: exit 2, nothing written, the document kept.
"""

import numpy as np
import pytest

from CadRobotWB import fileio, posts
from CadRobotWB.core import program as ir
from CadRobotWB.errors import InputError, PostError
from CadRobotWB.posts import output_check

MUST = "; " + output_check.CONTRACT

#: (case, body of export(program, options), what the refusal says after the post's name).
#: "{must}" is the contract every refusal of what a post returned ends with.
RETURNS = [
    ("raises", "raise ValueError('bad value')",
     " failed: ValueError: bad value. Fix the post, or choose another."),
    ("sys_exit_0", "import sys; sys.exit(0)",
     " failed: SystemExit(0), it called sys.exit. Fix the post, or choose another."),
    ("sys_exit_3", "import sys; sys.exit(3)",
     " failed: SystemExit(3), it called sys.exit. Fix the post, or choose another."),
    ("base_exception", "class Stop(BaseException): pass\n    raise Stop('stop')",
     " failed: Stop: stop. Fix the post, or choose another."),
    ("recursion", "def f(n): return f(n + 1)\n    f(0)",
     " failed: RecursionError: maximum recursion depth exceeded. Fix the post, or choose another."),
    ("memory", "return [('a.prg', bytearray(2 ** 62))]",
     " failed: MemoryError. Fix the post, or choose another."),
    ("its_own_refusal",
     "from CadRobotWB.errors import PostError\n    raise PostError('no arcs here')",
     ": no arcs here"),
    ("none", "return None", " returned None{must}."),
    ("str", "return 'MOVE 1 2 3'", " returned a str 'MOVE 1 2 3'{must}."),
    ("bytes", "return b'MOVE'", " returned a bytes b'MOVE'{must}."),
    ("int", "return 5", " returned an int 5{must}."),
    ("ints", "return [1, 2]", " returned an int 1 as item 1, not a (file name, text) pair{must}."),
    ("dict", "return {'a.prg': 'text'}", " returned a dict {'a.prg': 'text'}{must}."),
    ("dict_of_ints", "return {'a.prg': 10 ** 8}", " returned a dict {'a.prg': 100000000}{must}."),
    ("triple", "return [('a.prg', 'x', 'y')]",
     " returned a tuple ('a.prg', 'x', 'y') as item 1, not a (file name, text) pair{must}."),
    ("no_files", "return []", " returned no files{must}, at least one pair."),
    ("endless", "import itertools\n    return (('f%d.prg' % i, 'x') for i in itertools.count())",
     " returned more than 10000 files{must}, a program has at most 10000."),
    ("text_int", "return [('a.prg', 10 ** 8)]", " returned an int as the text of 'a.prg'{must}."),
    ("text_bytes", "return [('a.prg', b'abc')]", " returned a bytes as the text of 'a.prg'{must}."),
    ("text_none", "return [('a.prg', None)]", " returned None as the text of 'a.prg'{must}."),
    ("text_nested", "return [('a.prg', {'b': 'c'})]",
     " returned a dict as the text of 'a.prg'{must}."),
    ("text_nul", "return [('a.prg', 'A\\nB\\x00')]",
     " returned a NUL character in the text of 'a.prg' (line 2){must}."),
    ("text_surrogate", "return [('a.prg', 'MOVE \\udcff')]",
     " returned '\\udcff' in the text of 'a.prg' (line 1), which is not valid Unicode{must}."),
    ("text_too_big", "return [('a%d.prg' % i, 'x' * 30_000_000) for i in range(4)]",
     " returned more than 100 MB of text (at 'a3.prg'){must}, a program holds at most "
     "100000000 bytes."),
    ("name_int", "return [(5, 'x')]", " returned the file name 5 (item 1), but it is an int, "
     "not a str{must}."),
    ("name_twice", "return [('a.prg', 'x'), ('a.prg', 'y')]",
     " returned the file name 'a.prg' twice{must}, each name must differ in more than case."),
    ("name_case", "return [('A.prg', 'x'), ('a.PRG', 'y')]",
     " returned the file names 'A.prg' and 'a.PRG', one file where case is ignored (Windows, "
     "macOS){must}, each name must differ in more than case."),
]

#: (file name a post returns, why it is refused).
BAD_NAMES = [
    ("", "it is not a file name"),
    (".", "it is not a file name"),
    ("..", "it is not a file name"),
    ("../x.prg", "it holds '/'"),
    ("/tmp/x.prg", "it holds '/'"),
    ("..\\x.prg", "it holds '\\\\'"),
    ("C:x.prg", "it holds ':'"),
    ("a\x00.prg", "it holds '\\x00'"),
    ("a\x1b[31m.prg", "it holds '\\x1b'"),
    ("a\n.prg", "it holds '\\n'"),
    ("a\udcff.prg", "it holds '\\udcff', which is not valid Unicode"),
    ("a?.prg", "it holds '?'"),
    ("CON", "CON is a device name on Windows"),
    ("con.prg", "con is a device name on Windows"),
    ("LPT9.a.b", "LPT9 is a device name on Windows"),
    ("x.prg.", "it ends in '.'"),
    ("x.prg ", "it ends in ' '"),
    ("x" * 197 + ".prg", "it is 201 bytes long, more than 200"),
    ("\u00e9" * 99 + ".prg", "it is 202 bytes long, more than 200"),
    ("ready", "CadRobot's writing uses that name itself"),
    (".CadRobot-files-a.prg", "CadRobot's writing uses that name itself"),
]

#: (file of the post, what loading it says after the post's name).
BAD_FILES = [
    ("def export(program, options)\n    return []\n",
     " failed to load: SyntaxError: expected ':' (bad_post.py, line 1). Fix or remove the file."),
    ("import no_such_module_for_cadrobot\n",
     " failed to load: ModuleNotFoundError: No module named 'no_such_module_for_cadrobot'. "
     "Fix or remove the file."),
    ("import sys\nsys.exit(0)\n",
     " failed to load: SystemExit(0), it called sys.exit. Fix or remove the file."),
    ("NAME = 'bad'\n", " does not define export(program, options); add it or remove the file."),
    ("def export(program):\n    return []\n", ": its export(program) cannot be called as "
     "export(program, options); give it those two parameters."),
    ("def export(program, options, extra):\n    return []\n",
     ": its export(program, options, extra) cannot be called as export(program, options); give "
     "it those two parameters."),
    ("OPTIONS = ['verbose']\ndef export(program, options):\n    return []\n",
     ": OPTIONS is a list ['verbose']; it must be a dict of option name to one line of help, "
     "e.g. {'verbose': 'true or false'}."),
    ("DESCRIPTION = None\ndef export(program, options):\n    return []\n",
     ": DESCRIPTION is None; it must be a str."),
    ("FILE_EXTENSIONS = '.prg'\ndef export(program, options):\n    return []\n",
     ": FILE_EXTENSIONS is a str '.prg'; it must be a tuple of str, e.g. ('.prg',)."),
    ("OPTIONS = {'verbose': 5}\ndef export(program, options):\n    return []\n",
     ": OPTIONS is a dict {'verbose': 5}; it must be a dict of option name to one line of help, "
     "e.g. {'verbose': 'true or false'}."),
]


def small_program(name="Job", label="Path"):
    tool = ir.ToolData(label, np.eye(4), label=label)
    frames = {"B": ir.WorkFrame("B", np.eye(4), np.eye(4), source=label)}
    move = ir.Move(ir.LINEAR, ir.Target("t1", np.eye(4)), 10.0, 0.0, "B", comment=label)
    return ir.Program(name, "ABB_IRB2400", tool, frames, [ir.ProgramPath(label, label, [move])],
                      source=label)


def user_post(folder, name, source):
    """Write ``<name>_post.py`` into `folder`; returns its path and the words naming it."""
    path = folder / (name + "_post.py")
    path.write_text(source, encoding="utf-8", errors="surrogatepass")
    return path, "User post-processor '%s' (%s)" % (name, path)


def refusal(folder, name):
    """The message of the PostError that loading and running post `name` of `folder` gives."""
    with pytest.raises(PostError) as info:
        posts.run(posts.get(name, [folder]), small_program(), {"date": None})
    return str(info.value)


@pytest.mark.parametrize("case, body, says", RETURNS, ids=[c[0] for c in RETURNS])
def test_what_a_user_post_does_wrong_is_one_line_naming_it(tmp_path, case, body, says):
    _, who = user_post(tmp_path, case, "def export(program, options):\n    %s\n" % body)
    assert refusal(tmp_path, case) == who + says.replace("{must}", MUST)


@pytest.mark.parametrize("name, why", BAD_NAMES, ids=[repr(n)[:20] for n, _ in BAD_NAMES])
def test_a_file_name_no_os_takes_is_refused(tmp_path, name, why):
    _, who = user_post(tmp_path, "names", "def export(program, options):\n    return [(%r, 'x')]\n"
                       % name)
    shown = output_check._repr(name)
    assert refusal(tmp_path, "names") == "%s returned the file name %s (item 1), but %s%s." % (
        who, shown, why, MUST)
    with pytest.raises(InputError, match="^Output file name .* is not a plain file name: "):
        fileio.refuse_bad_names(["ok.prg", name])   # and fileio, for every file it writes


@pytest.mark.parametrize("source, says", BAD_FILES, ids=range(len(BAD_FILES)))
def test_a_post_file_that_cannot_be_used_is_one_line_naming_it(tmp_path, source, says):
    _, who = user_post(tmp_path, "bad", source)
    with pytest.raises(PostError) as info:
        posts.get("bad", [tmp_path])
    assert str(info.value) == who + says


def test_a_good_post_passes_and_ctrl_c_stays_an_interrupt(tmp_path):
    user_post(tmp_path, "good", "def export(program, options):\n"
              "    return (pair for pair in [('%s.prg' % program.name, 'MOVE\\n')])\n")
    assert posts.run(posts.get("good", [tmp_path]), small_program(), {}) == [("Job.prg", "MOVE\n")]
    user_post(tmp_path, "stop", "def export(program, options):\n    raise KeyboardInterrupt\n")
    with pytest.raises(KeyboardInterrupt):
        posts.run(posts.get("stop", [tmp_path]), small_program(), {})


HOSTILE_LABELS = ["../x", "CON", "con.txt", "a\x00b\x1b[31m\udcff\r\nZ", "x" * 300, "\u00e9" * 200,
                  ".", "..", "", "a/b\\c:d", "trailing. ", "LPT1", "\x7f\u0085", "ready"]


@pytest.mark.parametrize("post", posts.BUILTIN)
def test_built_in_posts_make_labels_safe(post):
    """Names and comments come from the user's labels: every file name is safe, every text
    has no control character but line ends (checked before posts.run's own check)."""
    for label in HOSTILE_LABELS:
        files = posts.get(post).export(small_program(name=label, label=label), {})
        assert output_check.checked_files(files, post) == files
        for _, text in files:
            assert not [c for c in text if (ord(c) < 32 or c == "\x7f") and c not in "\r\n\t"], \
                (post, label)


def test_the_readme_states_what_a_post_must_return_and_the_limits():
    from pathlib import Path
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    section = readme[readme.index("## Your own post-processor"):readme.index("## Scripting")]
    section = " ".join(section.split())
    for words in ("list of `(file name, text)` pairs",
                  "at most %s" % format(output_check.MAX_FILES, ","),
                  "%d MB of text" % (output_check.MAX_OUTPUT_BYTES // 10 ** 6),
                  "at most %d bytes in UTF-8" % output_check.MAX_NAME_BYTES, "`sys.exit`", "exit 2",
                  "one line naming the post and its file"):
        assert words in section, words


def test_an_iterable_that_raises_is_contained(tmp_path):
    _, who = user_post(tmp_path, "lazy", "class Files:\n"
                       "    def __iter__(self):\n        raise OSError('disk gone')\n"
                       "def export(program, options):\n    return Files()\n")
    assert refusal(tmp_path, "lazy") == (
        who + " failed: OSError: disk gone. Fix the post, or choose another.")
