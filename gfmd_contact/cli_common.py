"""What the command line's subcommands share: SIGINT/SIGTERM as KeyboardInterrupt while work goes, and notes on
stderr."""

from __future__ import annotations

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
