#!/usr/bin/env python3
"""Run one test tier as several pytest processes sharing a queue of test files.

    /usr/bin/python3 tools/parallel_pytest.py [--workers N] [--tier NAME] [--timeout SEC]
        [--save-durations] TESTDIR [PYTEST ARGS...]

runs plain pytest (the core and install tiers); ``tools/run_pytest_in_freecad.py`` uses
:func:`run_tier` for pytest inside FreeCAD. Every worker collects the whole tier and takes
test files from the shared queue (``tools/pytest_file_queue.py``), longest first. Each
worker's output is printed after the run, one after the other, then one line::

    TIER: N passed, N failed, N skipped, N errors in S s (W workers)

and the machine-readable ``CADROBOT-TIER tier=... tests=... passed=... seconds=...`` that
``.ci/run`` reads for its table. The exit status is 0 when every worker passed (pytest's
5, "no tests", counts as a failure for the tier as a whole).

Workers: ``--workers``, else ``$CADROBOT_TEST_WORKERS``, else the number of CPUs this
process may use. ``--save-durations`` writes the seconds each file took to
``tests/durations.json`` (the queue's order; commit it when files were added or changed
much).
"""

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.realpath(os.path.abspath(__file__)))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import pytest_file_queue  # noqa: E402  (same folder)

PYTEST_NO_TESTS = 5
#: Seconds between the progress lines printed while the workers run (their own output
#: is printed whole at the end, so that two workers' tracebacks never interleave).
HEARTBEAT_S = 60.0
COUNT_WORDS = ("passed", "failed", "skipped", "error", "errors", "xfailed", "xpassed", "deselected")


def default_workers():
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:
        cpus = os.cpu_count() or 1
    return max(1, int(os.environ.get("CADROBOT_TEST_WORKERS") or cpus))


def test_files(testdir):
    """The test files under `testdir` (a file or a folder), sorted."""
    if os.path.isfile(testdir):
        return [testdir]
    found = []
    for root, _dirs, files in os.walk(testdir):
        found += [os.path.join(root, name) for name in files
                  if name.endswith(".py") and (name.startswith("test_") or name.endswith("_test.py"))]
    return sorted(found)


def closing_counts(output):
    """{word: count} of pytest's last summary line in `output` (``3 failed, 10 passed in 1s``)."""
    for line in reversed(output.splitlines()):
        line = line.strip().strip("=").strip()
        if re.search(r"\bin [0-9.]+s\b", line) and re.search(r"\d+ (%s)\b" % "|".join(COUNT_WORDS), line):
            counts = {}
            for number, word in re.findall(r"(\d+) (\w+)", line):
                if word in COUNT_WORDS:
                    word = "errors" if word == "error" else word
                    counts[word] = counts.get(word, 0) + int(number)
            return counts
    return {}


