"""A Robot's camera: opened at first use, from the backend's source or a given one."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from ego.errors import CameraError

if TYPE_CHECKING:
    from ego.camera import Camera, FrameSource
    from ego.core.robot_stop import Parts

__all__ = ["CameraSlot"]


class CameraSlot:
    """Where a robot's camera comes from, and the camera once something asked for it.

    Opened, the camera is handed to the robot's ``parts`` (closed with the robot) and to
    its step's ``local_devices`` (captured when due)."""

    def __init__(
        self,
        port: str,
        parts: Parts,
        local_devices: list[Camera],
        given: FrameSource | None,
        backend_source: Callable[[], FrameSource] | None,
    ) -> None:
        self._port = port
        self._parts = parts
        self._local_devices = local_devices
        self._given = given
        self._backend_source = backend_source
        #: The camera if something opened it, else None (looking does not open it).
        self.opened: Camera | None = None

    @property
    def camera(self) -> Camera:
        """The camera, opened at first use (the robot's V4L2 device, the emulator's, or remote)."""
        if self.opened is None:
            from ego.camera import Camera

            self.opened = Camera(source=self._given or self._default_source())
            self._parts.camera = self.opened
            self._local_devices.append(self.opened)
        return self.opened

    def _default_source(self) -> FrameSource:
        if self._backend_source is None:
            raise CameraError(f"this robot has no camera ({self._port}; EGO_CAMERA=none?)")
        return self._backend_source()
