"""Reading a camera's last frame: single pixels as Webots' getters do, and files."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from ego.camera.convert import rgb888_to_bgra
from ego.camera.encode import save_image
from ego.errors import OutOfRangeError
from ego.seam.validate import check_int

__all__ = ["PixelReads"]


class PixelReads:
    """The pixel and file part of :class:`~ego.camera.Camera`, over its ``image``."""

    _bgra: npt.NDArray[np.uint8] | None
    _bgra_frame: int
    _frames: int

    if TYPE_CHECKING:  # the Camera's own property

        @property
        def image(self) -> npt.NDArray[np.uint8]: ...

    def image_bgra(self) -> bytes:
        """The last frame as BGRA bytes (alpha 255), as Webots' ``getImage`` returns it."""
        image = self.image
        if self._bgra is None or self._bgra.shape[:2] != image.shape[:2]:
            self._bgra = np.empty((image.shape[0], image.shape[1], 4), dtype=np.uint8)
            self._bgra_frame = -1
        if self._bgra_frame != self._frames:
            rgb888_to_bgra(image, out=self._bgra)
            self._bgra_frame = self._frames
        return self._bgra.tobytes()

    def save_image(self, filename: str | os.PathLike[str], quality: int = 90) -> None:
        """Save the last frame as JPEG (``quality`` 1..100) or PNG, by the file's extension."""
        save_image(self.image, filename, quality)

    def _pixel(self, x: int, y: int) -> tuple[int, int, int]:
        image = self.image
        height, width = image.shape[:2]
        x, y = check_int("x", x, integral=True), check_int("y", y, integral=True)
        if not 0 <= x < width:
            raise OutOfRangeError(f"x {x} is outside 0..{width - 1}")
        if not 0 <= y < height:
            raise OutOfRangeError(f"y {y} is outside 0..{height - 1}")
        red, green, blue = image[y, x].tolist()
        return red, green, blue

    def get_red(self, x: int, y: int) -> int:
        """Red of pixel (x, y) of the last frame, 0..255 (x to the right, y down)."""
        return self._pixel(x, y)[0]

    def get_green(self, x: int, y: int) -> int:
        """Green of pixel (x, y), 0..255."""
        return self._pixel(x, y)[1]

    def get_blue(self, x: int, y: int) -> int:
        """Blue of pixel (x, y), 0..255."""
        return self._pixel(x, y)[2]

    def get_grey(self, x: int, y: int) -> int:
        """Grey of pixel (x, y): (red + green + blue) // 3, as Webots' imageGetGray."""
        red, green, blue = self._pixel(x, y)
        return (red + green + blue) // 3
