"""Writing a program's files all-or-nothing as a set (pure Python).

How a set of files is replaced in one step
------------------------------------------
A program of many files (a long KRL or INFORM program split into parts) must
never be left as a mix of two versions, even when the process is killed.
No single file-system call replaces several files, so the write is a journal
that only ever rolls forward:

1. every new file is written into a fresh hidden folder ``.cadrobot-writing-*``
   inside the output folder (same file system, so a rename moves it);
2. the list of its files, ``READY``, is written last: from then on the new set
   is complete on disk;
3. the files are renamed into place one by one, the files of the previous
   version that the new one no longer has are deleted (see below), and the
   hidden folder is removed.

Interrupted before step 2, the output folder still holds the previous program
and the hidden folder is only debris. Interrupted in step 3 by SIGINT or SIGTERM
(SIGTERM raises KeyboardInterrupt while a set is written), the renames are finished first,
so the folder holds the new program, complete. SIGKILL cannot be caught: killed
between two renames of step 3, the folder holds a mix until the next write into
it, which first finishes every ``READY`` set it finds and deletes the debris of
the others (:func:`finish_interrupted_writes`). Rolling forward needs no copy of
the old files, which is why this is simpler than keeping a backup to restore.

A set of several files also writes the list of its files and their SHA-256,
``.cadrobot-files-<first file>``. The next set with the same first file deletes
the files of that list it does not write again (a longer program split into more
parts before), unless they were changed since: a file CadRobot did not write, or
one the user edited, is never deleted. The deletions are lines ``/<name>`` of
``READY``, so a killed write finishes them too.

Two writes into one folder at once run one after the other (a lock on the folder).
"""

import contextlib
import hashlib
import os
import shutil
import signal
import tempfile
import threading

from .errors import InputError
from .posts import output_check

#: Prefix of the hidden folder a write stages its files in.
STAGE_PREFIX = output_check.RESERVED_PREFIX + "writing-"
#: The file, written last into a staging folder, that lists its complete set.
READY = output_check.WRITE_LIST_NAME
#: Prefix of the list of a set's files (the first file's name follows it).
MANIFEST_PREFIX = output_check.RESERVED_PREFIX + "files-"
#: What :func:`write_files_atomically` sets as ``program_left`` on an interrupt.
LEFT_PREVIOUS = "previous"
LEFT_NEW = "new"
#: Test-only: ``"<phase>:<k>:<INT|TERM|KILL>"`` sends that signal to this process the
#: k-th time (1-based) a write reaches `phase` ("staged" after each file, "ready",
#: "moved" after each rename). Read only by :func:`_test_signal`.
TEST_HOOK_VARIABLE = "CADROBOT_TEST_WRITE_SIGNAL"
_hook_counts = {}


def write_files_atomically(output_dir, files, inputs=()):
    """Write every ``(filename, text)`` of `files` into `output_dir`, all or none.

    See the module docstring for how the set is replaced in one step.

    Parameters
    ----------
    output_dir : str
        Created if missing.
    files : list of (str, str or bytes)
        Bare file names (no directories) and their text (UTF-8) or bytes.
    inputs : iterable of str, optional
        Files read to make `files` (the document): a file of `files` that is one
        of them (symlinks resolved) is refused before anything is written.

    Returns
    -------
    list of str
        Absolute paths written, in the order given.

    Raises
    ------
    InputError
        A bad file name, a file that is an input, an unwritable folder.
    KeyboardInterrupt
        Interrupted; its ``program_left`` is :data:`LEFT_PREVIOUS` or
        :data:`LEFT_NEW` and its ``output_dir`` the folder.
    """
    output_dir = os.path.abspath(output_dir)
    names = [name for name, _ in files]
    refuse_bad_names(names)
    refuse_inputs(output_dir, names, inputs)
    try:
        os.makedirs(output_dir, exist_ok=True)
    except OSError as err:
        raise InputError("Cannot create output folder '%s': %s. Choose a writable folder."
                         % (output_dir, err.strerror)) from None
    try:
        with _folder_lock(output_dir):
            finish_interrupted_writes(output_dir, names)
            staged, deleted = _with_manifest(output_dir, files)
            with _sigterm_as_interrupt():
                _replace_set(output_dir, staged, deleted)
    except OSError as err:
        raise InputError("Cannot write into '%s': %s. Choose a writable folder."
                         % (output_dir, err.strerror)) from None
    return [os.path.join(output_dir, name) for name in names]


