"""One progress protocol for every long computation of the engine.

A long function takes ``progress=None``: a callable ``progress(fraction, text)``
with ``fraction`` in [0, 1] (of that function's work, never decreasing) and
``text`` saying what it is doing ("sampling moves").  The rule:

* the function calls it at its start, between stages and every few items of
  its long loops (often enough that a GUI stays live: vectorised code reports
  between its chunks);
* a callback that returns ``False`` (exactly False; None means go on) asks to
  stop: the function raises :class:`Cancelled` from that report, before it
  changes anything it was not going to throw away.  Functions that write into
  a document write only after their last report.

A function calling another long function gives it a sub-range of its own
scale with :func:`stage`, so the fractions its caller sees keep growing::

    def check(cell, progress=None):
        program = generate(cell, progress=stage(progress, 0.0, 0.3))
        report_now(progress, 0.3, "sampling moves")
        sampled = sample(program, progress=stage(progress, 0.3, 0.8))

A caller that cannot pass the callback (a GUI button that journals its API
call as a line of Python, so that a recorded macro replays it) sets it for the
calls made meanwhile with :func:`ambient`; the API's entry points take it when
they are given none (:func:`or_ambient`).

Pure Python: the core layers use it, and so do the App and GUI layers.
"""

import contextlib

from ..errors import CadRobotError

#: How many reports :class:`Steps` makes over a loop (at most).
REPORTS_PER_LOOP = 50


class Cancelled(CadRobotError):
    """The progress callback asked to stop; nothing was changed.

    The CLI ends with exit code 130 (as after Ctrl-C); the GUI says once that
    the work was cancelled.
    """

    exit_code = 130

    def __init__(self, message="Cancelled: nothing was changed.", obj_name=None):
        super().__init__(message, obj_name)


def report_now(progress, fraction, text=""):
    """Tell `progress` how far the work is; raise :class:`Cancelled` if it says stop.

    Parameters
    ----------
    progress : callable or None
        ``progress(fraction, text) -> bool or None``; None: nothing to tell.
    fraction : float
        Of the work, in [0, 1] (clipped).
    text : str
        What is being done, lower case, no full stop ("sampling moves").
    """
    if progress is not None and progress(min(max(float(fraction), 0.0), 1.0), text) is False:
        raise Cancelled()


def stage(progress, lo, hi):
    """A callback reporting into the sub-range [lo, hi] of `progress`.

    Parameters
    ----------
    progress : callable or None
    lo, hi : float
        The sub-range, 0 <= lo <= hi <= 1.

    Returns
    -------
    callable or None
        ``sub(fraction, text)`` calling ``progress(lo + fraction * (hi - lo),
        text)`` and returning what it returns; None when `progress` is None
        (so the called function can skip its reporting entirely).
    """
    if progress is None:
        return None
    lo, hi = float(lo), float(hi)

    def sub(fraction, text=""):
        return progress(lo + min(max(float(fraction), 0.0), 1.0) * (hi - lo), text)

    return sub


class Steps:
    """Reports over a loop of `total` items, every ``total / reports`` items.

    Parameters
    ----------
    progress : callable or None
    total : int
        Items in the loop.
    text : str
        What the loop does.
    reports : int
        How many reports at most over the whole loop (plus the first).

    Examples
    --------
    >>> steps = Steps(progress, len(moves), "sampling moves")
    >>> for i, move in enumerate(moves):
    ...     steps(i)          # raises Cancelled when progress says stop
    """

    def __init__(self, progress, total, text, reports=REPORTS_PER_LOOP):
        self.progress = progress
        self.total = max(int(total), 1)
        self.text = text
        self.every = max(1, self.total // max(int(reports), 1))

    def __call__(self, done):
        """Report `done` items of `total` finished (only every ``every`` items)."""
        if self.progress is not None and done % self.every == 0:
            report_now(self.progress, done / self.total, self.text)


_ambient = []            # callbacks set by ambient(), innermost last


@contextlib.contextmanager
def ambient(progress):
    """Within the block, API calls given no ``progress`` report to `progress`.

    Parameters
    ----------
    progress : callable or None
    """
    _ambient.append(progress)
    try:
        yield progress
    finally:
        _ambient.pop()


def or_ambient(progress):
    """`progress`, or the :func:`ambient` callback when `progress` is None."""
    if progress is not None or not _ambient:
        return progress
    return _ambient[-1]
