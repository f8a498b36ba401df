"""Resident memory of a program under QEMU user-mode emulation, its guest's pages only.

qemu-arm passes the host's /proc/PID/smaps through: the emulator's own mappings (its code,
its translation cache) sit above 4 GiB, a 32-bit guest's below. Summing Rss below 4 GiB
counts what the program would hold on the board."""

from __future__ import annotations

GUEST_TOP = 1 << 32


def guest_rss_kb(pid: str = "self") -> int:
    """Resident kB of ``pid``'s mappings below 4 GiB (a 32-bit guest's address space)."""
    total = 0
    below = False
    with open(f"/proc/{pid}/smaps") as smaps:
        for line in smaps:
            head = line.split(maxsplit=1)[0]
            if "-" in head and not head.endswith(":"):
                below = int(head.split("-")[0], 16) < GUEST_TOP
            elif head == "Rss:" and below:
                total += int(line.split()[1])
    return total
