"""The e-puck2's camera over WiFi as a :class:`~ego.camera.source.FrameSource`.

The radio sends 160x120 RGB565 big-endian frames (ESP:socket_e-puck2.c:206-226), upright
as the clients show them (``wifi_packets.image_to_rgb888``, rotation 0). A
:class:`~ego.camera.Camera` turns its source's frames by 180 degrees unless told
otherwise (the e-puck1's sensor is mounted upside down), so this source hands a frame
over turned by 180 degrees: the Camera's default then shows the radio's frame as it came,
pixel for pixel what ``image_to_rgb888`` gives. It serves RGB565 big-endian as it came
and, byte-swapped, the little-endian RGB565 a Camera asks by default; it has no
controls (the WiFi command has no camera field).

Images are asked of the robot only while frames are read (see the channel's
``next_image``): a 38400-byte frame costs the radio's loop a multiple of a sensor
packet's time.
"""

from __future__ import annotations

import errno
from typing import TYPE_CHECKING

import numpy as np

from ego.backends.epuck2.wifi_packets import IMAGE_HEIGHT, IMAGE_WIDTH
from ego.camera.source import GrantedFormat, PixelFormat, check_control_name
from ego.errors import CameraCaptureError, UnsupportedControlError

if TYPE_CHECKING:
    from ego.backends.epuck2.channel import Epuck2Channel

__all__ = ["WifiCamera"]


class WifiCamera:
    """The image stream of ``channel`` as raw frames."""

    def __init__(self, channel: Epuck2Channel) -> None:
        self.channel = channel
        self._format: PixelFormat | None = None

    def open(self, width: int, height: int, pixel_format: PixelFormat) -> GrantedFormat:
        if pixel_format not in (PixelFormat.RGB565, PixelFormat.RGB565_BE):
            raise CameraCaptureError(
                errno.EINVAL,
                f"{self.channel.name}: the e-puck2's WiFi camera sends RGB565, not "
                f"{pixel_format.value}",
            )
        self._format = pixel_format
        self.channel.camera_open(True)
        return GrantedFormat(IMAGE_WIDTH, IMAGE_HEIGHT, 2 * IMAGE_WIDTH)

    def read_frame(self) -> bytes:
        if self._format is None:
            raise CameraCaptureError(errno.EBADF, f"{self.channel.name}: the camera is not open")
        pixels = np.frombuffer(self.channel.next_image(), dtype=">u2")[::-1]
        order = ">u2" if self._format is PixelFormat.RGB565_BE else "<u2"
        return pixels.astype(order).tobytes()

    def set_control(self, name: str, value: int) -> int:
        raise UnsupportedControlError(
            f"{self.channel.name}: the e-puck2's WiFi link cannot set the camera's "
            f"{check_control_name(name)}"
        )

    def close(self) -> None:
        if self._format is not None:
            self._format = None
            self.channel.camera_open(False)

    def __repr__(self) -> str:
        return f"<WifiCamera of {self.channel.name}>"
