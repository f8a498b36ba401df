"""The PC side: a robot behind ``ego serve`` as a :class:`~ego.seam.channel.Channel`, and
its camera.

:class:`RemoteChannel` carries a Robot's batches to the server as lists of requests; the
server encodes each for its own serial link and answers with exactly the batch's reply
bytes, or with the ego error its link met (LinkTimeoutError, RobotResetError...), which
is raised here as that class with its fields. Nothing is relayed byte by byte: the
server's link resynchronises, retries and re-detects its line by itself.

While the controller waits out a step (:meth:`RemoteChannel.waiting_until`, which
``Robot.step`` calls), a heartbeat thread pings the server when the line is quiet, so
that a controller with a 1 s step is not taken for a dead one; once the controller
stops stepping (it hangs, or loops without calling step), the pings stop too and the
server's deadman stops the robot after ``deadline_s``. Before the first step nothing
drives the robot, and the pings go on. A ping told that the server ended the session
(its deadman stopped the robot, it shut down) ends the controller as a lost link does:
the next step raises that LinkLostError (``Robot.step`` is -1), even a step that sends
nothing. So does a server gone without a word (killed: its socket refuses or breaks)
whose pings have failed for the reconnection window, ``settings.reconnect_timeout_s``: a
request would have tried to reconnect that long, and a step that sends nothing would
otherwise step on blind for ever (a supervised controller whose supervisor was killed).
``close`` says goodbye.

>>> channel = RemoteChannel.from_url("udp://127.0.0.1:4242")   # doctest: +SKIP
"""

from __future__ import annotations

import contextlib
import logging
import math
import threading
import time
import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ego.backends.remote.connection import Connection, RemoteStats, error_from_reply
from ego.errors import (
    CameraCaptureError,
    CameraError,
    EgoError,
    ImageFormatError,
    LinkLostError,
    LinkTimeoutError,
    OutOfRangeError,
    PortNotFoundError,
    ProtocolError,
    RobotBusyError,
    RobotResetError,
)
from ego.net.auth import coerce_secret
from ego.net.frames import MessageType
from ego.net.messages import (
    Ascii,
    CameraClose,
    CameraControl,
    CameraFrame,
    CameraOpen,
    Info,
    RobotCall,
    Step,
    pack_request,
)
from ego.net.payloads import ASCII_REPLY_LINES, unpack_json
from ego.net.urls import parse_url
from ego.nursery import Nursery
from ego.seam.batch import Batch
from ego.seam.channel import ChannelBase, FirmwareInfo, reconnect_within
from ego.seam.profile import Firmware
from ego.serial.firmware import profile_for
from ego.serial.link import LinkSettings

if TYPE_CHECKING:
    from ego.camera.source import GrantedFormat, PixelFormat

__all__ = ["RemoteChannel", "RemoteFrameSource", "RemoteStats", "error_from_reply", "info_from"]

log = logging.getLogger(__name__)


def info_from(fields: dict[str, Any]) -> FirmwareInfo:
    """The server link's firmware, profile included, from what it said (service.firmware_fields)."""
    firmware = Firmware(str(fields.get("firmware", "webots")))
    selector = fields.get("selector")
    profile = profile_for(
        firmware, selector if isinstance(selector, int) else None, fields.get("rev13") or None
    )
    hardware = fields.get("hardware_version")
    return FirmwareInfo(
        profile,
        str(fields.get("firmware_version", "")),
        hardware if isinstance(hardware, int) else None,
        fields.get("selector") if isinstance(fields.get("selector"), int) else None,
        bool(fields.get("detected", True)),
    )


