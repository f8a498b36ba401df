"""One batch per step over a transport: exact-length replies, resynchronisation, bounded retries.

The e-puck link has no checksum: the reply length is the only integrity check there is
(docs/protocol.md). So the link reads exactly the bytes a batch asks for, with a timeout,
watches for bytes left over after them, and never waits for a reply that the batch
does not produce. On a short or overlong reply it resynchronises (a few zeros, then
drains until the line is quiet) and sends the batch again, a bounded number of times,
before raising a typed error.

A dsPIC that restarted (its banner arrived) or a port that went away and came back
cannot simply be retried: the robot has lost its actuator state. The link then
re-detects the firmware and raises :class:`~ego.errors.RobotResetError`, so that its
owner re-applies that state and builds the batch again.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass

from ego.errors import (
    ExtraBytesError,
    LineFloodedError,
    LinkLostError,
    LinkTimeoutError,
    PortNotFoundError,
    ProtocolError,
    RobotResetError,
    ShortReplyError,
)
from ego.seam.batch import Batch
from ego.seam.channel import ChannelBase, FirmwareInfo, LinkStats, reconnect_within
from ego.seam.profile import DEFAULT_BAUD, Firmware, Profile
from ego.serial.probe import probe_firmware
from ego.serial.profiles import BANNER_END, BANNER_MARKER, BANNER_START, PROFILES, wire_time_s
from ego.serial.transport import Transport

__all__ = [
    "Link",
    "LinkSettings",
    "LinkStats",
    "banner_rest",
    "drain_line",
    "read_lines",
    "reply_timeout_s",
]

log = logging.getLogger(__name__)

#: docs/protocol.md: "sending a few zeros is the way to resynchronise". Eight complete any
#: pending D/P arguments (4 bytes) and still end a batch.
RESYNC_ZEROS = b"\x00" * 8
#: Zeros cannot end an ASCII line: a desynchronised stream (a D misread as L, say) can
#: leave a positive byte outside a batch, and asercom then reads a line until ``\n`` or
#: ``\r``, swallowing every later batch. A newline ends such a line; a dsPIC that was idle
#: instead skips it and takes the next byte as a line's first, so a harmless ``V`` line
#: follows. Either way the dsPIC ends up idle, and the drain discards what it answered.
RESYNC = RESYNC_ZEROS + b"\nV\n"
#: How the answer to that ``V`` starts (docs/protocol.md: ``v,Version ...``).
VERSION_REPLY = b"v,Version"


#: The trailing guard in byte times: a 4-byte burst, and two byte times of wake-up margin.
TRAILING_GUARD_BYTES = 6


@dataclass(frozen=True, slots=True)
class LinkSettings:
    """Timeouts and bounds of the link; the defaults suit the 230400-baud Overo line."""

    #: Attempts after the first before a fault is raised to the caller.
    retries: int = 3
    #: A reply may take this long beyond ``wire_factor`` x its wire time.
    reply_timeout_s: float = 0.025
    #: The thesis measured 84 us/byte against a 43.4 us/byte wire: allow 3x.
    wire_factor: float = 3.0
    #: After the last expected byte, how long to watch for bytes that should not be
    #: there. Extra bytes come at line rate right behind the reply, but a UART driver
    #: hands them over in bursts (a FIFO's trigger level, 4 bytes in the emulator), so
    #: None watches for TRAILING_GUARD_BYTES byte times at the line's rate (260 us at
    #: 230400 baud). A heuristic bounded in time, as no protocol field can do better; a
    #: byte later still is caught as stale before the next batch.
    trailing_guard_s: float | None = None
    #: Resynchronising drains until the line has been quiet this long ...
    resync_quiet_s: float = 0.1
    #: ... but never longer than this, nor more bytes than ``resync_max_bytes``: a line
    #: still sending then is flooded (LineFloodedError, at once, no retry).
    resync_max_s: float = 1.0
    resync_max_bytes: int = 1 << 16
    #: How long a resynchronisation waits for the answer to its own ``V`` (which proves
    #: that every late byte before it is in) before it settles for a quiet line.
    resync_marker_s: float = 0.25
    #: How long a lost port may take to come back before the link is lost for good.
    reconnect_timeout_s: float = 3.0
    #: How long to wait for each line of an ASCII reply (V, C, S...).
    line_timeout_s: float = 0.3

    def trailing_guard_at(self, baud: int) -> float:
        """The trailing guard on a line that runs at ``baud``."""
        if self.trailing_guard_s is not None:
            return self.trailing_guard_s
        return wire_time_s(TRAILING_GUARD_BYTES, baud)


def read_lines(transport: Transport, lines: int, timeout_s: float) -> list[str]:
    """Up to ``lines`` non-empty reply lines, each within ``timeout_s``; fewer if the
    firmware falls silent."""
    replies: list[str] = []
    while len(replies) < lines:
        raw = transport.read_line(timeout_s + transport.latency_s)
        if not raw.endswith(b"\n"):
            break
        text = raw.decode("ascii", errors="replace").strip()
        if text:
            replies.append(text)
    return replies


def banner_rest(data: bytes) -> bytes:
    """What is still to come of the banner's start when ``data`` ends with at least its
    first three bytes (fewer are too common in sensor values to wait on); else b"".
    A reply that ends so was cut short by a dsPIC reset whose banner is late (a loaded
    machine, a USB hub): read as it is, its step would take the banner's first bytes
    for its values."""
    for size in range(len(BANNER_START) - 1, 2, -1):
        if data.endswith(BANNER_START[:size]):
            return BANNER_START[size:]
    return b""


def drain_line(transport: Transport, settings: LinkSettings, until: bytes = b"") -> bytes:
    """Read until ``until`` has arrived (if given, within ``settings.resync_marker_s``),
    then until the line is quiet (``resync_quiet_s``), all within ``resync_max_s`` and
    ``resync_max_bytes``. A line still sending when either runs out never stops (a
    flood): LineFloodedError, and what it sent is dropped (issue 32)."""
    start = time.monotonic()
    deadline = start + settings.resync_max_s
    marker_deadline = start + min(settings.resync_marker_s, settings.resync_max_s)
    limit = settings.resync_max_bytes
    drained = bytearray()
    while until and until not in drained and len(drained) < limit:
        remaining = marker_deadline - time.monotonic()
        byte = transport.read(1, remaining) if remaining > 0 else b""
        if not byte:
            break
        drained += byte + transport.pending()
    if len(drained) < limit:
        remaining = max(0.0, deadline - time.monotonic())
        drained += transport.drain(settings.resync_quiet_s, remaining, limit - len(drained))
    if len(drained) >= limit or time.monotonic() >= deadline:
        raise LineFloodedError(
            f"{transport.name}: the line never went quiet ({len(drained)} bytes in "
            f"{time.monotonic() - start:.2f} s; at most {limit} bytes or "
            f"{settings.resync_max_s:g} s): something on it never stops sending"
        )
    return bytes(drained)


def reply_timeout_s(
    batch: Batch, profile: Profile, transport: Transport, settings: LinkSettings
) -> float:
    """Reply timeout of a batch: its wire time and the dsPIC's work, scaled, plus slack.

    The wire time counts the batch's bytes both ways at the slower of the port's rate and
    the rate the firmware answers at (docs/protocol.md, Line: Webots' firmware speaks
    115200 baud only, whatever the port was opened at); the dsPIC's work is the profile's
    time per command (an I2C read for ``M``, software floats for ``A``).
    """
    baud = min(transport.baudrate or DEFAULT_BAUD, profile.line_baud)
    wire = wire_time_s(len(batch.tx) + batch.reply_size, baud)
    work = sum(profile.work_s.get(r.command, 0.0) for r in batch.requests)
    return settings.reply_timeout_s + settings.wire_factor * (wire + work) + transport.latency_s


class Link(ChannelBase):
    """The dsPIC behind a transport, spoken to one batch per step.

    >>> link = Link(SerialTransport("/dev/ttyS0"))        # doctest: +SKIP
    >>> batch = encode_batch([Request(Command.PROXIMITY)], link.profile)
    >>> (ps,) = batch.decode(link.exchange(batch))
    """

    def __init__(
        self,
        transport: Transport,
        firmware: Firmware | str | None = None,
        settings: LinkSettings | None = None,
    ) -> None:
        super().__init__()
        self.transport = transport
        self.settings = settings or LinkSettings()
        self._forced = Firmware.choose(firmware)
        #: The last bytes seen, for a banner split across two reads.
        self._tail = b""
        #: A restart seen while answering an ASCII command, not yet told to the owner.
        self._unreported_restart = False
        #: Until the firmware is known, timeouts assume the slower of the two lines.
        self._info = FirmwareInfo(PROFILES[Firmware.WEBOTS], detected=False)
        self._info = self._identify(first=True)
        self._unreported_restart = False  # at open there is no state to re-apply

    @property
    def name(self) -> str:
        return self.transport.name

    def waiting_until(self, deadline_s: float) -> None:
        """The owner waits out a step (the Channel seam); the transport may care."""
        self.transport.waiting_until(deadline_s)

    def _identify(self, first: bool = False) -> FirmwareInfo:
        """Drain the welcome banner, then ask the firmware (unless told it): ``probe.py``."""
        bounds = self.settings
        self.transport.drain(bounds.resync_quiet_s, bounds.resync_max_s, bounds.resync_max_bytes)
        self._tail = b""
        if self._forced is not None:
            return FirmwareInfo(PROFILES[self._forced], detected=False)
        return probe_firmware(self, first)

    def _ascii_command(
        self, letter: str, lines: int, line_timeout_s: float | None = None
    ) -> list[str]:
        """Send an ASCII command (``V``, ``S``, ``C``...) and return its reply lines.

        Fewer lines than asked come back when the firmware stays silent; a first line
        that does not start with the command's lower-case letter raises ProtocolError.
        ``line_timeout_s`` overrides the settings' wait for each line (for ``K``, whose
        last line comes only after the calibration).
        """
        command = letter.encode("ascii") + b"\n"
        self._discard_stale()
        self.transport.write(command)
        replies = read_lines(self.transport, lines, self._line_timeout(line_timeout_s))
        if replies and BANNER_MARKER.decode() in replies[0]:
            # The dsPIC started while the command was on its way (a robot switched on
            # as the port opened): it may not have heard it. Ask again once the banner
            # is in; the next batch tells the owner to re-apply the robot's state.
            log.warning("%s: the dsPIC restarted before answering %r", self.transport.name, letter)
            if not any(BANNER_END.strip().decode() in line for line in replies):
                self._drain(until=BANNER_END)
            self._tail = b""
            self._unreported_restart = True
            self.transport.write(command)
            replies = read_lines(self.transport, lines, self._line_timeout(line_timeout_s))
        # docs/protocol.md: the reply "starts with the command's lower-case letter" (S answers
        # a bare "s", so no comma is required here).
        # A command with arguments ("T,1") is answered by its letter alone ("t").
        first = letter[:1].lower()
        if replies and not replies[0].startswith(first):
            raise ProtocolError(
                f"reply {replies[0]!r} to {letter!r} does not start with {first!r}"
            )
        return replies

    def _line_timeout(self, line_timeout_s: float | None) -> float:
        return self.settings.line_timeout_s if line_timeout_s is None else line_timeout_s

    def _calibrate_proximity(self) -> list[str]:
        """The ASCII ``K``: calibrate the IR sensors, sending nothing until it is done.

        docs/protocol.md, quirk "K": the dsPIC answers a first line at once, then spends
        about 1 s (stock) or 1.5 s (Webots) calibrating without reading its 64-byte
        receive ring, which has no overflow check; only its last line says it listens
        again. Raises LinkTimeoutError when that line does not come.
        """
        wait_s = 2 * self.profile.calibration_s + self.settings.line_timeout_s
        replies = self._ascii_command("K", 2, line_timeout_s=wait_s)
        if len(replies) < 2 or "finished" not in replies[-1]:
            raise LinkTimeoutError(
                f"{self.transport.name}: the IR calibration did not finish within {wait_s:.1f} s "
                f"(got {replies!r})"
            )
        return replies

    # -- binary batches ----------------------------------------------------------------

    def _line_baud(self) -> int:
        """The rate bytes really flow at: the slower of the port's and the firmware's."""
        return min(self.transport.baudrate or DEFAULT_BAUD, self.info.profile.line_baud)

    def timeout_for(self, batch: Batch) -> float:
        """Reply timeout of a batch on this line (see :func:`reply_timeout_s`)."""
        return reply_timeout_s(batch, self.info.profile, self.transport, self.settings)

    def _exchange(self, batch: Batch) -> bytes:
        """Send one step's batch and return exactly its reply bytes (b'' if it has none).

        Raises LinkTimeoutError / ShortReplyError / ExtraBytesError after the bounded
        retries, RobotResetError when the robot restarted or the port was re-plugged
        (the caller re-applies its state and rebuilds the batch), LinkLostError when
        the port is gone for good.
        """
        commands = self.info.profile.commands
        for request in batch.requests:
            if request.command not in commands:
                # Made for another firmware: its bytes would desynchronise this one.
                self.info.profile.wire_format(request.command)  # raises, naming the device
        if self._unreported_restart:
            self._unreported_restart = False
            self._raise_restarted("the dsPIC restarted during an ASCII command")
        last: Exception | None = None
        for attempt in range(self.settings.retries + 1):
            if attempt:
                self.stats.retries += 1
            try:
                try:
                    return self._attempt(batch)
                except LineFloodedError:
                    self.stats.faults["LineFloodedError"] += 1
                    raise  # a flood does not end for a retry: fail the step now
                except (ShortReplyError, ExtraBytesError, LinkTimeoutError) as exc:
                    last = exc
                    self.stats.faults[type(exc).__name__] += 1
                    log.warning("%s; resynchronising (attempt %d)", exc, attempt + 1)
                    self._resync()
            except LinkLostError as exc:
                # The port can vanish mid-batch or mid-resynchronisation alike.
                self.stats.faults["LinkLostError"] += 1
                self._reconnect(exc)
        assert last is not None
        raise last

    def _attempt(self, batch: Batch) -> bytes:
        self._discard_stale()
        self.transport.write(batch.tx)
        if not batch.expects_reply:
            # docs/protocol.md: a batch that asks for nothing gets no reply: never wait.
            return b""
        # The reply cannot come sooner than its bytes take at the faster of the two rates
        # (a pty, an emulator, may run a firmware faster than the real one): sleep through
        # that much. Trailing bytes come no faster than the slower: watch for that long.
        fastest = max(self.transport.baudrate or DEFAULT_BAUD, self.info.profile.line_baud)
        try:
            reply = self.transport.read_exactly(
                batch.reply_size,
                self.timeout_for(batch),
                expected_s=wire_time_s(len(batch.tx) + batch.reply_size, fastest),
            )
        except LinkTimeoutError as exc:
            self._check_banner(getattr(exc, "partial", b""))
            raise
        extra = self.transport.trailing(self.settings.trailing_guard_at(self._line_baud()))
        rest = banner_rest(self._tail + reply + extra)
        if rest:  # a reset cut the reply short and its banner is late: wait for it here
            extra += self._drain(until=rest)
        self._check_banner(reply + extra)
        if extra:
            raise ExtraBytesError(
                f"{self.transport.name}: bytes left over after the {batch.reply_size}-byte reply"
            )
        return reply

    def _discard_stale(self) -> None:
        stale = self.transport.pending()
        if stale:
            self.stats.faults["stale"] += 1
            log.warning(
                "%s: %d stale bytes before a batch; draining", self.transport.name, len(stale)
            )
            self._check_banner(stale + self._drain())

    def _drain(self, until: bytes = b"") -> bytes:
        return drain_line(self.transport, self.settings, until)

    def _resync(self) -> None:
        """End whatever the dsPIC was parsing (a batch, an ASCII line); drain what it sent.

        The dsPIC answers in order, so once the answer to the resync's own ``V`` is in,
        every late byte of an earlier reply is too: a reply delayed past its timeout can
        never be taken for the answer to the retry. A firmware that ignores ``V`` is
        drained until the line is quiet instead.
        """
        self.stats.resyncs += 1
        self.transport.write(RESYNC)
        answers = self.info.version and self.transport.relays_resync
        marker = VERSION_REPLY if answers else b""
        self._check_banner(self._drain(until=marker))

    def _check_banner(self, data: bytes) -> None:
        # The banner can straddle two reads: a short reply holds its first bytes, the
        # resync's drain the rest. So look at the tail of what came before, too.
        seen = self._tail + data
        self._tail = seen[-(len(BANNER_MARKER) - 1) :]
        if BANNER_MARKER in seen:
            self._tail = b""
            # The rest of the banner; its last line, not a quiet moment, says it is all in
            # (on a loaded machine, or a USB hub, its two lines can come 20 ms apart, and
            # the second one was then read as the reply to the probe's V).
            self._drain(until=b"" if BANNER_END in seen[seen.index(BANNER_MARKER):] else BANNER_END)
            self._restarted("the dsPIC restarted (welcome banner mid-stream)")

    def _reconnect(self, cause: LinkLostError) -> None:
        """Reopen a lost port until the deadline; then the robot must be set up again.

        A port that comes back and vanishes again while the firmware is re-detected
        (a loose connector) is reopened again, within the same deadline.
        """
        log.warning("%s: %s; reconnecting", self.transport.name, cause)

        def reopen() -> None:
            self.transport.reopen()
            self.stats.reconnects += 1
            self._redetect()

        not_back = (PortNotFoundError, LinkLostError)
        reconnect_within(self.name, self.settings.reconnect_timeout_s, reopen, not_back, cause)
        self._raise_restarted("the port was lost and reopened")

    def _restarted(self, why: str) -> None:
        self._redetect()
        self._raise_restarted(why)

    def _redetect(self) -> None:
        try:
            self._info = self._identify()
        except ProtocolError as exc:
            log.warning("%s: firmware re-detection failed: %s", self.transport.name, exc)

    def _raise_restarted(self, why: str) -> None:
        self.stats.restarts += 1
        raise RobotResetError(f"{self.transport.name}: {why}; robot state must be re-applied")

    def _close(self) -> None:
        """Close the transport; later exchanges raise LinkLostError instead of reopening it."""
        self.transport.close()
