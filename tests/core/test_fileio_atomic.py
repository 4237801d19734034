"""A program of several files is replaced as a set: a signal at any step of the
write leaves the previous program or the new one, complete (CadRobotWB.fileio).

Each case forks this process (cheap: no FreeCAD here) and lets the write
signal itself through fileio's test hook at one step.
"""

import os
import signal
import time

import pytest

from CadRobotWB import fileio
from CadRobotWB.errors import InputError

NAMES = ["Prog.src", "Prog1.src", "Prog2.src"]
OLD = [(name, "old %s\n" % name) for name in NAMES]
NEW = [(name, "new %s\n" % name) for name in NAMES]
#: Child exit codes: finished, interrupted leaving the previous / the new program.
FINISHED, LEFT = 10, {fileio.LEFT_PREVIOUS: 20, fileio.LEFT_NEW: 21}
#: Every step of a 3-file write: 3 staged files, READY, 3 renames.
STEPS = [("staged", 1), ("staged", 2), ("staged", 3), ("ready", 1),
         ("moved", 1), ("moved", 2), ("moved", 3)]


def _write_in_child(folder, hook):
    """Fork; the child writes NEW into `folder` with the test hook `hook`; its wait status."""
    pid = os.fork()
    if pid == 0:   # the child: never returns into pytest
        code = 99
        try:
            os.environ[fileio.TEST_HOOK_VARIABLE] = hook
            signal.signal(signal.SIGINT, signal.default_int_handler)
            signal.signal(signal.SIGTERM, signal.SIG_DFL)   # fileio turns it into an interrupt
            fileio.write_files_atomically(str(folder), NEW)
            code = FINISHED
        except KeyboardInterrupt as stop:
            code = LEFT.get(getattr(stop, "program_left", None), 98)
        finally:
            os._exit(code)
    return os.waitpid(pid, 0)[1]


def _program(folder):
    """The texts of NAMES in `folder` (None for a missing file)."""
    return [(folder / n).read_text() if (folder / n).exists() else None for n in NAMES]


def _hidden(folder):
    """Hidden entries but the list of the program's files."""
    return sorted(e for e in os.listdir(folder)
                  if e.startswith(".") and e != fileio.MANIFEST_PREFIX + NAMES[0])


@pytest.fixture
def folder(tmp_path):
    fileio.write_files_atomically(str(tmp_path), OLD)
    return tmp_path


@pytest.mark.parametrize("signal_name", ["INT", "TERM"])
@pytest.mark.parametrize("phase, k", STEPS)
def test_int_or_term_at_any_step_leaves_one_whole_program_and_says_which(folder, phase, k,
                                                                          signal_name):
    status = _write_in_child(folder, "%s:%d:%s" % (phase, k, signal_name))
    staging = phase == "staged"
    assert os.WEXITSTATUS(status) == LEFT[fileio.LEFT_PREVIOUS if staging else fileio.LEFT_NEW]
    assert _program(folder) == [text for _, text in (OLD if staging else NEW)]
    assert _hidden(folder) == []


@pytest.mark.parametrize("phase, k", STEPS)
def test_kill_at_any_step_is_finished_or_undone_by_the_next_write(folder, phase, k):
    status = _write_in_child(folder, "%s:%d:KILL" % (phase, k))
    assert os.WTERMSIG(status) == signal.SIGKILL
    moved = k if phase == "moved" else 0
    assert _program(folder) == [t for _, t in NEW[:moved] + OLD[moved:]]
    assert len(_hidden(folder)) == 1   # the staging folder, kept for the next write
    fileio.write_files_atomically(str(folder), [("Other.txt", "x")])
    expected = NEW if phase != "staged" else OLD   # a complete set is finished, else dropped
    assert _program(folder) == [text for _, text in expected]
    assert _hidden(folder) == []


