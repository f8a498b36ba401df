"""``pipuck``: a robot carrying GCtronic's Pi-puck, driven from the Pi over I2C.

``ego run --port pipuck [--robot epuck2|epuck]`` on the Pi, or
``ego.Robot("pipuck", robot="epuck2")``. The microcontroller is an I2C slave at 0x1F on
the robot's bus, ``/dev/i2c-12`` (``/dev/i2c-4`` on legacy kernels):

* an **e-puck2** in selector 10 with GCtronic's firmware that has the Pi-puck's I2C mode
  takes one 20-byte message and answers 47 bytes, each with an XOR checksum
  (:mod:`~ego.backends.pipuck.packet`, profile ``epuck2-i2c``);
* an **e-puck1** with York's Pi-puck firmware is a map of SMBus registers
  (:mod:`~ego.backends.pipuck.york`, profile ``york``).

Beside it the Pi reads the IMU, the ToF and the ground module on the same bus
(:mod:`~ego.backends.pipuck.chips`), the battery through the board's ADC in sysfs, and
the camera, a USB video device behind the board's FT903, through V4L2.

Options (:class:`PipuckOptions`): ``robot`` ("epuck2", "epuck"; None: detected from the
IMU that answers, the MPU-9250 on an e-puck2, the LSM330 on an e-puck1, and else from
the e-puck2's checksummed reply), ``i2c_bus`` (the robot's bus number; None: 12 if it
exists, else 4), ``camera_device`` (None: EGO_CAMERA, else ``/dev/video0``; "none": no
camera), ``sysfs`` (where sysfs is mounted, for the battery; None: EGO_SYSFS, else
``/sys``).

>>> with ego.Robot("pipuck") as robot:  # doctest: +SKIP
...     robot.motors.set_speeds(200, 200)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar, Literal

from ego.backends.pipuck.bus import open_buses
from ego.backends.pipuck.detect import open_robot
from ego.core.backend import BackendOptions, Opened, check
from ego.errors import BackendOptionError, PortNotFoundError

if TYPE_CHECKING:
    from ego.camera import FrameSource
    from ego.core.environment import Environment

__all__ = ["SCHEME", "PipuckBackend", "PipuckOptions"]

SCHEME = "pipuck"
#: The USB camera's node when nothing else says (the FT903 is usually the only one).
DEFAULT_CAMERA_DEVICE = "/dev/video0"


def _robot(value: object) -> str:
    if value not in ("epuck2", "epuck"):
        raise BackendOptionError(f"pipuck option robot={value!r} must be 'epuck2' or 'epuck'")
    return str(value)


def _bus(value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 255:
        raise BackendOptionError(f"pipuck option i2c_bus={value!r} must be a bus number 0..255")
    return value


@dataclass(frozen=True, kw_only=True)
class PipuckOptions(BackendOptions):
    """A Pi-puck's options; None: the default each names."""

    #: "epuck2" or "epuck" (None: detected).
    robot: Literal["epuck2", "epuck"] | None = field(default=None, metadata=check(_robot))
    #: The robot's I2C bus number (None: 12, else the legacy 4).
    i2c_bus: int | None = field(default=None, metadata=check(_bus))
    #: The V4L2 camera device, or "none" (None: EGO_CAMERA, else /dev/video0).
    camera_device: str | None = None
    #: Where sysfs is mounted (None: EGO_SYSFS, else /sys).
    sysfs: str | None = None

    def with_environment(self, environment: Environment) -> PipuckOptions:
        return dataclasses.replace(
            self,
            camera_device=self.camera_device or environment.camera,
            sysfs=self.sysfs or environment.sysfs,
        )


class PipuckBackend:
    """``Robot("pipuck")``: see the module's doc for its options."""

    options: ClassVar[type[BackendOptions]] = PipuckOptions
    #: ego runs on the robot's own computer: ``ego run`` supervises by default, as on
    #: the Overo's UART (ego.servers.supervisor.wants_supervision).
    on_robot: ClassVar[bool] = True

    def open(self, port: str, options: BackendOptions) -> Opened:
        given = PipuckOptions.narrow(options)
        if port not in (SCHEME, f"{SCHEME}://"):
            raise PortNotFoundError(f"{port!r}: a Pi-puck's port is 'pipuck'")
        if given.firmware is not None:
            raise BackendOptionError(
                f"{port}: a Pi-puck's firmware follows from its robot: leave firmware unset "
                "and give robot='epuck2' or robot='epuck' if it must be said"
            )
        bus, board_bus = open_buses(given.i2c_bus)
        try:
            channel = open_robot(bus, given.robot, board_bus, Path(given.sysfs or "/sys"))
        except BaseException:
            bus.close()
            raise
        device = given.camera_device or DEFAULT_CAMERA_DEVICE
        if device == "none":
            return Opened(channel)

        def camera() -> FrameSource:
            from ego.camera import V4L2Source

            return V4L2Source(device)

        return Opened(channel, camera)
