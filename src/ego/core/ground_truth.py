"""What a simulator knows of its robot and world, as the library reads it: the ground truth.

A real robot has none. A simulated one (the ``sim`` backend, the emulator ego never
imports) hands ``ego.Robot`` an object of its own that follows :class:`GroundTruth`, as
gpiozero's pin factories follow its ``Factory``: the true pose, and, where the whole world
is known, a :class:`TrueWorld` (``true_world``: its layout for drawing, the floor's
reflectance, the devices its file declares and what they read, the camera size it sets,
how far the robot went). A robot node reached over Zenoh knows only the pose its node
sent (``true_world`` None). Readers (telemetry, the dashboard, a recording, the faces,
the radio, the demo) read these types and nothing else of the simulator.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["Box", "GroundTruth", "Layout", "TruePose", "TrueWorld"]


@dataclass(frozen=True, slots=True)
class TruePose:
    """Where the robot truly is: x, y in metres, heading in radians (counter-clockwise
    from +x), in the simulator's frame (a Webots world's arena's own, centred and
    unturned, z up: what the dashboard draws; a Supervisor and a GPS answer in the world
    file's frame instead)."""

    x_m: float
    y_m: float
    theta_rad: float

    def rounded(self, digits: int = 5) -> list[float]:
        """[x, y, theta], rounded: as a telemetry sample and a Zenoh reply carry it."""
        return [round(self.x_m, digits), round(self.y_m, digits), round(self.theta_rad, digits)]


@dataclass(frozen=True, slots=True)
class Box:
    """One box of the world, seen from above: centre and half extents in metres, yaw in
    radians, colour 0..255."""

    x_m: float
    y_m: float
    half_x_m: float
    half_y_m: float
    yaw_rad: float
    rgb: tuple[int, int, int]


@dataclass(frozen=True, slots=True)
class Layout:
    """What is drawn of a world: the arena's half extents (m), its boxes, its lamp (m)."""

    half_x_m: float
    half_y_m: float
    boxes: tuple[Box, ...]
    lamp_m: tuple[float, float]


class TrueWorld(Protocol):
    """The whole simulated world of a robot."""

    def layout(self) -> Layout:
        """The arena, boxes and lamp as they are now (a Supervisor may move a box)."""
        ...

    def floor_reflectance(
        self, x_m: NDArray[np.float64], y_m: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """The floor's reflectance (0 black .. 1 white) at each point (m)."""
        ...

    def declared_devices(self) -> frozenset[str]:
        """Which of "gps", "compass", "touch sensor" the world file gives the robot."""
        ...

    def device_values(self, name: str) -> tuple[float, float, float]:
        """What the declared ``"gps"`` or ``"compass"`` reads now, as Webots' would: the
        GPS where it sits (the robot's pose offset by its mount, an E-puck slot's), the
        Compass north in the robot's axes; both in the world file's own frame (its arena
        where it stands, NUE numbers in an NUE world). KeyError for another name."""
        ...

    def touching(self) -> bool:
        """Whether the robot's body touches a wall or a box (a bumper's TouchSensor)."""
        ...

    @property
    def camera_size(self) -> tuple[int, int] | None:
        """The camera size the world file sets (Webots' camera_width/height), else None."""
        ...

    @property
    def distance_travelled_m(self) -> float:
        """How far the robot's body has moved since the start (m)."""
        ...

    @property
    def closest_approach_m(self) -> float:
        """The closest the body came to a wall or a box so far (m; inf: never near one)."""
        ...


class GroundTruth(Protocol):
    """What the simulator behind a robot knows of it (see the module's doc)."""

    def pose(self) -> TruePose | None:
        """The robot's true pose now; None while it is not known (no reply yet)."""
        ...

    @property
    def true_world(self) -> TrueWorld | None:
        """The whole world, where the simulator knows it; None (a remote node's pose only)."""
        ...
