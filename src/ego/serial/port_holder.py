"""Which process holds a serial port open: for the message that refuses a second opener."""

from __future__ import annotations

import os
from pathlib import Path
from typing import NamedTuple

__all__ = ["PortHolder", "find_port_holder"]


class PortHolder(NamedTuple):
    pid: int
    #: Its command line, as ``ps`` shows it ("python -m ego run ctrl.py").
    command: str


def find_port_holder(port: str, proc: Path = Path("/proc")) -> PortHolder | None:
    """A process with ``port`` among its open files (another one first), or None.

    Linux only (it reads ``/proc/PID/fd``); processes of other users cannot be looked
    into, so None does not prove that nobody holds the port.
    """
    try:
        target = os.path.realpath(port)
        entries = sorted(proc.iterdir(), key=lambda p: p.name)
    except OSError:
        return None
    me = str(os.getpid())
    # This process last: a second Robot on the same port in one program holds it too.
    entries.sort(key=lambda p: p.name == me)
    for entry in entries:
        if not entry.name.isdigit():
            continue
        try:
            fds = list((entry / "fd").iterdir())
        except OSError:
            continue
        for fd in fds:
            try:
                if os.readlink(fd) != target:
                    continue
                raw = (entry / "cmdline").read_bytes()
            except OSError:
                continue
            command = raw.replace(b"\0", b" ").decode(errors="replace").strip()
            return PortHolder(int(entry.name), command or "?")
    return None
