"""ego: run Webots e-puck controllers on the real robot, or drive it from a PC.

>>> import ego
>>> with ego.Robot("sim") as robot:                      # doctest: +SKIP
...     robot.proximity.enable(64)
...     robot.step(64)
"""

# The composition root: ``ego.backends`` registers the built-in backends by name, so that
# Robot(port) finds them although the core names none (docs/architecture.md). Python runs
# this file before any ``ego.*`` module, so every Robot sees them.
from ego import (
    backends,  # noqa: F401  (imported for its registrations)
    errors,
)
from ego._version import __version__
from ego.core.robot import SIM_PORT, Robot
from ego.devices.leds import LedValue
from ego.seam.profile import Firmware
from ego.serial.link import LinkSettings


def __getattr__(name: str) -> object:
    # RobotGroup pulls in concurrent.futures: imported when first asked for.
    if name == "RobotGroup":
        from ego.core.group import RobotGroup

        return RobotGroup
    raise AttributeError(f"module 'ego' has no attribute {name!r}")


__all__ = [
    "SIM_PORT",
    "Firmware",
    "LedValue",
    "LinkSettings",
    "Robot",
    "RobotGroup",
    "__version__",
    "errors",
]
