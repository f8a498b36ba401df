"""The e-puck2 over WiFi as a :class:`~ego.seam.channel.Channel`: batches in, the radio's
commands out, answers from its newest sensor packet.

What the radio's firmware asks of a client (docs/protocol.md, "e-puck2"), and where it
is met here:

* keep reading: :class:`~ego.backends.epuck2.connection.WifiConnection`'s thread;
* ask for the image only while the camera reads it (:meth:`Epuck2Channel.next_image`;
  a camera that stopped reading for :data:`IMAGE_IDLE_S` stops the stream);
* each one-shot (sound, calibration, the step counters) in exactly one command,
  cleared by the next, sent at once (:class:`~ego.serial.asercom2.ActuatorEncoder`);
* never connect without a valid command (``connection.connect`` sends it first);
* see the stop answered before closing: :meth:`_close` sends an all-off command with the
  request byte 0 and waits for two ``0x03`` replies (the first shows the radio read it;
  it hands a command to the main processor right after sending that reply,
  socket_e-puck2.c:266-276, so the second shows it went through), logging an error if
  they do not come within ``stop_timeout_s``;
* after a drop the robot keeps its last speeds until a new command comes, so the
  channel reconnects within ``reconnect_s`` with the controller's current command as
  the first one (the stop, when closing), or raises LinkLostError naming the robot and
  why; a link that keeps dropping (more than ``DropPolicy.max_drops`` drops within its
  ``window_s``) raises LinkLostError too, its reconnects backed off and its warnings
  summarised meanwhile (:mod:`ego.backends.epuck2.drops`), and the close still tries
  once to send the stop.

Batches are translated by :mod:`ego.backends.epuck2.requests`; the ASCII commands
(``V``, ``K``...) do not exist over WiFi and raise UnsupportedDeviceError naming the
transport, except ``K``'s calibration, which is the command's settings bit 0.
"""

from __future__ import annotations

import copy
import logging
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ego.backends.epuck2.connection import Heard, WifiConnection, connect
from ego.backends.epuck2.drops import DropPolicy, DropTally
from ego.backends.epuck2.requests import WIFI_PROFILE, answer, translate
from ego.backends.epuck2.wifi_packets import Request, encode_command
from ego.errors import LinkError, LinkLostError, LinkTimeoutError, UnsupportedDeviceError
from ego.seam.channel import ChannelBase, FirmwareInfo, reconnect_within
from ego.serial.asercom2 import ActuatorEncoder, Actuators, encode_actuators

if TYPE_CHECKING:
    from ego.seam.batch import Batch

__all__ = ["IMAGE_IDLE_S", "Epuck2Channel", "WifiSettings"]

log = logging.getLogger(__name__)

#: A camera that has not asked for a frame for this long no longer gets the image.
IMAGE_IDLE_S = 1.0
#: The radio's version as ego reports it (the WiFi protocol has no version command).
VERSION = "e-puck2 radio WiFi firmware (TCP port 1000 protocol)"


@dataclass(frozen=True, slots=True)
class WifiSettings:
    """The deadlines of one WiFi link, in seconds."""

    #: To connect, and for each awaited reply.
    timeout_s: float = 2.0
    #: To be back after a drop, before LinkLostError.
    reconnect_s: float = 5.0
    #: For the stop's answer at close.
    stop_timeout_s: float = 1.0
    #: How many drops the link may have before its reconnects do not hold.
    drops: DropPolicy = field(default_factory=DropPolicy)


