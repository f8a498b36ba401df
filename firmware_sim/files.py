"""Reading a file the emulator is given (a world, a floor texture): a regular file only,
with a size bound.

A FIFO would make ``open`` wait forever for a writer and a device (``/dev/zero``) never
ends, so the file is opened without blocking and refused, with ValueError naming it and
the reason, unless it is a regular file of at most the bound. (The emulator is written
apart from ego, so this is its own small copy of ``ego.seam.files``.)
"""

from __future__ import annotations

import os
import stat

__all__ = ["read_regular"]

_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def _size(count: int) -> str:
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if count >= size and count % size == 0:
            return f"{count // size} {unit}"
    return f"{count} bytes"


def read_regular(path: str | os.PathLike[str], limit_bytes: int, what: str) -> bytes:
    """The whole of ``path``, a regular file of at most ``limit_bytes`` (``what`` names it
    in the refusal: "a world file"). A missing file raises the OSError as it is."""
    name = os.fspath(path)
    fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    with os.fdopen(fd, "rb") as file:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            kind = next((n for test, n in _KINDS if test(info.st_mode)), "not a regular file")
            raise ValueError(f"{name}: is {kind}, not a regular file")
        if info.st_size > limit_bytes:
            raise ValueError(f"{name}: {info.st_size} bytes is over the {_size(limit_bytes)} "
                             f"bound for {what}")  # fmt: skip
        data = file.read(limit_bytes + 1)  # one byte more tells a file that grew
    if len(data) > limit_bytes:
        raise ValueError(f"{name}: grew past the {_size(limit_bytes)} bound for {what} "
                         "while it was read")  # fmt: skip
    return data
