"""Tests of the post-processor registry (posts/__init__.py)."""

import sys
import textwrap

import numpy as np
import pytest

from CadRobotWB import posts
from CadRobotWB.core import program as ir
from CadRobotWB.errors import PostError, UnknownNameError

USER_POST = '''
"""A user post for the (made-up) MyBrand controller."""
from dataclasses import dataclass

NAME = "mybrand"
DESCRIPTION = "MyBrand text program"
FILE_EXTENSIONS = (".txt",)


@dataclass
class _Line:          # dataclasses need the module in sys.modules while loading
    text: str


def export(program, options):
    lines = [_Line(f"MOVE {m.kind} {m.target.name}") for m in program.moves()]
    return [(program.name + ".txt", "\\n".join(l.text for l in lines) + "\\n")]
'''


def small_program():
    tool = ir.ToolData("Tool", np.eye(4))
    frames = {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))}
    move = ir.Move(ir.LINEAR, ir.Target("t1", np.eye(4)), 10.0, 0.0, "B")
    return ir.Program("Job", "ABB_IRB2400", tool, frames,
                      [ir.ProgramPath("Path", "Path", [move])])


def write(folder, filename, text):
    path = folder / filename
    path.write_text(textwrap.dedent(text))
    return path


def user_modules():
    return [n for n in sys.modules if n.startswith("_cadrobot_user_post_")]


# --- built-in posts -------------------------------------------------------------

def test_builtin_names():
    assert posts.names() == ["abb_rapid", "motoman_inform", "kuka_krl", "ur_script", "fanuc_ls"]
    assert posts.names() == list(posts.BUILTIN)


@pytest.mark.parametrize("name", posts.BUILTIN)
def test_builtin_posts_follow_the_contract(name):
    post = posts.get(name)
    assert post.NAME == name
    assert isinstance(post.DESCRIPTION, str) and post.DESCRIPTION
    assert all(ext.startswith(".") for ext in post.FILE_EXTENSIONS)
    files = post.export(small_program(), {})
    assert files and all(isinstance(f, str) and isinstance(t, str)
                         for f, t in files)
    assert all(f.endswith(post.FILE_EXTENSIONS) for f, _ in files)


def test_unknown_name(monkeypatch):
    monkeypatch.setenv("PATH", "/nowhere")     # no `cadrobot` launcher: FreeCADCmd's line
    with pytest.raises(UnknownNameError) as info:
        posts.get("xyz")
    assert str(info.value) == (
        "Unknown post-processor 'xyz'. Available: abb_rapid, motoman_inform, kuka_krl, ur_script, fanuc_ls. "
        "`FreeCADCmd -c \"from CadRobotWB import cli; cli.run('posts')\"` describes them.")


def test_unknown_name_lists_user_posts(tmp_path):
    write(tmp_path, "mybrand_post.py", USER_POST)
    with pytest.raises(UnknownNameError, match="Available: abb_rapid, motoman_inform, kuka_krl, ur_script, fanuc_ls, mybrand."):
        posts.get("xyz", extra_dirs=[tmp_path])


# --- user posts -----------------------------------------------------------------

def test_user_post_is_discovered_and_runs(tmp_path):
    write(tmp_path, "mybrand_post.py", USER_POST)
    write(tmp_path, "notes.py", "x = 1\n")            # not a post: ignored
    before = set(sys.modules)
    assert posts.names(extra_dirs=[tmp_path]) == list(posts.BUILTIN) + ["mybrand"]

    post = posts.get("mybrand", extra_dirs=[str(tmp_path)])
    assert post.NAME == "mybrand" and post.FILE_EXTENSIONS == (".txt",)
    assert post.export(small_program(), {}) == [("Job.txt", "MOVE linear t1\n")]
    assert set(sys.modules) == before                 # nothing left behind
    assert not user_modules()


def test_user_post_loads_fresh_each_time(tmp_path):
    write(tmp_path, "mybrand_post.py", USER_POST)
    first = posts.get("mybrand", [tmp_path])
    second = posts.get("mybrand", [tmp_path])
    assert first is not second


def test_user_post_without_metadata_gets_defaults(tmp_path):
    write(tmp_path, "bare_post.py", """
        def export(program, options):
            return []
        """)
    post = posts.get("bare", [tmp_path])
    assert post.NAME == "bare"
    assert "bare_post.py" in post.DESCRIPTION
    assert post.FILE_EXTENSIONS == ()


def test_user_post_shadows_builtin_and_first_folder_wins(tmp_path):
    first, second = tmp_path / "macros", tmp_path / "prefs"
    first.mkdir()
    second.mkdir()
    write(first, "abb_rapid_post.py", 'NAME = "mine"\n'
                                      'def export(program, options):\n'
                                      '    return [("a.mod", "first")]\n')
    write(second, "abb_rapid_post.py", 'def export(program, options):\n'
                                       '    return [("a.mod", "second")]\n')
    assert posts.names([first, second]) == list(posts.BUILTIN)
    post = posts.get("abb_rapid", [first, second])
    assert post.export(None, {}) == [("a.mod", "first")]
    assert posts.get("abb_rapid") is not post        # built-in still there


def test_missing_or_empty_extra_dirs_are_ignored(tmp_path):
    assert posts.names([tmp_path / "nowhere", "", None]) == list(posts.BUILTIN)
    assert posts.get("abb_rapid", [tmp_path / "nowhere"]).NAME == "abb_rapid"


@pytest.mark.parametrize("text, reason", [
    ("def export(program, options)\n    return []\n", "SyntaxError"),
    ("import no_such_module_for_cadrobot\n", "ModuleNotFoundError"),
    ("raise RuntimeError('half written')\n", "half written"),
    ("NAME = 'broken'\n", "does not define export"),
    ("export = 42\n", "does not define export"),
])
def test_broken_user_post_names_the_file(tmp_path, text, reason):
    path = write(tmp_path, "broken_post.py", text)
    assert "broken" in posts.names([tmp_path])      # listed, fails on use
    with pytest.raises(PostError) as info:
        posts.get("broken", [tmp_path])
    assert str(path) in str(info.value)
    assert reason in str(info.value)
    assert not user_modules()


def test_broken_user_post_does_not_hide_others(tmp_path):
    write(tmp_path, "broken_post.py", "this is not python\n")
    write(tmp_path, "mybrand_post.py", USER_POST)
    assert posts.get("mybrand", [tmp_path]).NAME == "mybrand"
    assert posts.get("abb_rapid", [tmp_path]).NAME == "abb_rapid"


def test_the_readme_example_post_works(tmp_path):
    """The user-post example in the README is loaded and run as a user would."""
    import re
    from pathlib import Path
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    section = readme[readme.index("## Your own post-processor"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "mybrand_post.py").write_text(code)
    assert "mybrand" in posts.names(extra_dirs=[tmp_path])
    T = np.eye(4)
    T[:3, 3] = (10, 20, 30)
    program = ir.Program("Demo", "ABB_IRB2400", ir.ToolData("t", np.eye(4)),
                         {"B": ir.WorkFrame("B", np.eye(4), np.eye(4))},
                         [ir.ProgramPath("p", "p", [ir.Move(ir.LINEAR, ir.Target("a", T), 12.5, 0, "B")])])
    files = posts.get("mybrand", extra_dirs=[tmp_path]).export(program, {})
    assert files == [("Demo.prg", "LINEAR 10.000 20.000 30.000 1.000000 0.000000 0.000000 0.000000 F12.5\n")]