class Epuck2Channel(ChannelBase):
    """The WiFi link to one e-puck2 at ``address`` (resolved), called ``name``."""

    def __init__(
        self, name: str, address: tuple[str, int], settings: WifiSettings | None = None
    ) -> None:
        super().__init__()
        self._name = name
        self.address = address
        self.settings = settings or WifiSettings()
        self._encoder = ActuatorEncoder(Actuators())
        self._last_sent = b""
        self._image_until = 0.0  # images are asked until then (monotonic)
        self._camera_open = False
        self._gone: LinkLostError | None = None
        self._drops = DropTally(self.settings.drops)
        #: The link was given up for dropping too often: the robot may still be reachable.
        self._flapping = False
        self._answered: dict[str, tuple[WifiConnection, int]] = {}
        self._conn = self._open(self._command(), "opening")
        packet = self._conn.heard.sensors
        assert packet is not None
        self._info = FirmwareInfo(WIFI_PROFILE, VERSION, selector=packet.sensors.selector)

    @property
    def name(self) -> str:
        return self._name

    @property
    def heard(self) -> Heard:
        """What the current connection heard (the bytes it received included)."""
        return self._conn.heard

    # -- the channel -------------------------------------------------------------------

    def _exchange(self, batch: Batch) -> bytes:
        before = copy.copy(self._encoder)
        try:
            # What the batch put on the wire, as its decode reads it (issue 32, item 4).
            getters = translate(batch.wire, self._encoder, self._name)
        except BaseException:
            self._encoder = before  # a refused batch changes nothing
            raise
        self._flush()
        if not getters:
            return b""
        heard = self._await("sensors_seq", self._seen("sensors_seq"))
        self._answered["sensors_seq"] = (self._conn, heard.sensors_seq)
        assert heard.sensors is not None
        state = self._encoder.state
        return answer(getters, heard.sensors.sensors, heard.sensors.data,
                      (state.speed_left, state.speed_right))  # fmt: skip

    def _ascii_command(self, letter: str, lines: int) -> list[str]:
        raise UnsupportedDeviceError(
            f"{self._name}: the e-puck2's WiFi link carries no ASCII commands ({letter!r}); "
            "use USB (selector 8) or Bluetooth (3) for them"
        )

    def _calibrate_proximity(self) -> list[str]:
        self._encoder.calibrate_proximity()
        self._flush()
        time.sleep(self.profile.calibration_s)  # the robot calibrates; the stream goes on
        return []

    def _close(self) -> None:
        stop = encode_command(Request(0), encode_actuators(Actuators()))
        try:
            if self._conn.heard.lost is not None and self._flapping:
                self._conn = self._open(stop, "stopping")  # one try, the tally aside
            elif self._conn.heard.lost is not None:
                self._recover(self._conn.heard.lost, stop)
            before = self._conn.heard.empties
            self._conn.send(stop)
            deadline = time.monotonic() + self.settings.stop_timeout_s
            heard = self._conn.wait("empties", before + 1, deadline)
            if heard is None or heard.empties < before + 2:
                log.error("%s: the robot did not answer its stop within %s s; it may still "
                          "be moving", self._name, self.settings.stop_timeout_s)  # fmt: skip
        except LinkError as exc:
            log.error("%s: could not send the stop before closing: %s", self._name, exc)
        finally:
            self._conn.close()

    # -- the camera's side ----------------------------------------------------------------

    def camera_open(self, is_open: bool) -> None:
        """The camera source opened (images may be asked) or closed (they are not)."""
        with self._lock:
            self._camera_open = is_open
            if not is_open:
                self._image_until = 0.0
                if self._closed or self._conn.heard.lost is not None:
                    return  # the next connection's first command asks no image
                try:
                    self._flush()
                except LinkError as exc:  # the next step's batch meets it again
                    log.warning("%s: could not stop the image stream: %s", self._name, exc)

    def next_image(self) -> bytes:
        """An image newer than the last one handed on (160x120 RGB565 big-endian),
        asking for the stream if it was not on and reconnecting after a drop;
        LinkTimeoutError if none comes within ``timeout_s``, LinkLostError when the robot
        does not come back."""
        deadline = time.monotonic() + self.settings.timeout_s
        while True:
            with self._lock:
                self._check_open()
                self._image_until = time.monotonic() + IMAGE_IDLE_S
                if self._conn.heard.lost is not None:
                    self._recover(self._conn.heard.lost, self._command())
                self._flush()
                conn, seq = self._conn, self._seen("image_seq")
            heard = conn.wait("image_seq", seq, deadline)
            if heard is not None and heard.image is not None and heard.image_seq > seq:
                self._answered["image_seq"] = (conn, heard.image_seq)
                return heard.image
            if heard is None:
                raise LinkTimeoutError(f"{self._name}: no image within {self.settings.timeout_s} s")

    # -- commands and connections ----------------------------------------------------------

    def _request(self) -> Request:
        images = self._camera_open and time.monotonic() < self._image_until
        return Request.SENSORS | Request.IMAGE if images else Request.SENSORS

    def _command(self) -> bytes:
        return encode_command(self._request(), self._encoder.next_payload())

    def _flush(self) -> None:
        """Send the command the state now calls for, if it is not the one in force, and
        the one that clears a one-shot right after it (reconnecting if need be)."""
        command = self._command()
        follow_up = self._command() if self._encoder.needs_follow_up else None
        for packet in (command, follow_up):
            if packet is None or packet == self._last_sent:
                continue
            if self._conn.heard.lost is None:
                try:
                    self._conn.send(packet)
                    self._last_sent = packet
                    continue
                except LinkError:
                    pass
            self._recover(self._conn.heard.lost or "sending failed", packet)

    def _seen(self, ready: str) -> int:
        """The number of the last packet of kind ``ready`` handed on from the current
        connection (0: none): each step's answers come from a newer one, at most one of
        the radio's loops old, without waiting for one sent after the batch."""
        conn, seq = self._answered.get(ready, (None, 0))
        return seq if conn is self._conn else 0

    def _await(self, ready: str, after: int) -> Heard:
        """Wait for ``ready`` to pass ``after``; after a drop, reconnect and wait anew."""
        deadline = time.monotonic() + self.settings.timeout_s
        heard = self._conn.wait(ready, after, deadline)
        if heard is not None and heard.lost is None:
            return heard
        if heard is None:
            raise LinkTimeoutError(
                f"{self._name}: no sensor packet within {self.settings.timeout_s} s"
            )
        assert heard.lost is not None
        self._recover(heard.lost, self._command())
        return self._conn.heard  # a fresh connection waited for its first packet

    def _recover(self, why: str, first: bytes) -> None:
        """Reconnect within ``reconnect_s``, ``first`` as the first command; else
        LinkLostError naming the robot and ``why``."""
        self._conn.close()
        if self._gone is not None:
            raise self._gone
        verdict = self._drops.dropped(time.monotonic(), why)
        if verdict.give_up:
            self._flapping = True
            self._gone = LinkLostError(f"{self._name}: {self._drops.give_up_message(why)}")
            raise self._gone  # the owner learns it once, and logs it
        if verdict.warning is not None:
            log.warning("%s: %s", self._name, verdict.warning)
        time.sleep(verdict.backoff_s)  # the robot keeps its last command meanwhile

        def attempt() -> None:
            self._conn = self._open(first, "reconnecting")

        try:
            reconnect_within(self._name, self.settings.reconnect_s, attempt, (LinkError,),
                             LinkLostError(f"{self._name}: connection lost: {why}"))  # fmt: skip
        except LinkLostError as exc:
            self._gone = exc  # not tried again: the owner learns it once
            raise
        self._stats.reconnects += 1

    def _open(self, first: bytes, doing: str) -> WifiConnection:
        """A connection that sent ``first`` and heard its first sensor packet."""
        timeout_s = self.settings.timeout_s
        conn = WifiConnection(self._name, connect(self._name, self.address, first, timeout_s))
        self._last_sent = first
        # The first reply: a sensor packet, or the 0x03 of a stop (request byte 0).
        heard = conn.wait("empties" if first[1] == 0 else "sensors_seq", 0,
                          time.monotonic() + timeout_s)  # fmt: skip
        if heard is not None and heard.lost is None:
            return conn
        conn.close()  # it sent a valid command: the radio goes back to accept()
        why = heard.lost if heard is not None else f"no reply within {timeout_s} s"
        raise LinkTimeoutError(
            f"{self._name}: connected to {self.address[0]}:{self.address[1]} {doing}, but "
            f"{why}: is it an e-puck2 with its selector at 15 (WiFi)?"
        )
