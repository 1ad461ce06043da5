"""Surface height files read defensively: what the file is, its header and size before its content, and
never more than the scene needs.

A `.npy` file's header (numpy.lib.format: magic, then shape, dtype, order) is read first and its shape
compared with the scene's grid before one value is read: a 64-byte file that claims 10^12 values is refused
by its header. A text file is refused above `text_limit` bytes (what `nodes` heights with generous comments
take) and where its first bytes hold a NUL (binary junk under a text suffix) before it is read whole. A path
that is no regular file (a device such as /dev/zero, a FIFO, a dangling symbolic link) is refused by what
it is. Every refusal goes through the caller's `fail(problem)`, which raises a `SceneError` naming
surface.path (`gfmd_contact.core.topography_files`, `gfmd_contact.core.surfaces.from_file`).
"""

from __future__ import annotations

import os
import stat

import numpy as np

#: bytes a text file may hold per height (a number with 17 significant digits is < 30; the rest: comments)
TEXT_BYTES_PER_VALUE = 256
#: bytes a text file may hold besides its heights (a header comment)
TEXT_HEADER_BYTES = 64 * 1024
#: the first bytes of a text file searched for a NUL byte (binary content)
SNIFF_BYTES = 64 * 1024

_KINDS = ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a named pipe"),
          (stat.S_ISSOCK, "a socket"))


def check_regular_file(path, fail):
    """Refuse (`fail`) a path that is not a regular file, saying what it is; return its size (bytes)."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        fail("is a symbolic link to a missing file" if os.path.islink(path) else "no such file")
    except OSError as exc:
        fail(f"cannot be read ({exc.strerror or exc})")
    if stat.S_ISDIR(st.st_mode):
        fail("is a directory, not a file")
    if not stat.S_ISREG(st.st_mode):
        what = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
        fail(f"is {what}, not a regular file of heights")
    return st.st_size


class _Npz(Exception):
    """The file is a zip archive (numpy's .npz), not one array."""


def read_npy(path, shape, fail):
    """The array of a .npy file whose header says `shape` (checked before any value is read), else `fail`."""
    size = check_regular_file(path, fail)
    fmt = np.lib.format
    try:
        with open(path, "rb") as f:
            if f.read(4) == b"PK\x03\x04":
                raise _Npz
            f.seek(0)
            version = fmt.read_magic(f)
            if version not in ((1, 0), (2, 0)):
                raise ValueError(f"format version {version[0]}.{version[1]} is not read here (1.0 and 2.0 are)")
            header = (fmt.read_array_header_1_0 if version == (1, 0) else fmt.read_array_header_2_0)(f)
            offset = f.tell()
    except _Npz:
        fail("holds a NpzFile (an .npz archive of arrays), not an array")
    except (ValueError, EOFError) as exc:  # no magic, a corrupt header
        fail(f"not a valid .npy file ({_first(exc)})")
    except OSError as exc:
        fail(f"cannot be read ({exc.strerror or exc})")
    file_shape, _, dtype = header
    if dtype.hasobject or dtype.kind not in "iuf":
        fail(f"holds values of dtype {dtype}, not real numbers")
    if tuple(file_shape) != tuple(shape):
        return None, tuple(file_shape)  # the caller names the keys the shape must match
    if size < offset + int(np.prod(file_shape, dtype=np.int64)) * dtype.itemsize:
        fail(f"is truncated: {size} bytes, but its header announces an array of shape {tuple(file_shape)} "
             f"of {dtype}")
    try:
        return np.load(path, allow_pickle=False), tuple(file_shape)
    except (ValueError, EOFError) as exc:
        fail(f"not a valid .npy file ({_first(exc)})")


def _first(exc):
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def text_limit(nodes):
    """The most bytes a text file of `nodes` heights is read with (module docstring)."""
    return TEXT_HEADER_BYTES + TEXT_BYTES_PER_VALUE * int(nodes)


def read_text(path, nodes, fail, binary_hint=""):
    """The text of a heights file of `nodes` values: refused (`fail`) above `text_limit`, with a NUL byte in its
    first SNIFF_BYTES, or not UTF-8 (binary content; `binary_hint` says what else it may be)."""
    size = check_regular_file(path, fail)
    limit = text_limit(nodes)
    if size > limit:
        fail(f"is {size} bytes, more than the {limit} bytes a text file of surface.nodes = {nodes} heights may take "
             f"({TEXT_BYTES_PER_VALUE} per line); is it the right file?")
    try:
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except OSError as exc:
        fail(f"cannot be read ({exc.strerror or exc})")
    if b"\0" in data[:SNIFF_BYTES]:
        fail("not a text file (binary content: NUL bytes)" + binary_hint)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        fail("not a text file (binary content)" + binary_hint)
