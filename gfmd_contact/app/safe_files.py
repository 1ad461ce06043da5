"""One writer per directory, atomic writes, and write errors that name the path.

`DirLock(directory)` holds an exclusive `fcntl.flock` on DIR/.gfmd.lock while a process writes
DIR; the file names the holder (host, pid, start time, command). A second process is refused
at once (`LockHeld`, the holder named) or waits (`wait`: seconds, or None/-1 for ever). A lock
file left by a process that ended without releasing it (kill -9, OOM killer, node failure) has a
free flock: it is taken over and `DirLock.took_over` says whose it was. The kernel releases a
flock when its holder's last descriptor closes, so a dead process never holds one; children that
inherited the descriptor (a forked pool worker) do, until they end (`die_with_parent`).
On release the lock file is removed (an acquirer checks that the file it locked is still the
one at the path, so removal cannot let two holders in).

`atomic_write(path, data)` writes to a temporary name in the same directory and publishes it with
`os.replace`; `append_line` appends and flushes one CSV row. Any OSError there (no space, quota,
file-size limit, read-only or unwritable directory) becomes `WriteFailed`, one line that names the
path; the file that was there before is untouched.
"""

from __future__ import annotations

import contextlib
import errno
import io
import json
import os
import socket
import sys
import tempfile
import time
from pathlib import Path

try:
    import fcntl
except ImportError:  # not POSIX: no locking (docs/guide/long_runs.rst)
    fcntl = None

LOCK_NAME = ".gfmd.lock"
#: why a write fails, in words (errno → text)
_WHY = {errno.ENOSPC: "no space left on the device", errno.EDQUOT: "disk quota exceeded",
        errno.EFBIG: "file larger than the file-size limit (ulimit -f)", errno.EROFS: "read-only file system",
        errno.EACCES: "permission denied", errno.EPERM: "operation not permitted"}


#: errors of the disk, not of one file: a study stops on them (exit 2) instead of failing one task
DISK_ERRNOS = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS})


class WriteFailed(OSError):
    """A file could not be written: the message names it and why (one line); code: the errno."""

    def __init__(self, message, code=None):
        super().__init__(message)
        self.code = code

    def __reduce__(self):  # through a process pool or Dask with its code
        return type(self), (str(self), self.code)


class LockHeld(OSError):
    """Another live process holds the directory's lock: the message names it and what to do."""


class DanglingLink(OSError):
    """The directory to write is a symbolic link to a path that does not exist: the message says which."""


def _why(exc):
    return _WHY.get(exc.errno, exc.strerror or str(exc))


@contextlib.contextmanager
def writing(path):
    """Turn an OSError raised inside into `WriteFailed` naming `path`."""
    try:
        yield
    except WriteFailed:
        raise
    except OSError as exc:
        name = errno.errorcode.get(exc.errno, "")
        raise WriteFailed(f"cannot write {path}: {_why(exc)}{f' ({name})' if name else ''}", exc.errno) from exc


def file_mode():
    """Permissions of a new file under the process umask (mkstemp alone would give 0600)."""
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write(path, data, binary=False):
    """Write `data` (str or bytes) to `path` through a temporary name and os.replace."""
    path = Path(path)
    tmp = None
    with writing(path):
        try:
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            with os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(data)
            os.chmod(tmp, file_mode())
            os.replace(tmp, path)
        except BaseException:
            if tmp is not None and os.path.exists(tmp):
                os.unlink(tmp)
            raise


def save_figure(fig, path, **kwargs):
    """fig.savefig into memory, then `atomic_write` to `path` (a figure is never left half-written)."""
    buf = io.BytesIO()
    buf.name = str(path)  # what the figure is for (a file object's name, as open() gives)
    fig.savefig(buf, **kwargs)
    atomic_write(path, buf.getvalue(), binary=True)


def append_line(path, line, header=None):
    """Append `line` (+ newline) to a text file, writing `header` first if the file is new; flushed."""
    path = Path(path)
    with writing(path):
        new = not path.is_file()
        with open(path, "a") as fh:
            if new and header is not None:
                fh.write(header + "\n")
            fh.write(line + "\n")
            fh.flush()
        if new:
            os.chmod(path, file_mode())


# ---------------------------------------------------------------- processes

def die_with_parent():
    """In a forked worker: be killed (SIGKILL) when the parent dies, as by kill -9 (Linux prctl
    PR_SET_PDEATHSIG), so no orphan goes on writing the run directory; elsewhere a no-op."""
    import signal

    parent = os.getppid()
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:  # the parent died before prctl
        os._exit(1)


