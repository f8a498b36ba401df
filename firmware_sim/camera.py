"""The emulated e-puck camera: the world rendered from the robot's pose, as raw RGB565 frames.

Each image column casts one ray (vectorised with numpy over all columns at once) into
the world: the arena's walls, the coloured blocks (5 cm high), the lamp (a lit post) and
the floor (``world.floor_rgb_at`` when the world has it, plain grey otherwise), with a
depth buffer so that near things hide far ones. The camera sits 3 cm above the floor at
the front of the body and sees 0.84 rad across, like the e-puck's.

Frames come out as the real sensor's do on the Overo: RGB565, little-endian as V4L2
delivers ``RGBP`` (or big-endian if asked), and **upside down**, the way the camera is
mounted, so that the camera's default rotation of 180 degrees turns them upright.

The world contract used here: ``world.snapshot()`` -> ``x_m, y_m, theta_rad`` (theta 0
faces +x, counter-clockwise positive); ``world.arena.half_size_m`` and ``.wall_rgb``
(``.half_y_m``, ``.wall_height_m`` if present); ``world.lamp.x_m, .y_m`` (``.height_m``
if present); ``world.blocks``, each with ``x_m, y_m, half_size_m, rgb`` (``half_y_m``,
``yaw_rad``, ``height_m`` if present); optionally ``world.floor_rgb_at(x_m, y_m)``.
"""

from __future__ import annotations

import math
from typing import Any, Final, NamedTuple, Protocol

import numpy as np
import numpy.typing as npt

__all__ = [
    "BACKGROUND_RGB",
    "CAMERA_FORWARD_M",
    "CAMERA_HEIGHT_M",
    "FLOOR_RGB",
    "SimulatedSource",
    "render_rgb888",
    "rgb888_to_rgb565",
]

#: The sensor's smallest and largest frame (the PO3030/PO6030 windows on the Overo).
MIN_SIZE: Final = (32, 32)
MAX_SIZE: Final = (640, 480)
#: The raw formats this camera delivers: RGB565, little-endian (V4L2 RGBP) or big-endian.
PIXEL_FORMATS: Final = ("RGB565", "RGB565_BE")
#: The image controls a camera driver offers; the renderer accepts and ignores them.
CONTROLS: Final = ("brightness", "contrast", "saturation", "auto_white_balance")
CAMERA_HEIGHT_M: Final = 0.03  # the lens above the floor
CAMERA_FORWARD_M: Final = 0.03  # the lens ahead of the body's centre
DEFAULT_FOV_RAD: Final = 0.84
WALL_HEIGHT_M: Final = 0.10
BLOCK_HEIGHT_M: Final = 0.05
LAMP_RADIUS_M: Final = 0.015
LAMP_HEIGHT_M: Final = 0.15  # when the world's lamp does not say
LAMP_RGB: Final = (255, 240, 190)
FLOOR_RGB: Final = (128, 128, 128)  # when the world has no floor_rgb_at
BACKGROUND_RGB: Final = (70, 75, 90)  # the room above the walls
# Faces turned along y are a little darker than those along x: edges stay visible.
_SHADE_Y_FACE: Final = 0.8

Image = npt.NDArray[np.uint8]
Floats = npt.NDArray[np.float64]


class _Pose(Protocol):
    x_m: float
    y_m: float
    theta_rad: float


def _ray_boxes(
    ox: float, oy: float, dx: Floats, dy: Floats, boxes: Floats
) -> tuple[Floats, npt.NDArray[np.bool_]]:
    """Slab test of every ray against every box (x, y, half x, half y, yaw), each in its
    own frame: distance (n, w), and whether the face hit is one of the box's y faces."""
    x, y, hx, hy, yaw = (boxes[:, i : i + 1] for i in range(5))
    c, s = np.cos(yaw), np.sin(yaw)
    lox, loy = c * (ox - x) + s * (oy - y), c * (oy - y) - s * (ox - x)
    ldx, ldy = c * dx + s * dy, c * dy - s * dx
    ldx = np.where(np.abs(ldx) < 1e-12, 1e-12, ldx)  # no division by zero
    ldy = np.where(np.abs(ldy) < 1e-12, 1e-12, ldy)
    tx1, tx2 = (-hx - lox) / ldx, (hx - lox) / ldx
    ty1, ty2 = (-hy - loy) / ldy, (hy - loy) / ldy
    tx_near, ty_near = np.minimum(tx1, tx2), np.minimum(ty1, ty2)
    near = np.maximum(tx_near, ty_near)
    far = np.minimum(np.maximum(tx1, tx2), np.maximum(ty1, ty2))
    hit = (near <= far) & (near > 0)
    return np.where(hit, near, np.inf), ty_near > tx_near


