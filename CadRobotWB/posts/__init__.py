"""Post-processor registry: find a post by name, built-in or user-supplied.

A post-processor ("post") is a Python module that turns a core
:class:`~CadRobotWB.core.program.Program` into the text files of one robot
language. Every post defines

``NAME`` : str
    The name it is selected by, e.g. ``"abb_rapid"``.
``DESCRIPTION`` : str
    One line for ``cadrobot posts`` and the GUI.
``FILE_EXTENSIONS`` : tuple of str
    Extensions of the files it writes, e.g. ``(".mod",)``.
``export(program, options)``
    Pure function returning ``[(filename, text), ...]``.

and may define

``OPTIONS`` : dict of str to str
    Every option it reads, with one line of help. A post with ``OPTIONS``
    refuses any other option name (:func:`run`), so a typo is an error and
    not a silently ignored setting. ``date`` is every post's option.

Built-in posts are the modules of this package listed in :data:`BUILTIN`.
User posts are files ``<name>_post.py`` in folders the App layer passes in
as ``extra_dirs`` (the FreeCAD macro folder, a preference folder). Like
FreeCAD CAM, a user post shadows a built-in post of the same name, so a
copied and edited ``abb_rapid_post.py`` is the one used; among the folders,
the first one holding the name wins.

This module is pure Python: it never imports FreeCAD.
"""

import collections.abc
import hashlib
import importlib
import importlib.util
import inspect
import itertools
import os
import sys

from .. import command_line
from ..errors import CadRobotError, PostError, UnknownNameError
from . import output_check

#: Names of the built-in posts (modules of this package), in listing order.
BUILTIN = ("abb_rapid", "motoman_inform", "kuka_krl", "ur_script", "fanuc_ls")

#: File name ending that marks a user post in an extra folder.
USER_POST_SUFFIX = "_post.py"
#: Start of the private module name a user post is loaded under.
_USER_MODULE_PREFIX = "_cadrobot_user_post_"


def _user_post_files(extra_dirs):
    """Map the name of every user post found to its file.

    Parameters
    ----------
    extra_dirs : iterable of str or path-like
        Folders to search; missing folders and empty entries are skipped.

    Returns
    -------
    dict of str to str
        ``{name: path}``; for a name found in several folders the first
        folder wins.
    """
    found = {}
    for folder in extra_dirs:
        if not folder or not os.path.isdir(folder):
            continue
        for filename in sorted(os.listdir(folder)):
            if not filename.endswith(USER_POST_SUFFIX):
                continue
            name = filename[: -len(USER_POST_SUFFIX)]
            path = os.path.join(folder, filename)
            if name and name not in found and os.path.isfile(path):
                found[name] = path
    return found


def names(extra_dirs=()):
    """List the names of every available post-processor.

    Parameters
    ----------
    extra_dirs : iterable of str or path-like, optional
        Folders searched for user posts (``<name>_post.py``).

    Returns
    -------
    list of str
        Built-in names first (in :data:`BUILTIN` order), then user-only
        names, sorted. User posts are listed without being loaded, so a
        broken file is listed too and reported by :func:`get`.
    """
    user = _user_post_files(extra_dirs)
    return list(BUILTIN) + sorted(n for n in user if n not in BUILTIN)


def get(name, extra_dirs=()):
    """Load the post-processor called ``name``.

    Parameters
    ----------
    name : str
        A name from :func:`names`.
    extra_dirs : iterable of str or path-like, optional
        Folders searched for user posts (``<name>_post.py``); they are
        searched before the built-in posts.

    Returns
    -------
    module
        With ``NAME``, ``DESCRIPTION``, ``FILE_EXTENSIONS`` and ``export``.

    Raises
    ------
    UnknownNameError
        No post of that name exists.
    PostError
        A user post file cannot be loaded or does not define ``export``.
    """
    user = _user_post_files(extra_dirs)
    if name in user:
        return _load_user_post(name, user[name])
    if name in BUILTIN:
        return importlib.import_module(f"{__name__}.{name}")
    raise UnknownNameError(
        f"Unknown post-processor '{name}'. "
        f"Available: {', '.join(names(extra_dirs))}."
        + command_line.outside_gui(" `%s` describes them.", "posts")
    )


def run(module, program, options):
    """Run a post: check its option names, export, check what it returned.

    A user post runs contained: whatever it raises (``sys.exit`` too; only
    Ctrl-C's KeyboardInterrupt passes) is a PostError naming the post and its
    file. Every post's files are checked by
    :func:`.output_check.checked_files` before anything is written.

    Parameters
    ----------
    module : module
        From :func:`get`.
    program : CadRobotWB.core.program.Program
    options : dict

    Returns
    -------
    list of (str, str)
        File names and texts, in the post's order.

    Raises
    ------
    PostError
        An option the post does not have (when it declares ``OPTIONS``),
        whatever the post refuses, a user post that fails, or output that
        cannot be written as it is.
    """
    from . import common
    known = getattr(module, "OPTIONS", None)
    if known is not None:
        common.check_option_names(options, known, module.NAME)
    who = describe(module)
    if user_post_file(module) is None:
        returned = module.export(program, options)
    else:
        returned = _contained(who, lambda: _listed(module.export(program, options)))
    return output_check.checked_files(returned, who)