class RemoteChannel(ChannelBase):
    """A robot served by ``ego serve``, over TCP or UDP: the Channel a Robot steps through.

    ``secret`` (None: none; ``Robot`` fills in ``EGO_SECRET_FILE`` / ``EGO_SECRET``); a
    client that has one refuses a server that cannot prove it has it too. ``timeout_s``
    bounds one request (the server may retry the serial line meanwhile); a lost server
    is reconnected to within ``settings.reconnect_timeout_s``, after which the robot's
    state is re-applied (RobotResetError), as after a re-plugged serial port.
    """

    def __init__(
        self,
        host: str,
        port: int,
        *,
        protocol: str = "tcp",
        secret: str | bytes | None = None,
        settings: LinkSettings | None = None,
        timeout_s: float = 5.0,
        heartbeat: bool = True,
        **connection_options: Any,
    ) -> None:
        if protocol not in ("tcp", "udp", "unix"):
            raise ValueError(f"protocol {protocol!r} is not tcp, udp or unix")
        super().__init__()
        self._address = (host, port, protocol)
        shown = f"[{host}]" if ":" in host else host
        self._name = f"unix://{host}" if protocol == "unix" else f"{protocol}://{shown}:{port}"
        self.secret = coerce_secret(secret)
        self.settings = settings or LinkSettings()
        self.timeout_s = timeout_s
        self.heartbeat = heartbeat
        self._options = connection_options
        self.net = RemoteStats()
        #: Held by one request to the server at a time (the heartbeat's pings included).
        self._call_lock = threading.Lock()
        self._last_activity = 0.0
        #: Until when the heartbeat may keep the session alive (time.monotonic()): no
        #: limit until the controller's first step, then the end of each step's wait.
        self._alive_until = math.inf
        #: The end of the session, as a heartbeat heard the server announce it (or met
        #: the server gone for the reconnection window).
        self._ended: LinkLostError | None = None
        #: Since when the heartbeat's pings fail (time.monotonic()), or None.
        self._failing_since: float | None = None
        self._conn: Connection | None = None
        self._beat: _Heartbeat | None = None
        self._connect()

    @classmethod
    def from_url(cls, url: str, secret: str | bytes | None = None, **options: Any) -> RemoteChannel:
        """``tcp://host:port``, ``udp://host:port`` (port 4242 if omitted) or ``unix:///path``."""
        try:
            scheme, host, port = parse_url(url)
        except ValueError as exc:
            raise PortNotFoundError(str(exc)) from exc
        return cls(host, port, protocol=scheme, secret=secret, **options)

    def _connect(self) -> None:
        host, port, protocol = self._address
        conn = Connection(host, port, protocol, self.secret, stats=self.net, **self._options)
        self._conn = conn
        self._info = info_from(conn.welcome)
        self.server_info = conn.welcome
        log.info("%s: connected, %s firmware", conn.name, self._info.firmware)
        if self.heartbeat:
            self._beat = _Heartbeat(weakref.WeakMethod(self._ping), max(0.01, conn.deadline_s / 4))

    @property
    def name(self) -> str:
        return self._name

    @property
    def deadline_s(self) -> float:
        """How long the server lets this client be silent before it stops the robot."""
        return self._conn.deadline_s if self._conn is not None else 0.5

    # -- the Channel -------------------------------------------------------------------------

    def _exchange(self, batch: Batch) -> bytes:
        if not batch.requests:
            return b""
        return self._request(Step(batch.requests))

    def _ascii_command(self, letter: str, lines: int) -> list[str]:
        if ASCII_REPLY_LINES.get(letter) is None:
            relayed = ", ".join(ASCII_REPLY_LINES)
            raise ProtocolError(f"{self.name}: ASCII command {letter!r} is not relayed ({relayed})")
        return self._lines(self._request(Ascii(letter, ASCII_REPLY_LINES[letter])))[:lines]

    def _calibrate_proximity(self) -> list[str]:
        return self._lines(self._request(Ascii("K", ASCII_REPLY_LINES["K"])))

    @staticmethod
    def _lines(reply: bytes) -> list[str]:
        return [line for line in reply.decode("ascii", "replace").split("\r\n") if line]

    def waiting_until(self, deadline_s: float) -> None:
        self._raise_if_ended()
        self._alive_until = deadline_s

    def _raise_if_ended(self) -> None:
        """The server ended the session behind a controller that sends nothing (its
        steps only wait): it ends, as on a lost link, rather than step on blind."""
        ended = self._ended
        if ended is not None:
            raise LinkLostError(str(ended)) from ended

    def call(self, request: RobotCall, timeout_s: float | None = None) -> bytes:
        """One request to the server (the camera's, say); its reply payload."""
        with self._call_lock:
            conn = self._conn
            if conn is None or self._closed:
                raise LinkLostError(f"{self.name}: not connected")
            mtype, payload = pack_request(request)
            self._last_activity = time.monotonic()
            try:
                return conn.call(mtype, payload, self.timeout_s if timeout_s is None else timeout_s)
            finally:
                self._last_activity = time.monotonic()

    def _request(self, request: RobotCall) -> bytes:
        """A request to the robot's link; a lost server is reconnected to (see the class)."""
        if self._closed:
            raise LinkLostError(f"{self.name}: the channel is closed")
        self._raise_if_ended()
        try:
            return self.call(request)
        except RobotResetError:
            self.stats.restarts += 1
            self._info = info_from(unpack_json(self.call(Info())))
            raise
        except LinkLostError as exc:
            self.stats.faults["LinkLostError"] += 1
            self._reconnect(exc)
            raise AssertionError("unreachable") from None

    def _reconnect(self, cause: LinkLostError) -> None:
        """Connect again until the deadline (a new session: the server stopped the robot)."""
        log.warning("%s: %s; reconnecting", self.name, cause)
        self._shutdown(goodbye=True)
        # A server still holding our old session refuses with RobotBusyError until its
        # deadman releases it: not back yet.
        not_back = (PortNotFoundError, LinkLostError, RobotBusyError, LinkTimeoutError)
        reconnect_within(
            self.name, self.settings.reconnect_timeout_s, self._connect, not_back, cause
        )
        self.stats.reconnects += 1
        raise RobotResetError(f"{self.name}: reconnected; robot state must be re-applied")

    def _close(self) -> None:
        """Say goodbye (the server stops the robot) and close the socket."""
        self._shutdown(goodbye=True)

    def stop_heartbeat(self) -> None:
        """Stop the heartbeat and join its thread: a controller that sends nothing more
        is then taken for a dead one after the server's deadline."""
        beat, self._beat = self._beat, None
        if beat is not None:
            beat.stop()  # joined: no ping goes out after this

    def _shutdown(self, goodbye: bool) -> None:
        self.stop_heartbeat()
        with self._call_lock:
            conn, self._conn = self._conn, None
            if conn is None:
                return
            if goodbye:
                with contextlib.suppress(EgoError, OSError):
                    conn.call(MessageType.BYE, b"", 0.3)
            conn.close()

    @property
    def is_open(self) -> bool:
        return self._conn is not None

    def _ping(self) -> bool:
        """Ping the server if nothing was sent for a while (the heartbeat thread's work);
        False once the server said the session ended (the heartbeat then stops)."""
        now = time.monotonic()
        conn = self._conn
        if (
            conn is None
            or now - self._last_activity < conn.deadline_s / 4
            or now > self._alive_until
        ):
            return True
        if not self._call_lock.acquire(blocking=False):
            return True  # a request is under way: that is activity enough
        try:
            if self._conn is not None:
                self.net.heartbeats += 1
                self._last_activity = now
                self._conn.call(MessageType.PING, b"", self._conn.deadline_s)
            self._failing_since = None
        except LinkLostError as exc:
            if getattr(exc, "session_ended", False):
                log.warning("%s", exc)
                self._ended = exc
                return False
            return self._ping_failed(now, exc)
        except (EgoError, OSError) as exc:
            return self._ping_failed(now, exc)
        finally:
            self._call_lock.release()
        return True

    def _ping_failed(self, now: float, exc: Exception) -> bool:
        """A ping that got no answer: True while the server may still come back, False
        (the session ended) once pings have failed for the reconnection window."""
        log.debug("%s: heartbeat failed: %s", self.name, exc)
        if self._failing_since is None:
            self._failing_since = now
        silent_s = now - self._failing_since
        if silent_s < self.settings.reconnect_timeout_s:
            return True
        ended = LinkLostError(
            f"{self.name}: the server has not answered for {silent_s:.1f} s "
            f"(its last ping: {exc})"
        )
        log.warning("%s", ended)
        self._ended = ended
        return False

    def frame_source(self) -> RemoteFrameSource:
        """The robot's camera, fetched through this connection."""
        return RemoteFrameSource(self)

    def __repr__(self) -> str:
        return f"<RemoteChannel {self.name} {'open' if self.is_open else 'closed'}>"


