"""pytest plugin: several pytest processes share one queue of test files.

Loaded by ``tools/parallel_pytest.py`` in every worker (``-p pytest_file_queue``) with
``$CADROBOT_TEST_QUEUE`` naming a folder the workers share. Each worker collects every
test, then takes the files one at a time, longest first (``tests/durations.json``), and
runs the tests of the files it took. A file is taken by creating ``<queue>/<n>.claim``
with ``O_EXCL``, so exactly one worker runs it, and a worker that is done early takes
what is left: the slowest worker ends at most about one file after the others. A file's
tests run together and in order in one process, so module and session fixtures work as
in a plain run.

Each worker writes ``<queue>/seconds-<pid>.json``: {test file: seconds spent in it}.
"""

import json
import os
import time

QUEUE_VARIABLE = "CADROBOT_TEST_QUEUE"
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DURATIONS = os.path.join(REPO, "tests", "durations.json")
#: What an unmeasured file is taken to cost (s): new files start early, not last.
UNKNOWN_FILE_S = 60.0


def known_seconds():
    """{test file relative to the repository (``tests/app/test_x.py``): seconds} from
    tests/durations.json, or {}."""
    try:
        with open(DURATIONS, encoding="utf-8") as stream:
            return {key: float(value) for key, value in json.load(stream).items()}
    except (OSError, ValueError):
        return {}


def _file_of(item):
    """The test file of `item`, relative to the repository."""
    return os.path.relpath(str(item.path), REPO)


def _claim(queue, index):
    try:
        os.close(os.open(os.path.join(queue, "%d.claim" % index), os.O_CREAT | os.O_EXCL))
        return True
    except FileExistsError:
        return False


def pytest_runtestloop(session):
    queue = os.environ.get(QUEUE_VARIABLE)
    if not queue or session.config.option.collectonly:
        return None                                   # pytest's own loop
    if session.testsfailed and not session.config.option.continue_on_collection_errors:
        raise session.Interrupted("%d error%s during collection"
                                  % (session.testsfailed, "s" if session.testsfailed != 1 else ""))
    by_file = {}
    for item in session.items:
        by_file.setdefault(_file_of(item), []).append(item)
    seconds = known_seconds()
    # The same order in every worker (they all collect the same tests): longest first.
    order = sorted(by_file, key=lambda f: (-seconds.get(f, UNKNOWN_FILE_S), f))
    spent = {}

    def next_file(start):
        for index in range(start, len(order)):
            if _claim(queue, index):
                return index
        return None

    current = next_file(0)
    while current is not None:
        items = by_file[order[current]]
        following = None
        started = time.monotonic()
        for position, item in enumerate(items):
            if position + 1 < len(items):
                nextitem = items[position + 1]
            else:
                following = next_file(current + 1)
                nextitem = by_file[order[following]][0] if following is not None else None
            item.config.hook.pytest_runtest_protocol(item=item, nextitem=nextitem)
            if session.shouldfail:
                raise session.Failed(session.shouldfail)
            if session.shouldstop:
                raise session.Interrupted(session.shouldstop)
        spent[order[current]] = round(time.monotonic() - started, 1)
        current = following
    with open(os.path.join(queue, "seconds-%d.json" % os.getpid()), "w", encoding="utf-8") as out:
        json.dump(spent, out)
    return True