def user_post_file(module):
    """The file of a user post loaded by :func:`get`; None for a built-in post."""
    if module.__name__.startswith(_USER_MODULE_PREFIX):
        return module.__file__
    return None


def describe(module):
    """The post in messages: ``"User post-processor 'mine' (/p/mine_post.py)"`` or
    ``"Post-processor 'abb_rapid'"``."""
    path = user_post_file(module)
    if path is None:
        return "Post-processor '%s'" % module.NAME
    return _user_post_words(path)


def _user_post_words(path):
    """``"User post-processor 'mine' (/p/mine_post.py)"``: its name and its file."""
    return "User post-processor '%s' (%s)" % (os.path.basename(path)[:-len(USER_POST_SUFFIX)], path)


def _contained(who, call):
    """``call()``, with anything it raises but Ctrl-C made a PostError naming `who`.

    SystemExit (``sys.exit`` in a post) and other BaseExceptions are caught too:
    a post must not end FreeCAD or the CLI. A CadRobotError the post raises on
    purpose keeps its message and object, after `who`.
    """
    try:
        return call()
    except KeyboardInterrupt:
        raise
    except CadRobotError as err:
        raise PostError("%s: %s" % (who, err), err.obj_name) from err
    except BaseException as err:  # noqa: B036 -- a user's code may raise anything
        raise PostError("%s failed: %s. Fix the post, or choose another." % (who, _one_line(err))) \
            from err


def _listed(returned):
    """An iterable `returned` (a generator, say) as a list, so that its code runs here,
    contained; at most MAX_FILES + 1 items (an endless one is refused). What is no
    iterable of pairs is left for :func:`.output_check.checked_files` to refuse."""
    if isinstance(returned, (list, tuple, str, bytes, bytearray, dict)) \
            or not isinstance(returned, collections.abc.Iterable):
        return returned
    return list(itertools.islice(returned, output_check.MAX_FILES + 1))


def _one_line(err):
    """``"SystemExit(3)"``, ``"ValueError: bad value"``: an exception in one line."""
    kind = type(err).__name__
    if isinstance(err, SystemExit):
        return "%s(%r), it called sys.exit" % (kind, err.code)
    text = " ".join(str(err).split())
    return "%s: %s" % (kind, text) if text else kind


def _load_user_post(name, path):
    """Import a user post file under a private module name and check it.

    The module is in ``sys.modules`` only while its code runs (some
    libraries, e.g. dataclasses, look it up there) and is removed after,
    so loading the same file twice gives two fresh modules.

    Parameters
    ----------
    name : str
        The post name (file name without ``_post.py``).
    path : str
        The file.

    Returns
    -------
    module

    Raises
    ------
    PostError
        The file raises while loading or defines no callable ``export``.
    """
    path = os.path.abspath(path)
    digest = hashlib.sha1(path.encode("utf-8", "surrogateescape")).hexdigest()[:12]
    module_name = f"{_USER_MODULE_PREFIX}{name}_{digest}"
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise PostError(f"User post-processor file {path} cannot be loaded "
                        "as a Python module; rename it to <name>_post.py.")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    who = _user_post_words(path)
    try:
        _contained(who, lambda: spec.loader.exec_module(module))
    except PostError as err:
        raise PostError(f"{who} failed to load: {_one_line(err.__cause__)}. Fix or remove the "
                        "file.") from err.__cause__
    finally:
        sys.modules.pop(module_name, None)
    _check_entry(module, who)
    if not hasattr(module, "NAME"):
        module.NAME = name
    if not hasattr(module, "DESCRIPTION"):
        module.DESCRIPTION = f"User post-processor ({path})"
    if not hasattr(module, "FILE_EXTENSIONS"):
        module.FILE_EXTENSIONS = ()
    return module


def _check_entry(module, who):
    """PostError unless `module` has ``export(program, options)`` and, where it has
    them, ``NAME`` and ``DESCRIPTION`` that are str, ``FILE_EXTENSIONS`` a tuple of
    str and ``OPTIONS`` a dict of option name to help text."""
    export = getattr(module, "export", None)
    if not callable(export):
        raise PostError(f"{who} does not define export(program, options); add it or remove the "
                        "file.")
    try:
        inspect.signature(export).bind(None, None)
    except TypeError:
        raise PostError(f"{who}: its export{inspect.signature(export)} cannot be called as "
                        "export(program, options); give it those two parameters.") from None
    except ValueError:   # no signature to read (a builtin): it is called as it is
        pass
    for attribute, kind, must in (("NAME", str, "a str"), ("DESCRIPTION", str, "a str"),
                                  ("FILE_EXTENSIONS", tuple, "a tuple of str, e.g. ('.prg',)")):
        value = getattr(module, attribute, kind())
        if not isinstance(value, kind) or not all(isinstance(v, str) for v in value):
            raise PostError(f"{who}: {attribute} is {output_check.describe_value(value)}; it "
                            f"must be {must}.")
    options = getattr(module, "OPTIONS", None)
    if options is not None and not (isinstance(options, dict) and all(
            isinstance(k, str) and isinstance(v, str) for k, v in options.items())):
        raise PostError(f"{who}: OPTIONS is {output_check.describe_value(options)}; it must be "
                        "a dict of option name to one line of help, e.g. {'verbose': 'true or "
                        "false'}.")
