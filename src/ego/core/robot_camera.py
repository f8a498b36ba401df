"""The Robot's camera: opened at first use, from the backend's source or a given one."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ego.errors import CameraError

if TYPE_CHECKING:
    from ego.camera import Camera, FrameSource
    from ego.core.backend import Opened
    from ego.core.robot_stop import Parts

__all__ = ["CameraWiring"]


class CameraWiring:
    """The part of :class:`~ego.core.robot.Robot` that opens its camera."""

    port: str
    _opened: Opened
    _parts: Parts
    _camera: Camera | None
    _camera_source: FrameSource | None
    #: Devices the step clock schedules on this side of the link (the camera, once
    #: opened): each is updated with the step's time.
    _local_devices: list[Camera]

    @property
    def camera(self) -> Camera:
        """The camera, opened at first use (the robot's V4L2 device, the emulator's, or remote)."""
        if self._camera is None:
            from ego.camera import Camera

            self._camera = Camera(source=self._camera_source or self._default_camera_source())
            self._parts.camera = self._camera
            self._local_devices.append(self._camera)
        return self._camera

    @property
    def open_camera(self) -> Camera | None:
        """The camera if something opened it, else None (looking does not open it)."""
        return self._camera

    def _default_camera_source(self) -> FrameSource:
        if self._opened.camera is None:
            raise CameraError(f"this robot has no camera ({self.port}; EGO_CAMERA=none?)")
        return self._opened.camera()