def _box_row(block: Any) -> list[float]:
    half = float(block.half_size_m)
    half_y = getattr(block, "half_y_m", None)
    return [block.x_m, block.y_m, half, half if half_y is None else half_y,
            getattr(block, "yaw_rad", 0.0)]  # fmt: skip


def render_rgb888(
    world: Any,
    width: int,
    height: int,
    *,
    fov_rad: float = DEFAULT_FOV_RAD,
    pose: _Pose | None = None,
) -> Image:
    """The upright view from the robot's camera, RGB888 ``(height, width, 3)``."""
    pose = pose if pose is not None else world.snapshot()
    theta = float(pose.theta_rad)
    ox = float(pose.x_m) + CAMERA_FORWARD_M * math.cos(theta)
    oy = float(pose.y_m) + CAMERA_FORWARD_M * math.sin(theta)
    focal = (width / 2) / math.tan(fov_rad / 2)
    # Column c looks left of the heading for c < width/2 (angles grow counter-clockwise).
    offsets = np.arctan(((width / 2) - (np.arange(width) + 0.5)) / focal)
    angles = theta + offsets
    cos_off = np.cos(offsets)
    dx, dy = np.cos(angles), np.sin(angles)
    dx = np.where(np.abs(dx) < 1e-12, 1e-12, dx)  # no division by zero in the slab tests
    dy = np.where(np.abs(dy) < 1e-12, 1e-12, dy)
    rows = np.arange(height, dtype=np.float64)[:, None] + 0.5 - height / 2  # + is down

    image = np.empty((height, width, 3), dtype=np.uint8)
    depth = np.full((height, width), np.inf)
    image[...] = BACKGROUND_RGB
    below = rows[:, 0] > 0
    if below.any():  # the floor, where each pixel's ray meets it
        floor_depth = focal * CAMERA_HEIGHT_M / rows[below]  # (rows, 1), along the axis
        reach = floor_depth / cos_off  # (rows, w), along each ray
        floor_rgb = getattr(world, "floor_rgb_at", None)
        if floor_rgb is None:
            image[below] = FLOOR_RGB
        else:
            image[below] = floor_rgb(ox + reach * dx, oy + reach * dy)
        depth[below] = np.broadcast_to(floor_depth, (int(below.sum()), width))

    # Everything standing on the floor: (distance along each ray, y face?, top, rgb).
    things: list[tuple[Floats, npt.NDArray[np.bool_], float, tuple[int, int, int]]] = []
    arena = world.arena
    half_x = float(arena.half_size_m)
    half_y = getattr(arena, "half_y_m", None)
    half_y = half_x if half_y is None else float(half_y)
    tx = (np.sign(dx) * half_x - ox) / dx
    ty = (np.sign(dy) * half_y - oy) / dy
    wall_height = float(getattr(arena, "wall_height_m", WALL_HEIGHT_M))
    things.append((np.minimum(tx, ty), ty < tx, wall_height, tuple(arena.wall_rgb)))
    blocks = list(world.blocks)
    if blocks:
        boxes = np.array([_box_row(b) for b in blocks], dtype=np.float64)
        distance, y_face = _ray_boxes(ox, oy, dx, dy, boxes)
        for i, block in enumerate(blocks):
            block_height = float(getattr(block, "height_m", BLOCK_HEIGHT_M))
            things.append((distance[i], y_face[i], block_height, tuple(block.rgb)))
    lamp = world.lamp
    mx, my = ox - float(lamp.x_m), oy - float(lamp.y_m)
    b = mx * dx + my * dy
    disc = b * b - (mx * mx + my * my - LAMP_RADIUS_M**2)
    t_lamp = -b - np.sqrt(np.maximum(disc, 0.0))
    t_lamp = np.where((disc >= 0) & (t_lamp > 0), t_lamp, np.inf)
    lamp_height = float(getattr(lamp, "height_m", LAMP_HEIGHT_M))
    things.append((t_lamp, np.zeros(width, dtype=bool), lamp_height, LAMP_RGB))

    for distance, y_face, top_m, rgb in things:
        seen = np.isfinite(distance)
        if not seen.any():
            continue
        axis_depth = np.where(seen, distance * cos_off, np.inf)  # perspective, not fisheye
        safe = np.where(seen, axis_depth, 1.0)
        top = focal * (CAMERA_HEIGHT_M - top_m) / safe  # rows from the horizon, + down
        bottom = focal * CAMERA_HEIGHT_M / safe
        mask = seen & (rows >= top) & (rows < bottom) & (axis_depth < depth)
        shade = np.where(y_face, _SHADE_Y_FACE, 1.0)[:, None] * np.asarray(rgb, np.float64)
        colour = np.broadcast_to(shade.astype(np.uint8), image.shape)
        image[mask] = colour[mask]
        depth[mask] = np.broadcast_to(axis_depth, depth.shape)[mask]
    return image


