"""ego: run Webots e-puck controllers on the real robot, or drive it from a PC.

>>> import ego
>>> with ego.Robot("sim") as robot:                      # doctest: +SKIP
...     robot.proximity.enable(64)
...     robot.step(64)
"""

from ego import errors
from ego._version import __version__
from ego.core.robot import SIM_PORT, Robot
from ego.devices.leds import LedValue
from ego.serial.link import LinkSettings
from ego.serial.protocol import Firmware


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
