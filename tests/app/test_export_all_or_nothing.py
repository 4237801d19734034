"""Export writes a program all or nothing, and never over its input (issue 21, items 1-2).

The signal cases run the real launcher with fileio's test hook, which makes the
process signal itself at one step of the write; tests/core/test_fileio_atomic.py
tries every step with SIGINT, SIGTERM and SIGKILL on bare files.
"""

import io
import os
import shutil

import pytest

from conftest import run_cadrobot, sha256
from CadRobotWB import api, cli, fileio
from CadRobotWB.workflow import export as api_export

#: Small enough modules that the seam program is a main module and parts.
SPLIT = ("--post", "abb_rapid", "--option", "max_lines=50")


def _folder(path):
    """{file name: bytes} of everything in `path`, hidden entries included."""
    return {name: (path / name).read_bytes() for name in sorted(os.listdir(path))}


@pytest.fixture(scope="module")
def new_program(seam_file, tmp_path_factory):
    """{file name: bytes} of the split seam program, as an uninterrupted export writes it."""
    out = tmp_path_factory.mktemp("new")
    run = run_cadrobot("export", seam_file, *SPLIT, "-o", str(out))
    assert run.returncode == 0, run.stderr
    return _folder(out)


@pytest.mark.parametrize("hook, left", [
    ("staged:2:TERM", "nothing was written: the folder '{out}' holds the previous program."),
    ("moved:1:INT", "the folder '{out}' holds the new program, complete."),
])
def test_an_interrupted_export_leaves_one_whole_program_and_says_which(
        seam_file, new_program, tmp_path, hook, left):
    assert len(new_program) >= 2                # a main module and its part(s)
    old_program = {name: b"old " + name.encode() for name in new_program}
    for name, data in old_program.items():
        (tmp_path / name).write_bytes(data)
    run = run_cadrobot("export", seam_file, *SPLIT, "-o", str(tmp_path),
                       env={fileio.TEST_HOOK_VARIABLE: hook})
    assert run.returncode == 130, run.stderr
    assert run.stderr.splitlines() == ["cadrobot: interrupted: " + left.format(out=tmp_path)]
    expected = old_program if "previous" in left else new_program
    assert _folder(tmp_path) == expected        # no hidden staging folder either


def _run(*argv):
    out, err = io.StringIO(), io.StringIO()
    code = cli.main(list(argv), out=out, err=err)
    return code, err.getvalue().splitlines()


def _saved_as_program(seam_file, tmp_path):
    """The seam document saved as in/SeamWeld.mod, the name of the module its export writes."""
    document = tmp_path / "in" / "SeamWeld.mod"
    document.parent.mkdir()
    shutil.copy(seam_file, document)
    return document


@pytest.mark.parametrize("output", ["in", "link"])
def test_export_onto_its_own_input_is_refused_and_nothing_is_written(seam_file, tmp_path, output):
    document = _saved_as_program(seam_file, tmp_path)
    (tmp_path / "link").symlink_to(document.parent)
    before = sha256(str(document))
    code, lines = _run("export", str(document), "-o", str(tmp_path / output))
    assert code == 2
    assert lines == ["cadrobot: error: Writing 'SeamWeld.mod' into '%s' would overwrite the input "
                     "'%s'. Choose another output folder or program name; nothing was written."
                     % (tmp_path / output, document)]
    assert sha256(str(document)) == before
    assert os.listdir(document.parent) == ["SeamWeld.mod"]


def test_a_user_post_naming_the_document_is_refused(seam_file, tmp_path, monkeypatch):
    document = tmp_path / "in" / "seam.FCStd"
    document.parent.mkdir()
    shutil.copy(seam_file, document)
    (tmp_path / "evil_post.py").write_text(
        "DESCRIPTION = 'writes the document'\n"
        "def export(program, options):\n"
        "    return [('seam.FCStd', 'not a document')]\n")
    for module in (api, api_export):
        monkeypatch.setattr(module, "user_post_dirs", lambda: [str(tmp_path)])
    before = sha256(str(document))
    code, lines = _run("export", str(document), "--post", "evil", "-o", str(document.parent))
    assert code == 2
    assert len(lines) == 1 and "would overwrite the input '%s'" % document in lines[0]
    assert sha256(str(document)) == before
    assert os.listdir(document.parent) == ["seam.FCStd"]
