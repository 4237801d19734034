"""What a post-processor returns, checked before anything is written.

Every post (built-in or the user's ``<name>_post.py``) returns
``[(file_name, text), ...]``; :func:`checked_files` refuses, in one line naming
the post, what it returned and what a post must return, anything else: not a
list of pairs, no files, too many, a name that is not a bare file name every OS
accepts (:func:`file_name_problem`), two names that are one file where case is
ignored, text that is not a ``str``, holds a NUL or cannot be written as UTF-8,
and more output than :data:`MAX_OUTPUT_BYTES`.

The file name rules live here (and :mod:`..fileio` applies them to every file
it writes); :func:`file_stem` makes a valid name out of any text.

Pure Python: never imports FreeCAD.
"""

import itertools
import re
import reprlib
import unicodedata

from ..errors import PostError

#: Most files one program may have.
MAX_FILES = 10_000
#: Most bytes (UTF-8) all files of one program may hold together: 100 MB.
MAX_OUTPUT_BYTES = 100_000_000
#: Longest file name, in bytes of UTF-8: file systems take 255, and :mod:`..fileio`
#: names the list of a set's files after its first file, with a prefix.
MAX_NAME_BYTES = 200

#: The file :mod:`..fileio` writes last beside a program's files while it writes them
#: (the list of a complete set): no program file may be called so, in any case.
WRITE_LIST_NAME = "READY"
#: How the names of :mod:`..fileio`'s own files and folders in an output folder start
#: (its staging folders, the lists of a set's files): no program file's may.
RESERVED_PREFIX = ".cadrobot-"

#: Names Windows keeps for devices: no file may be called so, in any case and
#: with any extension (``con.mod``, ``Aux.src.dat``).
WINDOWS_DEVICE_NAMES = frozenset(
    ["CON", "PRN", "AUX", "NUL"]
    + [port + digit for port in ("COM", "LPT") for digit in "123456789\u00b9\u00b2\u00b3"])

# Characters Windows refuses in a file name (and '/', which no OS takes).
_BAD_FILE_CHARACTERS = re.compile(r'[<>:"/\\|?*\x00-\x1f\x7f]')

#: What a post must return, the end of every refusal of :func:`checked_files`.
CONTRACT = ("a post must return a list of (file name, text) pairs: bare file names that "
            "Windows, macOS and Linux accept, text a str")

_short = reprlib.Repr()
_short.maxstring = _short.maxother = 40
_short.maxlist = _short.maxtuple = _short.maxdict = 3


def file_stem(text):
    """A file name stem Windows, macOS and Linux all accept, made from any text.

    Parameters
    ----------
    text : str
        A program or cell name, e.g. a label.

    Returns
    -------
    str
        `text` with ``<>:"/\\|?*`` and control characters replaced by
        ``_``, a trailing dot or blank replaced by ``_``, and ``_`` put
        after a Windows device name (:data:`WINDOWS_DEVICE_NAMES`, before
        the first dot): ``"a:b"`` -> ``"a_b"``, ``"x."`` -> ``"x_"``,
        ``"CON"`` -> ``"CON_"``, ``"aux.mod"`` -> ``"aux_.mod"``.  Text that
        is already valid comes back unchanged.
    """
    stem = _BAD_FILE_CHARACTERS.sub("_", str(text)) or "_"
    stem = re.sub(r"[. ]+$", lambda tail: "_" * len(tail.group()), stem)
    base, dot, rest = stem.partition(".")
    if base.rstrip(" ").upper() in WINDOWS_DEVICE_NAMES:
        stem = base + "_" + dot + rest
    return stem


def file_name_problem(name):
    """Why `name` cannot be the name of a file a program writes, or None.

    Parameters
    ----------
    name : object

    Returns
    -------
    str or None
        E.g. ``"it holds '/'"``; None for a bare file name Windows, macOS and
        Linux all accept, of at most :data:`MAX_NAME_BYTES` bytes.
    """
    if not isinstance(name, str):
        return "it is %s, not a str" % _type_phrase(name)
    if name in ("", ".", ".."):
        return "it is not a file name"
    try:
        size = len(name.encode("utf-8"))
    except UnicodeEncodeError as err:
        return "it holds %r, which is not valid Unicode" % err.object[err.start]
    bad = _BAD_FILE_CHARACTERS.search(name)
    if bad:
        return "it holds %r" % bad.group()
    if name[-1] in ". ":
        return "it ends in %r" % name[-1]
    if file_stem(name) != name:
        return "%s is a device name on Windows" % name.partition(".")[0].rstrip(" ")
    if size > MAX_NAME_BYTES:
        return "it is %d bytes long, more than %d" % (size, MAX_NAME_BYTES)
    key = same_file_key(name)
    if key == same_file_key(WRITE_LIST_NAME) or key.startswith(RESERVED_PREFIX):
        return "CadRobot's writing uses that name itself"
    return None


