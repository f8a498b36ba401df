"""What the floor under the e-puck looks like to its ground sensors and its camera.

A floor gives a reflectance (1.0 white, 0.15 black) at any point; the ground sensors read
it under their three spots and the camera renders it. Four kinds: the default marks (a
black stripe and a disc on white), a line track (a black line of some width along a
polyline) for line followers, a plain white floor, and an image laid on the floor (a
Webots world's floor texture), which also gives the camera its colours.

A floor image file is a PNG or a JPEG (as Webots takes), a regular file of at most
:data:`MAX_TEXTURE_BYTES`, whose declared size is checked against
:data:`MAX_TEXTURE_PIXELS` before it is decoded (a 445 KB PNG can declare 12000x12000).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from firmware_sim.files import read_regular

__all__ = [
    "BLACK",
    "MAX_TEXTURE_BYTES",
    "MAX_TEXTURE_PIXELS",
    "WHITE",
    "ImageFloor",
    "LineTrack",
    "Marks",
    "Plain",
]

#: A floor image file's size, at most.
MAX_TEXTURE_BYTES = 64 << 20
#: A floor image's pixels, at most (4096 x 4096): about 200 MB while it is read.
MAX_TEXTURE_PIXELS = 4096 * 4096
#: Rows converted to grey at a time: the float32 copy of a block, not of the image.
_ROWS = 256

WHITE = 1.0
BLACK = 0.15


@dataclass(frozen=True)
class Marks:
    """White, with a black stripe along y = 0.2 m and a black disc around (-0.3, -0.3)."""

    def reflectance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        stripe = np.abs(y - 0.2) < 0.02
        disc = (x + 0.3) ** 2 + (y + 0.3) ** 2 < 0.08**2
        return np.where(stripe | disc, BLACK, WHITE)


@dataclass(frozen=True)
class LineTrack:
    """A black line ``width_m`` wide along ``points`` (closed into a loop if ``closed``)."""

    points: tuple[tuple[float, float], ...]
    width_m: float = 0.02
    closed: bool = True

    def __post_init__(self) -> None:
        if len(self.points) < 2:
            raise ValueError("a line track needs at least two points")
        if not 0.001 <= self.width_m <= 0.2:
            raise ValueError(f"line width {self.width_m} m is outside 0.001..0.2 m")

    def segments(self) -> Sequence[tuple[tuple[float, float], tuple[float, float]]]:
        pts = list(self.points)
        ends = pts[1:] + ([pts[0]] if self.closed else [])
        return list(zip(pts, ends, strict=False))

    def distance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Distance (m) from each point to the line's centre, vectorised over points."""
        best = np.full(np.shape(x), np.inf)
        for (ax, ay), (bx, by) in self.segments():
            dx, dy = bx - ax, by - ay
            length2 = dx * dx + dy * dy or 1e-12
            t = np.clip(((x - ax) * dx + (y - ay) * dy) / length2, 0.0, 1.0)
            best = np.minimum(best, np.hypot(x - (ax + t * dx), y - (ay + t * dy)))
        return best

    def reflectance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.where(self.distance(x, y) <= self.width_m / 2, BLACK, WHITE)


@dataclass(frozen=True)
class Plain:
    """A white floor with nothing on it."""

    def reflectance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.full(np.broadcast(x, y).shape, WHITE)


@dataclass(frozen=True)
class ImageFloor:
    """An image laid on the floor, as Webots' RectangleArena lays its floor texture: the
    floor is ``size_m`` (x, y) centred on the origin, tiled with copies of the image each
    ``tile_m`` across, the image's top row towards +y and its left column towards -x.
    Reflectance follows the image's luminance, from BLACK (black) to WHITE (white)."""

    rgb_image: np.ndarray  # (height, width, 3) uint8
    size_m: tuple[float, float]
    tile_m: tuple[float, float]
    _grey: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        image = np.asarray(self.rgb_image)
        if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
            raise ValueError("a floor image must be (height, width, 3) uint8")
        if min(*self.size_m, *self.tile_m) <= 0:
            raise ValueError("a floor's size and tile size must be positive")
        # float32, a block of rows at a time: a float64 copy of a 16 Mpx image is 400 MB.
        weights = np.array([0.299, 0.587, 0.114], np.float32) * np.float32((WHITE - BLACK) / 255)
        grey = np.empty(image.shape[:2], np.float32)
        for top in range(0, image.shape[0], _ROWS):
            grey[top : top + _ROWS] = image[top : top + _ROWS].astype(np.float32) @ weights
        grey += np.float32(BLACK)
        object.__setattr__(self, "_grey", grey)

    @classmethod
    def from_file(cls, path: Path, size_m: tuple[float, float],
                  tile_m: tuple[float, float]) -> ImageFloor:  # fmt: skip
        import io
        import warnings

        from PIL import Image, UnidentifiedImageError

        try:
            data = read_regular(path, MAX_TEXTURE_BYTES, "a floor image")
            with warnings.catch_warnings():  # the bound below says it, in one line
                warnings.simplefilter("ignore", Image.DecompressionBombWarning)
                image = Image.open(io.BytesIO(data), formats=("PNG", "JPEG"))
            with image:
                width, height = image.size  # read from the header: nothing decoded yet
                if width * height > MAX_TEXTURE_PIXELS:
                    raise ValueError(
                        f"{path}: a floor image of {width}x{height} pixels is "
                        f"over the bound of {MAX_TEXTURE_PIXELS} (4096x4096)"
                    )
                rgb = np.asarray(image.convert("RGB"), dtype=np.uint8)
        except (OSError, UnidentifiedImageError, Image.DecompressionBombError) as exc:
            raise ValueError(f"floor image {str(path)!r} cannot be read: {exc}") from exc
        return cls(rgb, size_m, tile_m)

    def _pixels(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        height, width = self._grey.shape
        u = np.mod(np.asarray(x) + self.size_m[0] / 2, self.tile_m[0]) / self.tile_m[0]
        v = np.mod(self.size_m[1] / 2 - np.asarray(y), self.tile_m[1]) / self.tile_m[1]
        cols = np.clip((u * width).astype(np.intp), 0, width - 1)
        rows = np.clip((v * height).astype(np.intp), 0, height - 1)
        return rows, cols

    def reflectance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        rows, cols = self._pixels(x, y)
        grey: np.ndarray = self._grey[rows, cols]
        return grey

    def rgb(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """The image's colour at each point, (..., 3) uint8: what the camera sees."""
        rows, cols = self._pixels(x, y)
        colours: np.ndarray = np.asarray(self.rgb_image)[rows, cols]
        return colours
