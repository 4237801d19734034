"""A user post that fails or returns what cannot be written: one line, exit 2, nothing
written, the document kept (issue 21, item 4).

tests/core/test_user_posts_contained.py checks every case's exact message on
``posts.run``; here one case of each kind goes through an export as a user runs
it: ``cli.main`` in this process, ``api.export``, and a few through the real
launcher (one process each), where a post's ``sys.exit`` used to end the CLI.
"""

import io
import json
import os
import shutil

import pytest

import FreeCAD
from conftest import run_cadrobot, sha256
from CadRobotWB import api, cli
from CadRobotWB.errors import CadRobotError, InputError, PostError
from CadRobotWB.workflow import export as api_export

#: (post name, body of its export(program, options), words its refusal holds after
#: "User post-processor '<name>' (<file>)").
POSTS = [
    ("raises", "raise ValueError('bad value')", "failed: ValueError: bad value"),
    ("exits", "import sys; sys.exit(0)", "failed: SystemExit(0), it called sys.exit"),
    ("base_exception", "class Stop(BaseException): pass\n    raise Stop('stop')",
     "failed: Stop: stop"),
    ("gives_none", "return None", "returned None; a post must return a list of (file name, text)"),
    ("text_int", "return [('a.prg', 10 ** 8)]", "returned an int as the text of 'a.prg'"),
    ("climbs_out", "return [('../a.prg', 'x')]", "returned the file name '../a.prg' (item 1), "
                                                "but it holds '/'"),
    ("device", "return [('CON', 'x')]", "returned the file name 'CON' (item 1), but CON is a "
                                        "device name on Windows"),
    ("case_twins", "return [('A.prg', 'x'), ('a.prg', 'y')]", "returned the file names 'A.prg' "
                                                              "and 'a.prg', one file where case"),
    ("text_nul", "return [('a.prg', 'x\\x00')]", "returned a NUL character in the text of 'a.prg'"),
    ("one_argument", None, "its export(program) cannot be called as export(program, options)"),
]

#: Cases run through the real launcher: exit 0 and no line, and 100 MB of zero bytes
#: written, before issue 21.
LAUNCHED = ["exits", "text_int"]


def post_source(body):
    if body is None:
        return "def export(program):\n    return [('a.prg', 'x')]\n"
    return "def export(program, options):\n    %s\n" % body


def write_posts(folder):
    for name, body, _ in POSTS:
        (folder / (name + "_post.py")).write_text(post_source(body))


@pytest.fixture(scope="module")
def document(seam_file, tmp_path_factory):
    """The seam document in a folder of its own, and a folder holding every post of POSTS."""
    root = tmp_path_factory.mktemp("user_posts")
    path = root / "in" / "seam.FCStd"
    path.parent.mkdir()
    shutil.copy(seam_file, path)
    (root / "posts").mkdir()
    write_posts(root / "posts")
    return path


@pytest.fixture
def user_posts(document, monkeypatch):
    folder = str(document.parent.parent / "posts")
    for module in (api, api_export):
        monkeypatch.setattr(module, "user_post_dirs", lambda: [folder])
    return document


def everything_under(folder):
    """{path: sha256} of every file below `folder` but Python's own bytecode caches (Python
    3.14 in FreeCAD 1.1 writes one for a post it loads)."""
    return {os.path.join(d, f): sha256(os.path.join(d, f))
            for d, _, names in os.walk(folder) if os.path.basename(d) != "__pycache__"
            for f in names}


def expected_line(document, name, words):
    path = document.parent.parent / "posts" / (name + "_post.py")
    return "cadrobot: error: User post-processor '%s' (%s)" % (name, path), words


@pytest.mark.parametrize("name, body, words", POSTS, ids=[p[0] for p in POSTS])
def test_a_failing_user_post_is_one_line_and_nothing_is_written(user_posts, tmp_path, capfd,
                                                                name, body, words):
    document = user_posts
    before = everything_under(document.parent.parent)
    out, err = io.StringIO(), io.StringIO()
    capfd.readouterr()
    code = cli.main(["export", str(document), "--post", name, "--no-check", "--quiet", "-o",
                     str(tmp_path / "out")], out=out, err=err)   # --quiet: no progress line
    lines = (err.getvalue() + capfd.readouterr().err).splitlines()
    assert code == 2 and len(lines) == 1, lines
    start, words = expected_line(document, name, words)
    assert lines[0].startswith(start) and words in lines[0], lines[0]
    assert not (tmp_path / "out").exists()
    assert everything_under(document.parent.parent) == before     # the document too


def test_the_api_raises_one_cadrobot_error(user_posts, tmp_path):
    document = user_posts
    doc = FreeCAD.openDocument(str(document))
    try:
        cell = api.find_cells(doc)[0]
        with pytest.raises(PostError, match="^User post-processor 'exits' .* called sys.exit"):
            api.export(cell, post="exits", output_dir=str(tmp_path / "out"), check_first=False)
        with pytest.raises(InputError, match="^export on 'SeamCell': options must be None or a dict, "
                                             "got \\['max_lines'\\] \\(a list\\)"):
            api.export(cell, options=["max_lines"], output_dir=str(tmp_path / "out"))
        assert not doc.isTouched()
    finally:
        FreeCAD.closeDocument(doc.Name)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", LAUNCHED)
def test_the_launcher_exits_2_with_one_line(document, tmp_path, name):
    """The real CLI (one FreeCAD start, about 4 s: only there did sys.exit(0) end the run
    with exit 0 and no line). The post goes into this FreeCAD's own macro folder (this
    worker's throw-away user folder), which the launched FreeCAD searches."""
    macros = FreeCAD.getUserMacroDir(True)
    os.makedirs(macros, exist_ok=True)
    post = os.path.join(macros, name + "_post.py")
    words = dict((p[0], p[2]) for p in POSTS)[name]
    before = sha256(str(document))
    try:
        shutil.copy(document.parent.parent / "posts" / (name + "_post.py"), post)
        run = run_cadrobot("export", document, "--post", name, "--no-check", "-o", tmp_path / "out")
    finally:
        os.remove(post)
    assert run.returncode == 2, run.stderr
    [line] = run.stderr.splitlines()
    assert line.startswith("cadrobot: error: User post-processor '%s' (%s)" % (name, post)), line
    assert words in line, line
    assert not (tmp_path / "out").exists()
    assert sha256(str(document)) == before


def test_two_cells_writing_names_equal_but_for_case_are_refused():
    from CadRobotWB.cli import _refuse_shared_names
    with pytest.raises(CadRobotError, match="Cells 'A' and 'B' both write 'job.mod'"):
        _refuse_shared_names([{"cell": "A", "files": ["JOB.mod"]},
                              {"cell": "B", "files": ["job.mod"]}])


def test_a_post_that_does_not_load_is_one_warning_and_the_others_stay_listed(user_posts, capfd):
    out, err = io.StringIO(), io.StringIO()
    capfd.readouterr()
    code = cli.main(["posts", "--json"], out=out, err=err)
    lines = (err.getvalue() + capfd.readouterr().err).splitlines()
    assert code == 0
    assert len(lines) == 1 and lines[0].startswith(
        "cadrobot: warning: User post-processor 'one_argument' (%s)"
        % (user_posts.parent.parent / "posts" / "one_argument_post.py")), lines
    listed = [row["name"] for row in json.loads(out.getvalue())]
    assert listed == list(api.post_names()[:5]) + sorted(n for n, _, _ in POSTS if n != "one_argument")