def same_file_key(name):
    """What two names have in common when they are one file on Windows and macOS
    (case ignored, Unicode normalised)."""
    return unicodedata.normalize("NFC", name).casefold()


def checked_files(returned, post):
    """The ``(file name, text)`` pairs a post returned, checked to be writable.

    Parameters
    ----------
    returned : object
        What the post's ``export`` returned; an iterator is consumed here
        (at most :data:`MAX_FILES` + 1 items).
    post : str
        The post in messages, e.g. ``"User post-processor 'mine' (/p/mine_post.py)"``.

    Returns
    -------
    list of (str, str)
        The pairs as tuples, in the post's order.

    Raises
    ------
    PostError
        One line: `post`, what it returned and what a post must return.
    """
    checked, seen, total = [], {}, 0
    for k, pair in enumerate(_pairs(returned, post), 1):
        name, text = _pair(pair, k, post)
        problem = file_name_problem(name)
        if problem:
            _refuse(post, "the file name %s (item %d), but %s" % (_repr(name), k, problem))
        key = same_file_key(name)
        if key in seen:
            _refuse(post, "the file name %s twice" % _repr(name) if seen[key] == name else
                    "the file names %s and %s, one file where case is ignored (Windows, macOS)"
                    % (_repr(seen[key]), _repr(name)), "each name must differ in more than case")
        seen[key] = name
        total += _text_size(text, name, post)
        if total > MAX_OUTPUT_BYTES:
            _refuse(post, "more than %d MB of text (at '%s')" % (MAX_OUTPUT_BYTES // 10 ** 6, name),
                    "a program holds at most %d bytes" % MAX_OUTPUT_BYTES)
        checked.append((name, text))
    return checked


def _pairs(returned, post):
    """`returned` as a list, if it is a list, tuple or iterator of at most MAX_FILES items."""
    if returned is None or isinstance(returned, (str, bytes, bytearray, dict)) \
            or not hasattr(returned, "__iter__"):
        _refuse(post, describe_value(returned))
    pairs = list(itertools.islice(returned, MAX_FILES + 1))
    if not pairs:
        _refuse(post, "no files", "at least one pair")
    if len(pairs) > MAX_FILES:
        _refuse(post, "more than %d files" % MAX_FILES, "a program has at most %d" % MAX_FILES)
    return pairs


def _pair(pair, k, post):
    if not isinstance(pair, (tuple, list)) or len(pair) != 2:
        _refuse(post, "%s as item %d, not a (file name, text) pair" % (describe_value(pair), k))
    return pair


def _text_size(text, name, post):
    """Bytes of `text` in UTF-8; PostError when it is not a str or holds a NUL or a
    lone surrogate."""
    if not isinstance(text, str):
        _refuse(post, "%s as the text of '%s'" % (_type_phrase(text), name))
    if "\x00" in text:
        _refuse(post, "a NUL character in the text of '%s' (line %d)"
                % (name, text.count("\n", 0, text.index("\x00")) + 1))
    if len(text) > MAX_OUTPUT_BYTES:   # before encoding a huge text
        return len(text)
    try:
        return len(text.encode("utf-8"))
    except UnicodeEncodeError as err:
        _refuse(post, "%r in the text of '%s' (line %d), which is not valid Unicode"
                % (err.object[err.start], name, text.count("\n", 0, err.start) + 1))


def _refuse(post, what, must=""):
    raise PostError("%s returned %s; %s%s." % (post, what, CONTRACT, (", " + must) if must else ""))


def describe_value(value):
    """`value` in one short line: its type, and its repr cut to about 40 characters."""
    if value is None:
        return "None"
    return "%s %s" % (_type_phrase(value), _repr(value))


def _repr(value):
    """repr of `value`, cut to about 40 characters, on one line (a user's own
    ``__repr__`` may raise or return anything)."""
    try:
        return "".join(c if c.isprintable() else "?" for c in _short.repr(value))
    except Exception:   # noqa: BLE001 -- the refusal must still be made
        return "<%s>" % type(value).__name__


def _type_phrase(value):
    """``"an int"``, ``"a str"``, ``"None"``."""
    if value is None:
        return "None"
    name = type(value).__name__
    return ("an " if name[:1].lower() in "aeiou" else "a ") + name
