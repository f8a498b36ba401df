"""What a robot node admits before anything reaches its serial line (sans-I/O).

A query must carry its controller's id; a batch must be one of the robot's firmware and
at most 1 KiB; an ASCII command is ``V``, ``C``, ``S`` or ``K`` and asks for at most
:data:`MAX_ASCII_LINES` lines. Who holds the robot is the node's
:class:`~ego.servers.sessions.control.ControlSession`'s to say.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ego.errors import EgoError, ProtocolError, RobotBusyError
from ego.serial.protocol import parse_batch

if TYPE_CHECKING:
    from ego.seam.batch import Batch
    from ego.seam.profile import Profile
    from ego.servers.sessions.control import ControlSession

__all__ = [
    "ASCII_LETTERS",
    "MAX_ASCII_LINES",
    "MAX_BATCH_BYTES",
    "MAX_ID_BYTES",
    "check_ascii",
    "check_batch",
    "check_lease",
    "controller_id",
]

#: The longest batch a query may carry (a step of every command is under 100 bytes).
MAX_BATCH_BYTES = 1024
#: A controller's id: what its queries carry as their attachment (UTF-8, 1..64 bytes).
MAX_ID_BYTES = 64
#: The ASCII commands a node serves.
ASCII_LETTERS = ("V", "C", "S", "K")
#: The most lines an ASCII query may ask for: docs/protocol.md, ``V`` answers two, the
#: others one. Each line asked for beyond the reply holds the line one line timeout.
MAX_ASCII_LINES = 2


def check_lease(control: ControlSession[str], who: str, now: float, robot: str) -> None:
    """A query of ``who`` arrives at ``now``: RobotBusyError if another controller holds
    ``robot``; if ``who`` holds it, it was heard (nothing is taken until the query runs)."""
    if not control.admit(who, now):
        raise RobotBusyError(f"robot {robot} is driven by another controller")


def controller_id(attachment: bytes | None) -> str:
    """The controller id a query or put carries as its attachment (1..64 UTF-8 bytes)."""
    raw = attachment or b""
    try:
        who = raw.decode("utf-8")
    except UnicodeDecodeError:
        who = ""
    if not who or len(raw) > MAX_ID_BYTES:
        raise ProtocolError(
            f"a query must carry its controller's id (1..{MAX_ID_BYTES} UTF-8 bytes) as "
            f"attachment, not {len(raw)} bytes{' of UTF-8' if who else ''}"
        )
    return who


def check_batch(payload: bytes, profile: Profile) -> Batch:
    """The batch a query carries, if it is one of ``profile``'s firmware (ProtocolError)."""
    if not 0 < len(payload) <= MAX_BATCH_BYTES:
        raise ProtocolError(f"a batch of {len(payload)} bytes (1..{MAX_BATCH_BYTES} accepted)")
    try:
        return parse_batch(payload, profile)
    except (ValueError, EgoError) as exc:
        raise ProtocolError(f"not a batch: {exc}") from exc


def check_ascii(text: str) -> tuple[str, int]:
    """The letter and line count of an ASCII query ``LETTER[,LINES]`` (ProtocolError)."""
    letter, comma, lines = text.partition(",")
    if letter not in ASCII_LETTERS or (comma and not (lines.isascii() and lines.isdigit())):
        raise ProtocolError(f"ASCII command {text[:40]!r} refused: V, C, S or K, then ',LINES'")
    if not comma:
        return letter, 1
    if len(lines) > 4 or not 1 <= int(lines) <= MAX_ASCII_LINES:
        shown = lines if len(lines) <= 12 else f"{lines[:12]}... ({len(lines)} digits)"
        raise ProtocolError(f"ASCII command {letter!r} refused: it may ask for "
                            f"1..{MAX_ASCII_LINES} lines, not {shown}")  # fmt: skip
    return letter, int(lines)
