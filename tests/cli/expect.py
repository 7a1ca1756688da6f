"""Expectations for the command-line tests' inline Python checks: each that
fails is printed and counted, and done() exits with the count, so one run
reports every failed property. Import with PYTHONPATH=$SRC/tests/cli."""

failed = 0


def check(ok, what):
    """Counts and prints `what` when `ok` is false."""
    global failed
    if not ok:
        print(what)
        failed += 1


def done():
    raise SystemExit(failed)
