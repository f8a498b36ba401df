"""Webots' ``Camera`` (BGRA images) and ``CameraRecognitionObject``."""

from __future__ import annotations

import logging
import sys
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ego.controller.device import view
from ego.controller.sensor import Sensor
from ego.errors import EgoError

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot

__all__ = [
    "CAMERA_NEAR_M",
    "WEBOTS_CAMERA_SIZE",
    "Camera",
    "CameraRecognitionObject",
    "webots_camera_size",
]

log = logging.getLogger(__name__)

#: The camera's near plane.
CAMERA_NEAR_M = 0.0055
#: The PROTO's camera_width and camera_height: what a Webots controller expects.
WEBOTS_CAMERA_SIZE = (52, 39)


def webots_camera_size(core: CoreRobot) -> None:
    """Give ``core``'s camera the size a Webots controller expects: the run's
    ``--camera WxH``, else the emulator's world's (its camera_width/camera_height, as a
    Webots world sets them), else Webots' e-puck's 52x39 (the E-GO face keeps 640x480)."""
    from ego.faces.default_robot import current_context

    truth = core.ground_truth
    world = truth.true_world if truth is not None else None
    size = (
        current_context().options.camera_size
        or (world.camera_size if world is not None else None)
        or WEBOTS_CAMERA_SIZE
    )
    if (core.camera.width, core.camera.height) != size:
        core.camera.set_size(*size)


@view("Camera")
class Camera(Sensor):
    """The camera, BGRA images as Webots gives them. The Webots faces give it Webots'
    e-puck size (52x39) unless ``ego run --camera WxH`` asks another
    (:func:`webots_camera_size`); the E-GO face keeps 640x480."""

    def enable(self, samplingPeriod: int) -> None:
        self._core.camera.enable(samplingPeriod)

    def disable(self) -> None:
        self._core.camera.disable()

    def getSamplingPeriod(self) -> int:
        return self._core.camera.sampling_period or 0

    def getWidth(self) -> int:
        return int(self._core.camera.width)

    def getHeight(self) -> int:
        return int(self._core.camera.height)

    def getFov(self) -> float:
        return float(self._core.camera.fov_rad)

    def setFov(self, fov: float) -> None:
        """Webots zooms within getMinFov()..getMaxFov(); the e-puck's optics are fixed, so
        only the emulator's renderer follows (a real camera keeps its own)."""
        self._core.camera.fov_rad = fov

    def getMinFov(self) -> float:
        return float(self._core.camera.fov_rad)

    def getMaxFov(self) -> float:
        return float(self._core.camera.fov_rad)

    def getNear(self) -> float:
        """The PROTO's near plane, metres."""
        return CAMERA_NEAR_M

    def getFocalLength(self) -> float:
        return 0.0  # no Focus node on the e-puck's camera, as Webots answers

    def getFocalDistance(self) -> float:
        return 0.0

    def getExposure(self) -> float:
        """The V4L2 brightness control stands for Webots' exposure (None set: 1.0)."""
        brightness = self._core.camera.brightness
        return 1.0 if brightness is None else brightness / 64.0

    def setExposure(self, exposure: float) -> None:
        self._core.camera.brightness = max(0, min(255, round(float(exposure) * 64)))

    def hasRecognition(self) -> bool:
        return False

    def getRecognitionNumberOfObjects(self) -> int:
        return 0

    def getRecognitionObjects(self) -> list[object]:
        return []

    def getRecognitionSamplingPeriod(self) -> int:
        return 0

    def recognitionEnable(self, samplingPeriod: int) -> None:
        """Webots says the camera has no Recognition node; so does this."""
        print(
            "Error: wb_camera_recognition_enable() called on a Camera without Recognition node.",
            file=sys.stderr,
        )

    def getMinFocalDistance(self) -> float:
        return 0.0

    def getMaxFocalDistance(self) -> float:
        return 0.0

    def setFocalDistance(self, focal_distance: float) -> None:
        """The e-puck's camera has no Focus node: nothing to set, as Webots ignores it."""

    width = property(lambda self: self.getWidth())
    height = property(lambda self: self.getHeight())
    fov = property(lambda self: self.getFov(), lambda self, f: self.setFov(f))
    min_fov = property(lambda self: self.getMinFov())
    max_fov = property(lambda self: self.getMaxFov())
    near = property(lambda self: self.getNear())
    image = property(lambda self: self.getImage())
    exposure = property(lambda self: self.getExposure(), lambda self, e: self.setExposure(e))
    focal_length = property(lambda self: self.getFocalLength())
    focal_distance = property(
        lambda self: self.getFocalDistance(), lambda self, d: self.setFocalDistance(d)
    )
    min_focal_distance = property(lambda self: self.getMinFocalDistance())
    max_focal_distance = property(lambda self: self.getMaxFocalDistance())

    def getImage(self) -> bytes:
        """BGRA bytes, row by row, as Webots' ``getImage``."""
        return bytes(self._core.camera.image_bgra())

    def getImageArray(self) -> npt.NDArray[np.int64]:
        """``image[x][y] = [r, g, b]`` as Webots' ``getImageArray``.

        A NumPy array of int64 rather than nested lists: it indexes, iterates,
        compares and sums as the lists do (no uint8 wrap-around), 40 times faster at
        640x480; ``.tolist()`` gives Webots' lists.
        """
        return self._core.camera.image.transpose(1, 0, 2).astype(np.int64)

    def saveImage(self, filename: str, quality: int) -> int:
        """PNG or JPEG by extension; 0 on success, -1 on failure (Webots' convention).

        As Webots prints why, the reason of a failure is logged as a warning.
        """
        try:
            self._core.camera.save_image(filename, quality)
        except (EgoError, OSError, ValueError) as exc:
            log.warning("saveImage(%r) failed: %s", filename, exc)
            return -1
        return 0

    @staticmethod
    def imageGetRed(image: bytes, width: int, x: int, y: int) -> int:
        return image[4 * (y * width + x) + 2]

    @staticmethod
    def imageGetGreen(image: bytes, width: int, x: int, y: int) -> int:
        return image[4 * (y * width + x) + 1]

    @staticmethod
    def imageGetBlue(image: bytes, width: int, x: int, y: int) -> int:
        return image[4 * (y * width + x)]

    @staticmethod
    def imageGetGray(image: bytes, width: int, x: int, y: int) -> int:
        i = 4 * (y * width + x)
        return (image[i] + image[i + 1] + image[i + 2]) // 3

    imageGetGrey = imageGetGray


class CameraRecognitionObject:
    """What Webots' camera recognition returns; the e-puck's camera recognises nothing."""

    def __init__(self) -> None:
        self.id = 0
        self.position = [0.0, 0.0, 0.0]
        self.orientation = [0.0, 0.0, 1.0, 0.0]
        self.size = [0.0, 0.0]
        self.position_on_image = [0, 0]
        self.size_on_image = [0, 0]
        self.number_of_colors = 0
        self.colors: list[float] = []
        self.model = ""
