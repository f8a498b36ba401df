"""What ``ego serve`` does on the robot for a typed request: the blocking half of a call.

The session (:mod:`ego.servers.sessions.session`) decides *what* to run; :class:`RobotService` runs
it on the robot's channel (one thread: the serial line is used by one at a time) or its
camera (another, so that a slow capture never delays a step), and returns the reply
payload or raises the ego error met. The safe stop is :func:`ego.core.safety.send_stop`, the
same batch a Robot sends; a frame is converted by :func:`ego.camera.frames.frame_to_rgb888`,
the same code a Camera uses.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

from ego.core.safety import send_stop
from ego.errors import CameraError, ProtocolError, UnsupportedDeviceError
from ego.net.messages import (
    Ascii,
    CameraClose,
    CameraControl,
    CameraFrame,
    CameraOpen,
    Info,
    RobotCall,
    Step,
)
from ego.net.payloads import pack_json
from ego.seam.batch import Batch
from ego.seam.channel import Channel, FirmwareInfo, as_channel_base
from ego.serial.protocol import encode_batch

if TYPE_CHECKING:
    from ego.camera.source import FrameSource, GrantedFormat, PixelFormat

__all__ = ["FrameEncoder", "RobotService", "encode_image", "firmware_fields"]

#: ``(raw, granted, pixel_format, kind, quality, rotation) -> bytes``: a raw frame as a
#: JPEG or PNG file's bytes.
FrameEncoder = Callable[[bytes, "GrantedFormat", "PixelFormat", str, int, int], bytes]


def encode_image(
    raw: bytes, granted: GrantedFormat, pixel_format: PixelFormat, kind: str, quality: int,
    rotation: int,
) -> bytes:  # fmt: skip
    """A raw frame as JPEG (``quality`` 1..100) or PNG, converted and rotated as a Camera
    would (``rotation`` 180 undoes the e-puck camera's mounting)."""
    from ego.camera.encode import encode_jpeg, encode_png
    from ego.camera.frames import frame_to_rgb888

    image = frame_to_rgb888(raw, granted, pixel_format, rotation)
    return encode_jpeg(image, quality) if kind == "jpeg" else encode_png(image)


def firmware_fields(info: FirmwareInfo) -> dict[str, object]:
    """What a client needs to speak to the same firmware profile (see RemoteChannel)."""
    return {
        "firmware": str(info.firmware),
        "firmware_version": info.version,
        "hardware_version": info.hardware_version,
        "selector": info.selector,
        "rev13": info.profile.rev13,
        "detected": info.detected,
    }


class RobotService:
    """The robot's channel and camera, as ``ego serve`` uses them for its client."""

    def __init__(
        self,
        channel: Channel,
        frame_source: FrameSource | None = None,
        frame_encoder: FrameEncoder = encode_image,
    ) -> None:
        #: Its lock is held while it is in use: the deadman's stop may come from its own
        #: thread, and must never come between a session's liveness check and its batch.
        self.channel = as_channel_base(channel)
        self.frame_source = frame_source
        self.frame_encoder = frame_encoder
        self._camera: tuple[GrantedFormat, PixelFormat] | None = None
        #: Guards the two below: a stop never closes the source under a camera call
        #: (another thread may be inside ``read_frame``); the call closes it as it ends.
        self._camera_lock = threading.Lock()
        self._camera_users = 0
        self._close_wanted = False

    def welcome(self) -> dict[str, object]:
        return {**firmware_fields(self.channel.info), "camera": self.frame_source is not None}

    @staticmethod
    def uses_camera(call: RobotCall) -> bool:
        return isinstance(call, CameraOpen | CameraFrame | CameraControl | CameraClose)

    def run(self, call: RobotCall, live: Callable[[], bool] = lambda: True) -> bytes | None:
        """Run one call (Ping and Bye do nothing); its reply payload. None, and nothing
        run, when ``live()`` says its session ended before the call's turn came: asked
        once the channel is ours, so that no stop can come between the check and the
        batch (a session's stop always comes after its calls, never before one)."""
        if self.uses_camera(call):
            return self._camera_turn(call, live)
        with self.channel.lock:
            if not live():
                return None
            if isinstance(call, Step):
                return self.channel.exchange(self._batch(call))
            if isinstance(call, Ascii):
                lines = (
                    self.channel.calibrate_proximity()
                    if call.letter == "K"
                    else self.channel.ascii_command(call.letter, call.lines)
                )
                return "".join(line + "\r\n" for line in lines).encode("ascii", "replace")
            if isinstance(call, Info):
                return pack_json(firmware_fields(self.channel.info))
        return b""

    def _batch(self, step: Step) -> Batch:
        try:
            return encode_batch(step.requests, self.channel.profile)
        except UnsupportedDeviceError as exc:
            raise UnsupportedDeviceError(f"batch refused: {exc}") from exc
        except ValueError as exc:
            raise ProtocolError(f"batch refused: {exc}") from exc

    def stop(self, close_camera: bool) -> None:
        """The confirmed stop batch (ego.core.safety.send_stop); the camera closed if asked."""
        try:
            with self.channel.lock:
                send_stop(self.channel)
        finally:
            if close_camera and self.frame_source is not None:
                self._release_camera()

    def _release_camera(self) -> None:
        """Close the camera now, or, if a call is using it, as soon as that call ends."""
        with self._camera_lock:
            if self._camera_users:
                self._close_wanted = True
                return
            self._close_camera()

    def _close_camera(self) -> None:
        """Under ``_camera_lock``, with no camera call running."""
        self._camera, self._close_wanted = None, False
        if self.frame_source is not None:
            self.frame_source.close()

    def _camera_turn(self, call: RobotCall, live: Callable[[], bool]) -> bytes | None:
        """A camera call, counted as a user of the source from before ``live()`` is asked
        (a stop that ends its session later defers the close to it) to its end."""
        with self._camera_lock:
            self._camera_users += 1
        try:
            return self._camera_call(call) if live() else None
        finally:
            with self._camera_lock:
                self._camera_users -= 1
                if not self._camera_users and self._close_wanted:
                    self._close_camera()

    def _camera_call(self, call: RobotCall) -> bytes:
        from ego.camera.source import FieldOfViewControl, PixelFormat

        source = self.frame_source
        if source is None:
            raise CameraError("this ego server has no camera")
        if isinstance(call, CameraClose):
            self._camera = None
            source.close()
            return b""
        if isinstance(call, CameraOpen):
            try:
                fmt = PixelFormat(call.pixel_format)
            except ValueError as exc:
                raise CameraError(f"unknown pixel format: {exc}") from exc
            granted = source.open(call.width, call.height, fmt)
            self._camera = (granted, fmt)
            return pack_json({"width": granted[0], "height": granted[1], "stride": granted[2]})
        if isinstance(call, CameraControl):
            if call.name == "fov_rad":
                # A renderer can zoom; real optics cannot, and keep what was asked.
                fov = float(call.value)
                if isinstance(source, FieldOfViewControl):
                    fov = source.set_fov_rad(fov)
                return pack_json({"value": fov})
            return pack_json({"value": int(source.set_control(call.name, int(call.value)))})
        assert isinstance(call, CameraFrame)
        if self._camera is None:
            raise CameraError("the camera is not open: open it first")
        raw = bytes(source.read_frame())  # a copy: the source may reuse its buffer
        if call.kind == "raw":
            return raw
        granted, fmt = self._camera
        return self.frame_encoder(raw, granted, fmt, call.kind, call.quality, call.rotation)
