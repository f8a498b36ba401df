"""Reading a camera's last frame: single pixels as Webots' getters do, and files."""

from __future__ import annotations

import os
from typing import Protocol

import numpy as np
import numpy.typing as npt

from ego.camera.convert import rgb888_to_bgra
from ego.camera.encode import save_image
from ego.errors import OutOfRangeError
from ego.seam.validate import check_int

__all__ = ["BgraCopy", "Framed", "PixelReads"]


class Framed(Protocol):
    """What the pixel reads need of their camera: its last frame, how many it took, and
    where its BGRA copy of that frame is kept."""

    @property
    def image(self) -> npt.NDArray[np.uint8]: ...

    @property
    def frame_count(self) -> int: ...

    @property
    def bgra_copy(self) -> BgraCopy: ...


class BgraCopy:
    """The last frame in BGRA, converted once a frame (Webots' ``getImage`` is often
    called several times a step)."""

    def __init__(self) -> None:
        self._bgra: npt.NDArray[np.uint8] | None = None
        self._frame = -1

    def of(self, image: npt.NDArray[np.uint8], frame: int) -> bytes:
        """``image`` (the ``frame``-th) as BGRA bytes, alpha 255."""
        if self._bgra is None or self._bgra.shape[:2] != image.shape[:2]:
            self._bgra = np.empty((image.shape[0], image.shape[1], 4), dtype=np.uint8)
            self._frame = -1
        if self._frame != frame:
            rgb888_to_bgra(image, out=self._bgra)
            self._frame = frame
        return self._bgra.tobytes()


class PixelReads:
    """The pixel and file part of :class:`~ego.camera.Camera`, over what :class:`Framed`
    gives (its methods take that as their ``self`` type: no host attributes here)."""

    def image_bgra(self: Framed) -> bytes:
        """The last frame as BGRA bytes (alpha 255), as Webots' ``getImage`` returns it."""
        return self.bgra_copy.of(self.image, self.frame_count)

    def save_image(self: Framed, filename: str | os.PathLike[str], quality: int = 90) -> None:
        """Save the last frame as JPEG (``quality`` 1..100) or PNG, by the file's extension."""
        save_image(self.image, filename, quality)

    def _pixel(self: Framed, x: int, y: int) -> tuple[int, int, int]:
        image = self.image
        height, width = image.shape[:2]
        x, y = check_int("x", x, integral=True), check_int("y", y, integral=True)
        if not 0 <= x < width:
            raise OutOfRangeError(f"x {x} is outside 0..{width - 1}")
        if not 0 <= y < height:
            raise OutOfRangeError(f"y {y} is outside 0..{height - 1}")
        red, green, blue = image[y, x].tolist()
        return red, green, blue

    def get_red(self: Framed, x: int, y: int) -> int:
        """Red of pixel (x, y) of the last frame, 0..255 (x to the right, y down)."""
        return PixelReads._pixel(self, x, y)[0]

    def get_green(self: Framed, x: int, y: int) -> int:
        """Green of pixel (x, y), 0..255."""
        return PixelReads._pixel(self, x, y)[1]

    def get_blue(self: Framed, x: int, y: int) -> int:
        """Blue of pixel (x, y), 0..255."""
        return PixelReads._pixel(self, x, y)[2]

    def get_grey(self: Framed, x: int, y: int) -> int:
        """Grey of pixel (x, y): (red + green + blue) // 3, as Webots' imageGetGray."""
        red, green, blue = PixelReads._pixel(self, x, y)
        return (red + green + blue) // 3