def refuse_bad_names(names):
    """InputError for a name that is not a bare file name every OS accepts
    (:func:`.posts.output_check.file_name_problem`), or two names that are one file
    where case is ignored (Windows, macOS)."""
    seen = {}
    for name in names:
        problem = output_check.file_name_problem(name)
        if problem:
            raise InputError("Output file name %r is not a plain file name: %s. Nothing was "
                             "written." % (name, problem))
        key = output_check.same_file_key(name)
        if key in seen:
            raise InputError("Output files %r and %r are one file where case is ignored (Windows, "
                             "macOS). Nothing was written." % (seen[key], name))
        seen[key] = name


def refuse_inputs(output_dir, names, inputs):
    """InputError when writing `names` into `output_dir` would replace a file of `inputs`.

    Real paths are compared, so an output folder that is a symlink to the
    document's folder is caught too.
    """
    real_inputs = {os.path.realpath(path): path for path in inputs if path}
    real_dir = os.path.realpath(output_dir)
    for name in names:
        target = os.path.join(real_dir, name)
        for path in (target, os.path.realpath(target)):   # the file, or where its symlink points
            if path in real_inputs:
                raise InputError("Writing '%s' into '%s' would overwrite the input '%s'. Choose "
                                 "another output folder or program name; nothing was written."
                                 % (name, output_dir, real_inputs[path]))


def refuse_before_work(output_dir, inputs, names=()):
    """InputError, before a command's work, when its output folder is a file or a file it
    writes whatever happens would replace an input.

    The names known only after the work (a corrected program, split into parts by its
    length) are checked by :func:`write_files_atomically`, before anything is written.

    Parameters
    ----------
    output_dir : str
        The output folder: refused when it is an existing file (an input or not).
    inputs : iterable of str
        The files the command reads (the document).
    names : iterable of str
        The file names the command writes whatever happens (``report.json``).
    """
    inputs = [path for path in inputs if path]
    if os.path.exists(output_dir) and not os.path.isdir(output_dir):
        raise InputError("Cannot create output folder '%s': it is a file%s. Choose a folder; "
                         "nothing was written." % (output_dir, " (the input document)" if any(
                             os.path.samefile(output_dir, path) for path in inputs
                             if os.path.exists(path)) else ""))
    refuse_inputs(output_dir, names, inputs)


def finish_interrupted_writes(output_dir, names=()):
    """Finish or delete what an earlier, killed write left in `output_dir`.

    A staging folder with its ``READY`` list holds a complete program: its
    remaining files are moved into place. One without is deleted, as are the
    ``.<name>.*.tmp`` files of older versions of CadRobot for `names`.
    """
    for entry in sorted(os.listdir(output_dir)):
        path = os.path.join(output_dir, entry)
        if entry.startswith(STAGE_PREFIX) and os.path.isdir(path):
            _move_into_place(path, output_dir)   # removes it too when it has no READY
        elif entry.endswith(".tmp") and any(entry.startswith("." + name + ".") for name in names):
            os.remove(path)


def _with_manifest(output_dir, files):
    """The files to stage (`files` and, for a set of several, its manifest) and the
    names to delete once they are in place: the files of the previous set with
    the same first file that this one does not write and that are unchanged."""
    manifest_name = MANIFEST_PREFIX + files[0][0] if files else None
    previous = _read_manifest(os.path.join(output_dir, manifest_name)) if files else {}
    names = {name for name, _ in files}
    deleted = [name for name, digest in previous.items()
               if name not in names and _digest_of_file(os.path.join(output_dir, name)) == digest]
    if len(files) < 2:
        return list(files), deleted + ([manifest_name] if previous else [])
    manifest = "".join("%s  %s\n" % (_digest(text), name) for name, text in files)
    return list(files) + [(manifest_name, manifest)], deleted


def _read_manifest(path):
    """{name: SHA-256 hex} of a manifest; empty when there is none or it is damaged."""
    try:
        with open(path, encoding="utf-8") as handle:
            rows = [line.split("  ", 1) for line in handle.read().splitlines()]
    except (OSError, UnicodeDecodeError):
        return {}
    return {row[1]: row[0] for row in rows if len(row) == 2 and _is_plain_name(row[1])}


def _is_plain_name(name):
    return output_check.file_name_problem(name) is None


def _digest(text):
    return hashlib.sha256(text.encode("utf-8") if isinstance(text, str) else bytes(text)).hexdigest()