class _Heartbeat:
    """The owner of a channel's heartbeat thread: it starts the thread, which calls
    ``ping`` every quarter of ``interval_s`` until ``ping`` says the session ended, and
    :meth:`stop` stops and joins it (a channel's close, or its reconnection). It holds
    the channel weakly: a channel dropped without ``close`` stops beating, and the
    server's deadman then stops the robot."""

    def __init__(self, ping: weakref.WeakMethod[Callable[[], bool]], interval_s: float) -> None:
        self._ping = ping
        self._interval_s = interval_s
        self._stop = threading.Event()
        # A program that exits with its channel open: the thread ends first (the server's
        # deadman then stops the robot).
        self._threads = Nursery("a remote channel's heartbeat", at_exit=self._stop.set)
        self._threads.start_thread(self._run, name="ego-remote-heartbeat")

    def _run(self) -> None:
        while not self._stop.wait(self._interval_s / 4):
            ping = self._ping()
            if ping is None or not ping():
                return
            del ping

    def stop(self) -> None:
        """End and join the thread (not waited for when the thread itself stops it)."""
        self._stop.set()
        self._threads.close()


class RemoteFrameSource:
    """The camera of a robot behind ``ego serve``: a frame source for ego's Camera.

    Raw frames come in the pixel format asked at :meth:`open` (RGB565, so the client's
    Camera converts and rotates them locally); :meth:`fetch_encoded` asks the server for
    a JPEG or PNG instead, far smaller on a slow network.
    """

    def __init__(self, channel: RemoteChannel) -> None:
        if not isinstance(channel, RemoteChannel):
            raise CameraError(f"{channel!r} is not a remote robot: no remote camera there")
        self.channel = channel
        self.granted: GrantedFormat | None = None

    def _request(self, request: RobotCall) -> bytes:
        try:
            return self.channel.call(request)
        except (LinkTimeoutError, LinkLostError) as exc:
            raise CameraCaptureError(f"camera of {self.channel.name}: {exc}") from exc

    def open(self, width: int, height: int, pixel_format: PixelFormat | str) -> GrantedFormat:
        """Start capture near ``width`` x ``height``; what the robot's camera granted."""
        from ego.camera.source import GrantedFormat, PixelFormat

        fmt = PixelFormat(pixel_format)
        reply = unpack_json(self._request(CameraOpen(width, height, fmt.value)))
        self.granted = GrantedFormat(
            int(reply["width"]), int(reply["height"]), int(reply["stride"])
        )
        return self.granted

    def read_frame(self) -> bytes:
        """The next raw frame, ``stride_bytes`` x ``height`` bytes."""
        return self._request(CameraFrame("raw"))

    def fetch_encoded(self, kind: str = "jpeg", quality: int = 90, rotation: int = 180) -> bytes:
        """The next frame as a JPEG (``quality`` 1..100) or PNG file's bytes, converted
        and rotated (degrees counter-clockwise; 180 undoes the camera's mounting) on the
        robot."""
        from ego.camera.encode import check_quality
        from ego.seam.validate import ROTATIONS

        if kind not in ("jpeg", "png"):
            raise ImageFormatError(f"image kind {kind!r} is not jpeg or png")
        quality = check_quality(quality)
        if isinstance(rotation, bool) or rotation not in ROTATIONS:
            raise OutOfRangeError(f"rotation {rotation!r} is not one of 0, 90, 180, 270 degrees")
        return self._request(CameraFrame(kind, quality, rotation))

    def set_control(self, name: str, value: int) -> int:
        """Set a camera control (brightness, contrast...); the value the camera took."""
        return int(unpack_json(self._request(CameraControl(name, int(value))))["value"])

    def set_fov_rad(self, fov_rad: float) -> float:
        """Zoom an emulated camera; a real one keeps its optics and reports ``fov_rad``."""
        return float(unpack_json(self._request(CameraControl("fov_rad", float(fov_rad))))["value"])

    def close(self) -> None:
        """Stop capture; harmless when not open or when the connection is gone."""
        if self.granted is None:
            return
        self.granted = None
        with contextlib.suppress(EgoError):
            self._request(CameraClose())
