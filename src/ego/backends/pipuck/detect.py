"""Which robot carries the Pi-puck, and the first word with it: the channel opened, or one
line naming why not (the bus, the selector, the firmware, the ``i2c`` group).

Detection reads identity registers only, which change nothing: the MPU-9250's WHO_AM_I
(0x71 at 0x68 or 0x69) means an e-puck2, the LSM330 accelerometer's (0x40 at 0x1E) an
e-puck1 rev 1.3. Otherwise the e-puck2's stop message is sent (zero speeds, LEDs off,
checksum 0): an e-puck2 answers it with a valid checksum. York's firmware would take it
as register 0 (its ring LEDs) set to 0, which is harmless; but an answer is never proof
of an e-puck1, so an older e-puck1 is named with ``robot='epuck'``.
"""

from __future__ import annotations

from pathlib import Path

from ego.backends.pipuck.beside import Battery
from ego.backends.pipuck.bus import RobotBus
from ego.backends.pipuck.channel import PipuckChannel
from ego.backends.pipuck.chips import LSM330_ACC, LSM330_GYRO, MPU9250_ACC, MPU9250_GYRO, Reader
from ego.backends.pipuck.epuck2 import Epuck2Side
from ego.backends.pipuck.york import IR_CONTROL
from ego.backends.pipuck.york_side import YorkSide
from ego.errors import ChecksumError, EgoError, LinkTimeoutError
from ego.seam.channel import FirmwareInfo

__all__ = ["detect", "open_robot"]

#: What an e-puck2 needs to answer at 0x1F (docs/guide/pipuck.md, "The robot's firmware").
EPUCK2_NEEDS = (
    "is it an e-puck2 with its selector at 10, running GCtronic's firmware with the "
    "Pi-puck's I2C mode? (an e-puck1 needs York's firmware and robot='epuck')"
)
EPUCK1_NEEDS = (
    "is it an e-puck1 running York's Pi-puck firmware (yorkrobotlab/pi-puck-e-puck1)? "
    "(an e-puck2 needs selector 10 and robot='epuck2')"
)


def _why(name: str, what: str, exc: BaseException, needs: str) -> str:
    """One line: ``name``, what went wrong, the error's own words, what the robot needs."""
    detail = str(exc).replace(f"{name}: ", "")
    return f"{name}: {what} ({detail})" + (f"; {needs}" if needs else "")


def _answers(bus: RobotBus, reader: Reader) -> bool:
    assert reader.identity is not None
    register, expected = reader.identity
    for address in reader.addresses:
        try:
            if bus.read_byte(address, register) == expected:
                return True
        except OSError:
            continue
    return False


def detect(bus: RobotBus) -> str | None:
    """"epuck2" or "epuck" from the IMU that answers on ``bus``; None if neither does."""
    if _answers(bus, MPU9250_ACC):
        return "epuck2"
    if _answers(bus, LSM330_ACC):
        return "epuck"
    return None


def open_robot(bus: RobotBus, robot: str | None, board_bus: int, sysfs: Path) -> PipuckChannel:
    """The channel to the robot on ``bus`` (``robot`` None: detected), its first
    exchange done; LinkTimeoutError in one line when nothing answers at 0x1F."""
    name = f"pipuck ({bus.path})"
    battery = Battery(sysfs, board_bus)
    chosen = robot or detect(bus)
    if chosen in ("epuck2", None):
        side = Epuck2Side(bus, name)
        try:
            side.stop_message()
        except ChecksumError as exc:
            if chosen is None:  # junk back: York's firmware would answer so [inferred]
                raise LinkTimeoutError(_why(name, "no e-puck2 answers at 0x1F", exc,
                                            EPUCK2_NEEDS)) from None  # fmt: skip
            raise ChecksumError(_why(name, "the e-puck2's replies fail", exc, "")) from None
        except EgoError as exc:
            raise LinkTimeoutError(_why(name, "no e-puck2 answers at 0x1F", exc,
                                        EPUCK2_NEEDS)) from None  # fmt: skip
        reply = side.reply
        info = FirmwareInfo(side.profile, "e-puck2 I2C mode (gumstix)",
                            selector=None if reply is None else reply.selector)  # fmt: skip
        return PipuckChannel(name, bus, side, (MPU9250_ACC, MPU9250_GYRO), battery, info,
                             play=side.play, calibrate=side.calibrate)  # fmt: skip
    york = YorkSide(bus, name)
    try:
        bus.read_word(0x1F, IR_CONTROL)
        york.stop_message()
    except (OSError, EgoError) as exc:
        raise LinkTimeoutError(_why(name, "no e-puck1 answers at 0x1F", exc,
                                    EPUCK1_NEEDS)) from None  # fmt: skip
    info = FirmwareInfo(york.profile, "York's Pi-puck e-puck1 firmware")
    return PipuckChannel(name, bus, york, (LSM330_ACC, LSM330_GYRO), battery, info)