def _digest_of_file(path):
    try:
        with open(path, "rb") as handle:
            return hashlib.sha256(handle.read()).hexdigest()
    except OSError:
        return None


def _replace_set(output_dir, files, deleted=()):
    """Stage `files` in a fresh hidden folder of `output_dir`, then move them into
    place and delete the names `deleted` from `output_dir`.

    Interrupted while staging, the hidden folder is removed and the interrupt
    says the previous program is left; once the set is complete, the renames are
    finished first and it says the new program is left.
    """
    stage = tempfile.mkdtemp(prefix=STAGE_PREFIX, dir=output_dir)
    ready = os.path.join(stage, READY)
    complete = []   # not empty once READY is in place (a flag a signal cannot half-set)
    try:
        for name, text in files:
            _write_synced(os.path.join(stage, name), text)
            _test_signal("staged")
        _write_synced(ready + ".tmp", "".join(name + "\n" for name, _ in files)
                      + "".join("/" + name + "\n" for name in deleted))
        os.replace(ready + ".tmp", ready)
        complete.append(True)
        _sync_folder(stage)
        _test_signal("ready")
        _move_into_place(stage, output_dir)
    except BaseException as stop:
        if complete or os.path.exists(ready):
            _move_into_place(stage, output_dir)
            _say_what_is_left(stop, LEFT_NEW, output_dir)
        else:
            shutil.rmtree(stage, ignore_errors=True)
            _say_what_is_left(stop, LEFT_PREVIOUS, output_dir)
        raise


def _move_into_place(stage, output_dir):
    """Rename the files of the complete set in `stage` (its READY list) into
    `output_dir`, those not moved yet, delete its ``/<name>`` lines from
    `output_dir`; then remove `stage`."""
    ready = os.path.join(stage, READY)
    if os.path.exists(ready):
        with open(ready, encoding="utf-8") as handle:
            for name in handle.read().splitlines():
                if name.startswith("/"):
                    _remove_if_there(os.path.join(output_dir, name[1:]))
                else:
                    _move_if_there(stage, output_dir, name)
                    _test_signal("moved")
        _sync_folder(output_dir)
    shutil.rmtree(stage, ignore_errors=True)


@contextlib.contextmanager
def _folder_lock(output_dir):
    """Two writes into one folder run one after the other: an exclusive lock on the
    folder itself (POSIX ``flock``, so no lock file is left behind; none on Windows).
    Without it, a second write would take the first one's staging folder for debris."""
    try:
        import fcntl
        fd = os.open(output_dir, os.O_RDONLY)
    except (ImportError, OSError):
        yield
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)   # releases the lock


@contextlib.contextmanager
def _sigterm_as_interrupt():
    """SIGTERM raises KeyboardInterrupt inside the block, so that a terminated
    write also ends with one whole program; only in the main thread, the one
    Python delivers signals to."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL if previous is None else previous)


def _raise_interrupt(signum, frame):
    raise KeyboardInterrupt


def _move_if_there(stage, output_dir, name):
    source = os.path.join(stage, name)
    if os.path.exists(source):
        os.replace(source, os.path.join(output_dir, name))


def _remove_if_there(path):
    with contextlib.suppress(FileNotFoundError):
        os.remove(path)


def _write_synced(path, text):
    """Write `text` (str as UTF-8, or bytes) to `path` and flush it to disk."""
    data = text.encode("utf-8") if isinstance(text, str) else bytes(text)
    with open(path, "wb") as handle:
        handle.write(data)
        handle.flush()
        os.fsync(handle.fileno())


def _sync_folder(path):
    """Flush `path`'s entries (the renames in it) to disk (where a folder can be
    opened: not on Windows, whose NTFS journals renames itself)."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _say_what_is_left(stop, left, output_dir):
    """Tell an interrupt (KeyboardInterrupt) which program `output_dir` holds."""
    if isinstance(stop, KeyboardInterrupt) and not hasattr(stop, "program_left"):
        stop.program_left = left
        stop.output_dir = output_dir


def _test_signal(phase):
    """Test-only: send the signal :data:`TEST_HOOK_VARIABLE` asks for at `phase`."""
    wanted = os.environ.get(TEST_HOOK_VARIABLE)
    if not wanted:
        return
    hook_phase, count, name = wanted.split(":")
    _hook_counts[phase] = _hook_counts.get(phase, 0) + 1
    if hook_phase == phase and _hook_counts[phase] == int(count):
        os.kill(os.getpid(), getattr(signal, "SIG" + name))