def run_tier(tier, commands, envs, timeout=None, save_durations=False):
    """Start one worker per command, wait for all, print their output and the summary.

    Parameters
    ----------
    tier : str
        Name for the summary line ("core", "App", "GUI", "install").
    commands : list of list of str
        One argv per worker; each runs pytest with ``-p pytest_file_queue`` (or
        ``-p tools.pytest_file_queue``) loaded.
    envs : list of dict
        The environment of each worker; the queue folder is added here.
    timeout : float, optional
        Seconds for the whole tier; workers still running then are killed.

    Returns
    -------
    int
        0 when every worker passed, else the first non-zero worker status.
    """
    started = time.monotonic()
    queue = tempfile.mkdtemp(prefix="cadrobot-queue-")
    logs, procs = [], []
    for number, (command, env) in enumerate(zip(commands, envs)):
        log = open(os.path.join(queue, "worker-%d.log" % number), "w+", encoding="utf-8",
                   errors="replace")
        env = dict(env, **{pytest_file_queue.QUEUE_VARIABLE: queue})
        # Each worker's own tmp_path root: pytest's shared numbered folders are cleaned
        # by whichever session starts, and several start together here.
        command = command + ["--basetemp", os.path.join(queue, "tmp-%d" % number)]
        procs.append(subprocess.Popen(command, env=env, cwd=REPO, stdout=log, stderr=subprocess.STDOUT,
                                      stdin=subprocess.DEVNULL, start_new_session=True))
        logs.append(log)
    codes = []
    try:
        for proc in procs:
            while True:
                elapsed = time.monotonic() - started
                left = None if timeout is None else max(1.0, timeout - elapsed)
                try:
                    codes.append(proc.wait(timeout=min(HEARTBEAT_S, left or HEARTBEAT_S)))
                    break
                except subprocess.TimeoutExpired:
                    if left is not None and left <= HEARTBEAT_S:
                        _kill(proc)
                        codes.append(124)
                        break
                    taken = sum(name.endswith(".claim") for name in os.listdir(queue))
                    print("%s: %.0f s, %d test files started, %d of %d workers running"
                          % (tier, elapsed + HEARTBEAT_S, taken,
                             sum(p.poll() is None for p in procs), len(procs)), flush=True)
    except KeyboardInterrupt:
        for proc in procs:
            _kill(proc)
        raise
    totals, spent = {}, {}
    for number, log in enumerate(logs):
        log.seek(0)
        output = log.read()
        log.close()
        if len(logs) > 1:
            print("----- %s worker %d of %d (exit %d)" % (tier, number + 1, len(logs), codes[number]))
        sys.stdout.write(output if output.endswith("\n") or not output else output + "\n")
        for word, count in closing_counts(output).items():
            totals[word] = totals.get(word, 0) + count
    for name in os.listdir(queue):
        if name.startswith("seconds-"):
            with open(os.path.join(queue, name), encoding="utf-8") as stream:
                spent.update(json.load(stream))
    seconds = time.monotonic() - started
    code = next((c for c in codes if c not in (0, PYTEST_NO_TESTS)), 0)
    tests = sum(totals.get(w, 0) for w in ("passed", "failed", "errors", "xfailed", "xpassed"))
    if code == 0 and tests == 0:
        code = PYTEST_NO_TESTS
    words = ["%d %s" % (totals.get(w, 0), w) for w in ("passed", "failed")]
    words += ["%d %s" % (totals[w], w) for w in ("skipped", "errors", "xfailed", "xpassed")
              if totals.get(w)]
    print("%s: %s in %.0f s (%d worker%s)" % (tier, ", ".join(words), seconds, len(procs),
                                             "" if len(procs) == 1 else "s"))
    print("CADROBOT-TIER tier=%s tests=%d passed=%d failed=%d skipped=%d seconds=%.0f code=%d" % (
        tier, tests, totals.get("passed", 0), totals.get("failed", 0) + totals.get("errors", 0),
        totals.get("skipped", 0), seconds, code))
    slowest = sorted(spent.items(), key=lambda kv: -kv[1])[:5]
    if slowest:
        print("%s: slowest files: %s" % (tier, ", ".join("%s %.0f s" % (os.path.basename(f), s)
                                                          for f, s in slowest)))
    if save_durations and spent:
        known = pytest_file_queue.known_seconds()
        known.update(spent)
        with open(pytest_file_queue.DURATIONS, "w", encoding="utf-8") as out:
            json.dump(dict(sorted(known.items())), out, indent=1)
            out.write("\n")
    shutil.rmtree(queue, ignore_errors=True)
    sys.stdout.flush()
    return code


def _kill(proc):
    import signal
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(proc.pid, sig)
            proc.wait(timeout=10)
            return
        except ProcessLookupError:
            return
        except subprocess.TimeoutExpired:
            continue


def parse_options(argv, flags=("--save-durations",), valued=("--workers", "--tier", "--timeout")):
    """Leading options of `argv` -> ({option: value or True}, the rest)."""
    options, argv = {}, list(argv)
    while argv and (argv[0] in flags or argv[0] in valued):
        name = argv.pop(0)
        options[name] = argv.pop(0) if name in valued else True
    return options, argv


def worker_count(options, testdir):
    return max(1, min(int(options.get("--workers") or default_workers()),
                      len(test_files(testdir)) or 1))


def main(argv=None):
    options, argv = parse_options(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0].startswith("-"):
        sys.stderr.write(__doc__.split("\n\n")[1] + "\n")
        return 2
    testdir = argv[0]
    if not test_files(testdir):
        sys.stderr.write("parallel_pytest: no test files in %s -- failing, a tier must run tests\n"
                         % testdir)
        return PYTEST_NO_TESTS
    workers = worker_count(options, testdir)
    command = [sys.executable, "-m", "pytest", "-p", "pytest_file_queue", "-p", "no:cacheprovider"] + argv
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (HERE, env.get("PYTHONPATH")) if p)
    timeout = float(options["--timeout"]) if "--timeout" in options else None
    return run_tier(options.get("--tier") or os.path.basename(os.path.normpath(testdir)),
                    [command] * workers, [env] * workers, timeout=timeout,
                    save_durations="--save-durations" in options)


if __name__ == "__main__":
    sys.exit(main())
