"""The five system calls V4L2 capture makes, as a seam: the protocol and the real thing.

Tests pass an in-process fake device instead of :class:`LinuxSyscalls`; it decodes the
same request numbers and struct bytes, so the capture code that runs is the robot's.
"""

from __future__ import annotations

import fcntl
import mmap
import os
import select
from typing import Protocol

from ego.camera.videodev2 import IoctlArg

__all__ = ["LinuxSyscalls", "V4L2Syscalls"]


class V4L2Syscalls(Protocol):
    """The five system calls capture needs; each raises ``OSError`` with the errno."""

    def open(self, path: str, flags: int) -> int: ...

    def ioctl(self, fd: int, request: int, arg: IoctlArg) -> None:
        """Run ``request``; the kernel reads and writes ``arg`` in place."""
        ...

    def mmap(self, fd: int, length: int, offset: int) -> mmap.mmap: ...

    def select(self, fd: int, timeout_s: float) -> bool:
        """Whether ``fd`` became readable (a frame is ready) within ``timeout_s``."""
        ...

    def close(self, fd: int) -> None: ...


class LinuxSyscalls:
    """The real thing: os.open, fcntl.ioctl, mmap.mmap, select.select, os.close."""

    def open(self, path: str, flags: int) -> int:
        return os.open(path, flags)

    def ioctl(self, fd: int, request: int, arg: IoctlArg) -> None:
        fcntl.ioctl(fd, request, arg, True)

    def mmap(self, fd: int, length: int, offset: int) -> mmap.mmap:
        prot = mmap.PROT_READ | mmap.PROT_WRITE
        return mmap.mmap(fd, length, mmap.MAP_SHARED, prot, offset=offset)

    def select(self, fd: int, timeout_s: float) -> bool:
        readable, _, _ = select.select([fd], [], [], timeout_s)
        return bool(readable)

    def close(self, fd: int) -> None:
        os.close(fd)