def test_temp_files_of_older_versions_are_removed_by_the_next_write(folder):
    (folder / ".Prog1.src.ab12cd.tmp").write_text("half")
    (folder / ".keep.tmp").write_text("not ours")
    fileio.write_files_atomically(str(folder), NEW)
    assert _hidden(folder) == [".keep.tmp"]


def test_a_file_that_is_an_input_is_refused_and_nothing_is_written(tmp_path):
    document = tmp_path / "in" / "Prog1.src"
    document.parent.mkdir()
    document.write_text("the document")
    link = tmp_path / "link"
    link.symlink_to(document.parent)
    for output in (document.parent, link):
        with pytest.raises(InputError, match="would overwrite the input '%s'" % document):
            fileio.write_files_atomically(str(output), NEW, inputs=[str(document)])
        assert sorted(os.listdir(document.parent)) == ["Prog1.src"]
        assert document.read_text() == "the document"


def _texts(folder):
    return {e: (folder / e).read_text() for e in os.listdir(folder) if not e.startswith(".")}


def test_parts_of_a_longer_previous_program_are_deleted_unless_changed_since(tmp_path):
    long = [("Prog.src", "1"), ("Prog1.src", "2"), ("Prog2.src", "3"), ("Prog3.src", "4")]
    fileio.write_files_atomically(str(tmp_path), long)
    (tmp_path / "Prog3.src").write_text("edited by hand")
    (tmp_path / "Notes.txt").write_text("the user's")
    fileio.write_files_atomically(str(tmp_path), [("Prog.src", "a"), ("Prog1.src", "b")])
    assert _texts(tmp_path) == {"Prog.src": "a", "Prog1.src": "b",
                                "Prog3.src": "edited by hand", "Notes.txt": "the user's"}
    fileio.write_files_atomically(str(tmp_path), [("Prog.src", "one file")])
    assert _texts(tmp_path)["Prog.src"] == "one file" and "Prog1.src" not in _texts(tmp_path)
    assert [e for e in os.listdir(tmp_path) if e.startswith(".")] == []


def test_a_killed_shorter_program_deletes_the_old_parts_on_the_next_write(folder):
    pid = os.fork()
    if pid == 0:
        os.environ[fileio.TEST_HOOK_VARIABLE] = "moved:1:KILL"
        fileio.write_files_atomically(str(folder), NEW[:1] + [("Other.src", "x")])
        os._exit(10)
    assert os.WTERMSIG(os.waitpid(pid, 0)[1]) == signal.SIGKILL
    assert _program(folder) == [NEW[0][1], OLD[1][1], OLD[2][1]]
    fileio.write_files_atomically(str(folder), [("Else.txt", "y")])
    assert _program(folder) == [NEW[0][1], None, None]


def _fork(job):
    """Run `job` in a forked child, exiting 10 when it returns; the child's pid."""
    pid = os.fork()
    if pid == 0:
        try:
            job()
        finally:
            os._exit(10)
    return pid


def test_a_second_write_into_the_folder_waits_for_the_first(folder):
    locked, release = os.pipe(), os.pipe()

    def first_write_under_way():     # holds the folder's lock until told to go on
        with fileio._folder_lock(str(folder)):
            os.write(locked[1], b"x")
            os.read(release[0], 1)

    holder = _fork(first_write_under_way)
    try:
        assert os.read(locked[0], 1) == b"x"
        writer = _fork(lambda: fileio.write_files_atomically(str(folder), NEW))
        time.sleep(0.3)
        waiting = os.waitpid(writer, os.WNOHANG) == (0, 0)
        assert waiting and _program(folder) == [text for _, text in OLD]   # nothing moved
        assert not any(e.startswith(fileio.STAGE_PREFIX) for e in os.listdir(folder))
    finally:
        os.write(release[1], b"x")
        os.waitpid(holder, 0)
    assert os.WEXITSTATUS(os.waitpid(writer, 0)[1]) == 10
    assert _program(folder) == [text for _, text in NEW]
