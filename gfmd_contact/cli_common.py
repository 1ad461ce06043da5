"""What the command line's subcommands share: SIGINT/SIGTERM as KeyboardInterrupt while work goes, notes on
stderr, and the argument types and options of several subcommands."""

from __future__ import annotations

import argparse
import contextlib
import signal
import sys


def _interrupted(signum, frame):
    raise KeyboardInterrupt


@contextlib.contextmanager
def interrupt_signals():
    """SIGINT and SIGTERM raise KeyboardInterrupt while a run goes, also in a process started in the
    background (a shell leaves SIGINT ignored there): `kill -INT` then stops it as Ctrl-C does."""
    previous = {s: signal.signal(s, _interrupted) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


def note(line):
    print(f"note: {line}", file=sys.stderr)


def count(minimum):
    """argparse type: an integer ≥ minimum."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{value} < {minimum}: must be an integer ≥ {minimum}")
        return value
    return parse


def seconds(text):
    """argparse type: a number of seconds ≥ 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"{text}: must be a number of seconds ≥ 0")
    return value


def wait_option(parser, what):
    """--wait [SECONDS]: wait for another process writing `what` instead of refusing at once."""
    parser.add_argument("--wait", nargs="?", type=seconds, const=-1, default=0, metavar="SECONDS",
                        help=f"if another process is writing the {what}, wait for it to end (at most SECONDS; "
                             "default: refuse at once, exit 2)")
