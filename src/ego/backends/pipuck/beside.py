"""What the Pi reads beside the e-puck's microcontroller: the IMU, the ToF and the ground
module on the robot's bus, and the battery through the Pi-puck's ADC in sysfs.

Each chip is found at its first use (its identity register read, its setup written) and
read each time its family is due. A chip that does not answer is refused with
UnsupportedDeviceError naming it, its address and the bus, never read as zeros.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from pathlib import Path
from typing import Final

from ego.backends.pipuck.bus import RobotBus, i2c_failure
from ego.backends.pipuck.chips import Reader
from ego.errors import LinkTimeoutError, ProtocolError, UnsupportedDeviceError

__all__ = ["BATTERY_PATHS", "Battery", "ChipReader", "Tof", "battery_volts"]

log = logging.getLogger(__name__)


class ChipReader:
    """One chip's readings on ``bus``, found at first need."""

    def __init__(self, bus: RobotBus, reader: Reader) -> None:
        self.bus = bus
        self.reader = reader
        self._address: int | None = None
        self._address_was = reader.addresses[0]

    def _find(self) -> int:
        reader = self.reader
        for address in reader.addresses:
            try:
                if reader.identity is not None:
                    register, expected = reader.identity
                    if self.bus.read_byte(address, register) != expected:
                        continue
                else:
                    self.bus.read_block(address, reader.register, reader.count)
                for register, value in reader.setup:
                    self.bus.write_byte(address, register, value)
            except OSError:
                continue
            return address
        where = "/".join(f"0x{a:02X}" for a in reader.addresses)
        raise UnsupportedDeviceError(
            f"no {reader.name} answers at {where} on {self.bus.path}: this robot has none "
            "(or it is not fitted)"
        )

    def read(self) -> tuple[int, ...]:
        """One reading, as the wire command's values."""
        if self._address is None:
            self._address = self._find()
        try:
            data = self.bus.read_block(self._address, self.reader.register, self.reader.count)
        except OSError as exc:
            self._address_was, self._address = self._address, None
            where = f"the {self.reader.name} at 0x{self._address_was:02X} on {self.bus.path}"
            raise UnsupportedDeviceError(i2c_failure(exc, where)) from None
        return self.reader.decode(data)


#: VL53L0X registers (ST's VL53L0X API register map, as Pololu's library names them).
TOF_ADDRESS: Final = 0x29
_MODEL_ID: Final = (0xC0, 0xEE)
_SYSRANGE_START: Final = 0x00
_BACK_TO_BACK: Final = 0x02
_INTERRUPT_CONFIG_GPIO: Final = 0x0A
_NEW_SAMPLE_READY: Final = 0x04
_GPIO_HV_MUX_ACTIVE_HIGH: Final = 0x84
_INTERRUPT_CLEAR: Final = 0x0B
_INTERRUPT_STATUS: Final = 0x13
_RANGE_MM: Final = 0x14 + 10  # RESULT_RANGE_STATUS + 10: the range, big-endian
_STOP_VARIABLE: Final = 0x91
#: How long the first range may take (a ranging takes about 33 ms by default).
FIRST_RANGE_S: Final = 0.2


