"""Writing output files all-or-nothing (pure Python)."""

import os
import tempfile

from .errors import InputError


def write_files_atomically(output_dir, files):
    """Write every ``(filename, text)`` of `files` into `output_dir`, or none.

    Each file is written to a temporary file in `output_dir` first; only when
    all are written are they renamed into place, so a failure never leaves a
    half-written program behind.

    Parameters
    ----------
    output_dir : str
        Created if missing.
    files : list of (str, str or bytes)
        Bare file names (no directories) and their text (UTF-8) or bytes.

    Returns
    -------
    list of str
        Absolute paths written, in the order given.
    """
    output_dir = os.path.abspath(output_dir)
    for name, _ in files:
        if not name or os.path.basename(name) != name or name in (".", ".."):
            raise InputError("Output file name '%s' is not a plain file name." % name)
    try:
        os.makedirs(output_dir, exist_ok=True)
    except OSError as err:
        raise InputError("Cannot create output folder '%s': %s. Choose a writable folder."
                         % (output_dir, err.strerror)) from None
    umask = os.umask(0)
    os.umask(umask)
    temps = []
    try:
        for name, text in files:
            fd, tmp = tempfile.mkstemp(prefix="." + name + ".", suffix=".tmp", dir=output_dir)
            temps.append(tmp)
            data = text.encode("utf-8") if isinstance(text, str) else bytes(text)
            with os.fdopen(fd, "wb") as handle:
                handle.write(data)
                handle.flush()
                os.fsync(handle.fileno())
            os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give what open() would
        paths = []
        for (name, _), tmp in zip(files, temps):
            path = os.path.join(output_dir, name)
            os.replace(tmp, path)
            paths.append(path)
        return paths
    except OSError as err:
        raise InputError("Cannot write into '%s': %s. Choose a writable folder."
                         % (output_dir, err.strerror)) from None
    finally:
        for tmp in temps:
            if os.path.exists(tmp):
                os.remove(tmp)
