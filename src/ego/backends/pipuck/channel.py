"""A robot through a Pi-puck as a :class:`~ego.seam.channel.Channel`: each batch's setters
go to the microcontroller's side, its getters are answered from that side's reply, the
chips beside it, or the battery, packed in the profile's wire formats.

The stop at close: :meth:`PipuckChannel._close` sends zero speeds and every LED off
(with a valid checksum on the e-puck2) whatever ego believes the robot's state is, after
the Robot's own confirmed stop batch, and logs an error if the robot does not take it.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import Protocol

from ego.backends.pipuck.beside import Battery, ChipReader, Tof
from ego.backends.pipuck.bus import RobotBus
from ego.backends.pipuck.chips import GROUND, Reader
from ego.errors import EgoError, UnsupportedDeviceError
from ego.seam.batch import Batch, Request
from ego.seam.channel import ChannelBase, FirmwareInfo
from ego.seam.profile import Command, Profile

__all__ = ["McuSide", "PipuckChannel"]

log = logging.getLogger(__name__)

_SETTERS = frozenset({Command.SET_SPEED, Command.SET_LED, Command.SET_STEPS, Command.RGB_LEDS})


class McuSide(Protocol):
    """The microcontroller's side: the e-puck2's packet or York's registers."""

    retries: int

    @property
    def profile(self) -> Profile: ...

    @property
    def answers(self) -> frozenset[Command]: ...

    def fold(self, request: Request) -> None: ...

    def sync(self, getters: tuple[Command, ...]) -> None: ...

    def answer(self, command: Command) -> tuple[int, ...]: ...

    def stop_message(self) -> None: ...


class PipuckChannel(ChannelBase):
    """The robot behind a Pi-puck: ``side`` on ``bus``, with ``imu`` readers for the
    accelerometer and the gyro and the battery in ``battery``."""

    def __init__(
        self,
        name: str,
        bus: RobotBus,
        side: McuSide,
        imu: tuple[Reader, Reader],
        battery: Battery,
        info: FirmwareInfo,
        *,
        play: Callable[[int], None] | None = None,
        calibrate: Callable[[], None] | None = None,
    ) -> None:
        super().__init__()
        self._name = name
        self.bus = bus
        self.side = side
        self._info = info
        self._play = play
        self._calibrate = calibrate
        tof = Tof(bus)
        readers = {
            Command.ACCELEROMETER_RAW: ChipReader(bus, imu[0]).read,
            Command.GYRO_RAW: ChipReader(bus, imu[1]).read,
            Command.FLOOR: ChipReader(bus, GROUND).read,
            Command.TOF: tof.read,
            Command.BATTERY: battery.read,
        }
        self._beside: dict[Command, Callable[[], tuple[int, ...]]] = readers

    @property
    def name(self) -> str:
        return self._name

    def _exchange(self, batch: Batch) -> bytes:
        profile = self.side.profile
        getters: list[Command] = []
        for request in batch.requests:
            command = request.command
            if command is Command.END:
                continue
            profile.wire_format(command)  # UnsupportedDeviceError naming the firmware
            if command in _SETTERS:
                self.side.fold(request)
            else:
                getters.append(command)
        self.side.sync(tuple(c for c in getters if c in self.side.answers))
        self._stats.retries = self.side.retries
        out = bytearray()
        for command in getters:
            read = self._beside.get(command)
            values = read() if read is not None else self.side.answer(command)
            out += profile.commands[command].reply.pack(*values)
        return bytes(out)

    def _ascii_command(self, letter: str, lines: int) -> list[str]:
        head, _, number = letter.partition(",")
        if head.upper() == "T" and self._play is not None and number.strip().isdigit():
            self._play(int(number))
            return ["t"]
        raise UnsupportedDeviceError(
            f"{self._name}: the Pi-puck's I2C link carries no ASCII commands ({letter!r}); "
            "the e-puck's Bluetooth (or the e-puck2's USB) serves them"
        )

    def _calibrate_proximity(self) -> list[str]:
        if self._calibrate is None:
            raise UnsupportedDeviceError(
                f"{self._name}: York's register map has no IR calibration; the e-puck1's "
                "Bluetooth (stock firmware, K) serves it"
            )
        self._calibrate()
        time.sleep(self.side.profile.calibration_s)  # calibrate_ir averages meanwhile
        return []

    def _close(self) -> None:
        try:
            self.side.stop_message()
        except EgoError as exc:
            log.error("%s: could not send the stop before closing: %s", self._name, exc)
        finally:
            self.bus.close()