class Tof:
    """The VL53L0X at 0x29, ranging back to back; each read hands the newest range (mm).

    The start is the part of ST's sequence (as Pololu's library, VL53L0X.cpp ``begin``,
    ``startContinuous``, ``readRangeContinuousMillimeters``, follows it) that ranging
    needs: I2C standard mode (0x88 = 0), the "stop variable" read from 0x91 and written
    back before starting, the interrupt set to "new sample ready" (0x0A = 0x04, active
    low), then back-to-back ranging (0x00 = 0x02). A range is read when the interrupt
    status (0x13, bits 0-2) says one is ready, and the interrupt cleared (0x0B = 1)
    [inferred: ego loads neither ST's tuning settings nor the SPAD map nor the reference
    calibration, which the e-puck2 firmware does when it owns the chip].
    """

    def __init__(self, bus: RobotBus, clock: Callable[[], float] = time.monotonic) -> None:
        self.bus = bus
        self._clock = clock
        self._started = False
        self._last: int | None = None

    def _paged(self, *writes: tuple[int, int]) -> None:
        for register, value in writes:
            self.bus.write_byte(TOF_ADDRESS, register, value)

    def _start(self) -> None:
        try:
            model = self.bus.read_byte(TOF_ADDRESS, _MODEL_ID[0])
            if model != _MODEL_ID[1]:
                raise OSError(f"model id 0x{model:02X}, not 0x{_MODEL_ID[1]:02X}")
            self._paged((0x88, 0x00), (0x80, 0x01), (0xFF, 0x01), (0x00, 0x00))
            stop = self.bus.read_byte(TOF_ADDRESS, _STOP_VARIABLE)
            self._paged((0x00, 0x01), (0xFF, 0x00), (0x80, 0x00))
            self._paged((_INTERRUPT_CONFIG_GPIO, _NEW_SAMPLE_READY))
            mux = self.bus.read_byte(TOF_ADDRESS, _GPIO_HV_MUX_ACTIVE_HIGH)
            self._paged((_GPIO_HV_MUX_ACTIVE_HIGH, mux & ~0x10), (_INTERRUPT_CLEAR, 0x01))
            self._paged((0x80, 0x01), (0xFF, 0x01), (0x00, 0x00), (_STOP_VARIABLE, stop),
                        (0x00, 0x01), (0xFF, 0x00), (0x80, 0x00))  # fmt: skip
            # Started, the interrupt is cleared once more: harmless before the first range,
            # and what a model that completes a range per clear needs [inferred].
            self._paged((_SYSRANGE_START, _BACK_TO_BACK), (_INTERRUPT_CLEAR, 0x01))
        except OSError as exc:
            raise UnsupportedDeviceError(
                f"no VL53L0X ToF answers at 0x{TOF_ADDRESS:02X} on {self.bus.path}: {exc}"
            ) from None
        self._started = True

    def _ready(self) -> int | None:
        if not self.bus.read_byte(TOF_ADDRESS, _INTERRUPT_STATUS) & 0x07:
            return None
        data = self.bus.read_block(TOF_ADDRESS, _RANGE_MM, 2)
        self.bus.write_byte(TOF_ADDRESS, _INTERRUPT_CLEAR, 0x01)
        return int.from_bytes(data, "big")

    def read(self) -> tuple[int, ...]:
        if not self._started:
            self._start()
        deadline = self._clock() + FIRST_RANGE_S
        while True:
            try:
                found = self._ready()
            except OSError as exc:
                where = f"the VL53L0X at 0x{TOF_ADDRESS:02X} on {self.bus.path}"
                raise UnsupportedDeviceError(i2c_failure(exc, where)) from None
            if found is not None:
                self._last = found
            if self._last is not None:
                return (self._last,)
            if self._clock() > deadline:
                raise LinkTimeoutError(
                    f"the VL53L0X on {self.bus.path} gave no range within {FIRST_RANGE_S} s"
                )
            time.sleep(0.002)


#: The e-puck's battery on the Pi-puck's ADS1015 (board bus, 0x48), channel 0: the iio
#: driver's raw count and scale (mV a count) on current kernels, the hwmon driver's
#: millivolts on legacy ones (GCtronic's battery/read-battery.py:4-8, 24-48).
BATTERY_PATHS: Final = (
    ("bus/i2c/devices/{board}-0048/iio:device0/in_voltage0_raw",
     "bus/i2c/devices/{board}-0048/iio:device0/in_voltage0_scale"),
    ("bus/i2c/drivers/ads1015/{board}-0048/in4_input", None),
)  # fmt: skip


def battery_volts(millivolts: int) -> float:
    """The battery's voltage from the ADC input's millivolts: read-battery.py:48 divides
    ``raw * scale`` by 500 (the board halves the battery's voltage)."""
    return millivolts / 500.0


class Battery:
    """The e-puck's battery through sysfs: millivolts at the ADC's input (half the
    battery's), 0..4095, which :func:`battery_volts` turns into volts."""

    def __init__(self, sysfs: Path, board_bus: int) -> None:
        self.sysfs = sysfs
        self.board_bus = board_bus

    def read(self) -> tuple[int, ...]:
        for raw_pattern, scale_pattern in BATTERY_PATHS:
            raw_path = self.sysfs / raw_pattern.format(board=self.board_bus)
            if not raw_path.exists():
                continue
            try:
                raw = float(raw_path.read_text())
                scale = 1.0
                if scale_pattern is not None:
                    scale_path = self.sysfs / scale_pattern.format(board=self.board_bus)
                    scale = float(scale_path.read_text())
            except (OSError, ValueError) as exc:
                raise ProtocolError(f"the battery's ADC in {raw_path} reads badly: {exc}") from None
            return (max(0, min(4095, round(raw * scale))),)
        raise UnsupportedDeviceError(
            f"no battery ADC under {self.sysfs}/bus/i2c (the Pi-puck's ADS1015 at 0x48 on "
            f"bus {self.board_bus}): is the Pi-puck's device tree overlay loaded?"
        )
