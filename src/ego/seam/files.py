"""Opening a file ego reads: a regular file only, read with a size bound.

A path may name a FIFO (whose open waits for a writer that never comes), a device
(``/dev/zero`` never ends) or a file far larger than anything it should hold. Every file
ego reads on a user's word (a recording, a camera configuration) goes through
:func:`open_regular` or :func:`read_regular`, which refuse those with one
:class:`~ego.errors.BadFileError` line naming the file and the reason, before reading
anything. A file that is missing or unreadable raises the operating system's
``OSError`` as it is.
"""

from __future__ import annotations

import fcntl
import os
import stat
from pathlib import Path
from typing import BinaryIO

from ego.errors import BadFileError

__all__ = ["BoundedReader", "describe_bytes", "open_regular", "read_regular"]

_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def describe_bytes(count: int) -> str:
    """``65536`` -> ``64 KiB``: a bound as a reader would write it."""
    for unit, size in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if count >= size and count % size == 0:
            return f"{count // size} {unit}"
    return f"{count} bytes"


def _kind(mode: int) -> str:
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def open_regular(path: str | os.PathLike[str], limit_bytes: int, what: str) -> BoundedReader:
    """``path`` opened for reading, once it is known to be a regular file of at most
    ``limit_bytes`` (``what`` names it in the refusal: "a recording")."""
    name = os.fspath(path)
    # O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
    fd = os.open(name, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise BadFileError(f"{name}: is {_kind(info.st_mode)}, not a regular file")
        if info.st_size > limit_bytes:
            raise BadFileError(
                f"{name}: {info.st_size} bytes is over the {describe_bytes(limit_bytes)} "
                f"bound for {what}"
            )
        fcntl.fcntl(fd, fcntl.F_SETFL, fcntl.fcntl(fd, fcntl.F_GETFL) & ~os.O_NONBLOCK)
        raw = os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
    return BoundedReader(raw, name, limit_bytes, what, info.st_size)


def read_regular(path: str | os.PathLike[str], limit_bytes: int, what: str) -> bytes:
    """The whole of a regular file of at most ``limit_bytes`` (see :func:`open_regular`)."""
    with open_regular(path, limit_bytes, what) as file:
        return file.read()


class BoundedReader:
    """A file read through a bound: reading past ``limit_bytes`` (a file that grows while
    it is read) raises BadFileError instead of going on."""

    def __init__(
        self, raw: BinaryIO, name: str, limit_bytes: int, what: str, size: int = 0
    ) -> None:
        #: The file's size when it was opened.
        self.size = size
        self.raw = raw
        self.name = name
        self.limit_bytes = limit_bytes
        self.what = what
        self.count = 0

    @property
    def path(self) -> Path:
        return Path(self.name)

    def read(self, size: int | None = -1) -> bytes:
        room = self.limit_bytes + 1 - self.count  # one byte more tells a file that grew
        data = self.raw.read(room if size is None or size < 0 else min(size, room))
        self.count += len(data)
        if self.count > self.limit_bytes:
            raise BadFileError(
                f"{self.name}: grew past the {describe_bytes(self.limit_bytes)} bound for "
                f"{self.what} while it was read"
            )
        return data

    def readall(self) -> bytes:
        return self.read(-1)

    def close(self) -> None:
        self.raw.close()

    def __enter__(self) -> BoundedReader:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()