def rgb888_to_rgb565(image: Image) -> npt.NDArray[np.uint16]:
    """RGB888 -> RGB565 codes (R in the top bits), each channel rounded to its nearest level."""
    wide = image.astype(np.uint32)
    r = (wide[..., 0] * 31 + 127) // 255
    g = (wide[..., 1] * 63 + 127) // 255
    b = (wide[..., 2] * 31 + 127) // 255
    return ((r << 11) | (g << 5) | b).astype(np.uint16)


class Granted(NamedTuple):
    """The frame geometry the camera agreed to (the fields a V4L2 driver reports)."""

    width: int
    height: int
    stride_bytes: int


class SimulatedSource:
    """The emulator's camera: a frame source rendering ``world`` (the shape ego's camera
    sources have: open, read_frame, set_control, close), written apart from ego.

    Grants any size in 32x32..640x480 (larger or smaller asks are clamped, as a driver
    adjusts them), RGB565 in either byte order. Brightness, contrast, saturation and
    auto white balance are accepted and reported as granted (the renderer ignores them).

    >>> camera = Camera(source=SimulatedSource(world), width=160, height=120)  # doctest: +SKIP
    """

    def __init__(self, world: Any, *, fov_rad: float = DEFAULT_FOV_RAD) -> None:
        self.world = world
        self.fov_rad = fov_rad
        self._format: Granted | None = None
        self._pixel_format = "RGB565"
        self._controls: dict[str, int] = {}
        self.frames_rendered = 0

    def open(self, width: int, height: int, pixel_format: str) -> Granted:
        """Deliver ``width`` x ``height`` frames (clamped to the sensor) in ``pixel_format``."""
        name = str(getattr(pixel_format, "value", pixel_format))
        if name not in PIXEL_FORMATS:
            raise ValueError(f"the simulated camera delivers RGB565 only, not {name}")
        width = min(max(int(width), MIN_SIZE[0]), MAX_SIZE[0])
        height = min(max(int(height), MIN_SIZE[1]), MAX_SIZE[1])
        self._pixel_format = name
        self._format = Granted(width, height, 2 * width)
        return self._format

    def render(self) -> Image:
        """The current view, upright RGB888 (what the camera shows after its rotation)."""
        if self._format is None:
            raise RuntimeError("the simulated camera is not open: call open() first")
        return render_rgb888(
            self.world, self._format.width, self._format.height, fov_rad=self.fov_rad
        )

    def read_frame(self) -> bytes:
        """A raw frame: RGB565, upside down like the real mounting."""
        codes = rgb888_to_rgb565(self.render())[::-1, ::-1]
        dtype = "<u2" if self._pixel_format == "RGB565" else ">u2"
        self.frames_rendered += 1
        return codes.astype(dtype).tobytes()

    def set_control(self, name: str, value: int) -> int:
        if name not in CONTROLS:
            raise KeyError(f"unknown camera control {name!r}; the controls are {CONTROLS}")
        self._controls[name] = int(value)
        return int(value)

    def set_fov_rad(self, fov_rad: float) -> float:
        self.fov_rad = float(fov_rad)
        return self.fov_rad

    def close(self) -> None:
        self._format = None

    def __repr__(self) -> str:
        size = "closed" if self._format is None else f"{self._format.width}x{self._format.height}"
        return f"SimulatedSource({size})"