def process_command():
    """This process's command line as typed: `python -m gfmd ARGS` reads "gfmd ARGS"."""
    name = Path(sys.argv[0]).name if sys.argv and sys.argv[0] else "python"
    return " ".join(["gfmd" if name in ("gfmd", "__main__.py") else name] + sys.argv[1:])


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


# ---------------------------------------------------------------- the lock

def describe_holder(info):
    """'pid 123 on host h, started 2026-…, command "gfmd run …"' from the lock file's dict."""
    if not info:
        return "an unknown process (its lock file names none)"
    return (f"pid {info.get('pid')} on host {info.get('host')}, started {info.get('started')}, "
            f"command {info.get('command')!r}")


def _read_info(path):
    try:
        text = Path(path).read_text()
        return json.loads(text) if text.strip() else {}
    except (OSError, ValueError):
        return {}


class DirLock:
    """Exclusive lock on a directory while this process writes it (module docstring).

    what: how the directory is named in messages ("run directory", "study directory", ...);
    advice: what the refused user may do (appended to the message).
    """

    def __init__(self, directory, what="directory", command=None, advice=None):
        self.directory = Path(directory)
        self.path = self.directory / LOCK_NAME
        self.what = what
        self.command = command or process_command()
        self.advice = advice or "wait for it to end (or add --wait), or stop it first"
        self.took_over = None  # the holder dict of a lock left by a process that ended without releasing it
        self._fd = None

    def _try(self):
        """Lock the file at self.path without blocking; True if locked (and it is still that path's file)."""
        fd = os.open(self.path, os.O_RDWR | os.O_CREAT, file_mode())
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as exc:
            os.close(fd)
            if exc.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
                return False
            raise
        try:
            same = os.fstat(fd).st_ino == os.stat(self.path).st_ino
        except FileNotFoundError:
            same = False
        if not same:  # the holder released (and removed) it between our open and flock: try again
            os.close(fd)
            return None
        self._fd = fd
        return True

    def acquire(self, wait=0):
        """Take the lock; wait: 0 refuse at once (LockHeld), seconds, or None / a negative number: for ever."""
        if fcntl is None:
            return self
        if self.directory.is_symlink() and not self.directory.exists():
            target = os.readlink(self.directory)
            raise DanglingLink(f"{self.directory}: the {self.what} is a symbolic link to {target!r}, which does not "
                               f"exist: create {target!r} (a directory), or choose another directory")
        with writing(self.path):
            self.directory.mkdir(parents=True, exist_ok=True)
        deadline = None if wait is None or wait < 0 else time.monotonic() + wait
        grace = None
        while True:
            with writing(self.path):
                got = self._try()
            if got:
                break
            if got is None:
                continue
            info = _read_info(self.path)
            if info.get("host") == socket.gethostname() and info.get("pid") and not _alive(info["pid"]):
                # the holder is gone, processes it started still hold the descriptor: they die with it
                grace = grace or time.monotonic() + 10
                if time.monotonic() < grace:
                    time.sleep(0.05)
                    continue
                raise LockHeld(f"{self.directory}: the {self.what} is locked by processes started by "
                               f"{describe_holder(info)}, which has ended; they still run: stop them first")
            if deadline is not None and time.monotonic() >= deadline:
                waited = f" (waited {wait:g} s)" if wait else ""
                raise LockHeld(f"{self.directory}: the {self.what} is being written by {describe_holder(info)}"
                               f"{waited}: {self.advice}")
            time.sleep(0.2)
        left = _read_info(self.path)
        if left and left.get("pid") != os.getpid():
            self.took_over = left
        info = {"host": socket.gethostname(), "pid": os.getpid(),
                "started": time.strftime("%Y-%m-%dT%H:%M:%S%z"), "command": self.command}
        os.ftruncate(self._fd, 0)
        os.pwrite(self._fd, json.dumps(info).encode(), 0)
        return self

    def took_over_note(self):
        """One line if the lock was taken over from a process that ended without releasing it, else None."""
        if not self.took_over:
            return None
        return (f"{self.directory}: took over the lock of {describe_holder(self.took_over)}, which ended without "
                "releasing it")

    def release(self):
        if self._fd is None:
            return
        try:
            os.unlink(self.path)  # before unlocking: a waiter that locked the removed file tries again
        except OSError:
            pass
        fcntl.flock(self._fd, fcntl.LOCK_UN)
        os.close(self._fd)
        self._fd = None

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()


@contextlib.contextmanager
def locked(directory, wait=0, what="directory", command=None, advice=None, note=None):
    """Context manager: `DirLock(...).acquire(wait)`; a take-over is reported through note(line)."""
    lock = DirLock(directory, what=what, command=command, advice=advice).acquire(wait)
    try:
        if note is not None and lock.took_over_note():
            note(lock.took_over_note())
        yield lock
    finally:
        lock.release()
