"""The e-puck2's VL53L0X time-of-flight sensor at 0x29, as far as a driver reading a
distance needs it.

Register addresses from the ST API the e-puck2 firmware carries
(e-puck2_main-processor@d2e0dbb src/sensors/VL53L0X/Api/core/inc/vl53l0x_device.h):
SYSRANGE_START 0x00 (:123-139: bit 0 starts, bit 1 picks back-to-back over single
shot), SYSTEM_INTERRUPT_CLEAR 0x0B (:161), RESULT_INTERRUPT_STATUS 0x13 (:164), the
12-byte result block from RESULT_RANGE_STATUS 0x14 (:165) whose bytes 10-11 (0x1E-0x1F)
are the range in mm, high byte first (vl53l0x_api.c:2411-2418), the model id 0xEE at
0xC0 (:215) and the revision at 0xC2 (:216). Register 0xFF selects a page; the stop
variable the API saves lives at 0x91 on page 1 (vl53l0x_api.c:438). The distance is the
e-puck2 model's ray from the sensor to the first face (firmware_sim.epuck2.sensors,
``TimeOfFlight.measure_mm``: 2 m reach, 8190 mm with no target).

[inferred, the sources being ST's closed register map]: a measurement completes at
once: after a start (single shot) or an interrupt clear (back-to-back) the status reads
0x04 ("new sample ready") and SYSRANGE_START's bit 0 reads 0 again; the range is taken
when the result is first read (the freshest a real 33 ms measurement could be); the range status
byte reads 0x58 (device status 11, range valid) or 0x20 (status 4, no target) with a
signal rate of 0x0280; 0x83 never reads 0 on any page (the NVM handshake a driver waits on), and
every other register reads back what was written (the ST API's reference SPAD and NVM
calibration reads see zeros).
"""

from __future__ import annotations

import struct

from firmware_sim.epuck2.sensors import TimeOfFlight
from firmware_sim.pipuck.registers import RegisterTarget

__all__ = ["Vl53l0x"]

SYSRANGE_START, SYSTEM_INTERRUPT_CLEAR, RESULT_INTERRUPT_STATUS = 0x00, 0x0B, 0x13
RESULT_RANGE_STATUS, PAGE, NVM_HANDSHAKE = 0x14, 0xFF, 0x83
IDENTITY = {0xC0: 0xEE, 0xC1: 0xAA, 0xC2: 0x10}
NEW_SAMPLE_READY = 0x04
VALID, NO_TARGET = 11 << 3, 4 << 3
SIGNAL_RATE = 0x0280


class Vl53l0x(RegisterTarget):
    """The sensor over the e-puck2 model's ``TimeOfFlight`` (its geometry and noise)."""

    address = 0x29

    def __init__(self, tof: TimeOfFlight) -> None:
        super().__init__(IDENTITY)
        self.tof = tof
        self._pages: dict[int, bytearray] = {}
        self._ready = False
        self._due = False  # a measurement started and not yet looked at
        self._result = bytes(12)

    def _page(self) -> bytearray:
        page = self.regs[PAGE]
        return self.regs if page == 0 else self._pages.setdefault(page, bytearray(256))

    def _measure(self) -> None:
        """Start a measurement: it is ready at once and ranges when first read."""
        self._ready = self._due = True

    def snapshot(self) -> None:
        if self._due:
            self._due = False
            mm = self.tof.measure_mm()
            status = NO_TARGET if mm >= self.tof.OUT_OF_RANGE_MM else VALID
            self._result = struct.pack(">B5xH2xH", status, SIGNAL_RATE, mm)

    def put(self, register: int, value: int) -> None:
        if register == PAGE:
            self.regs[PAGE] = value
            return
        if self.regs[PAGE] != 0:
            self._page()[register] = value
            return
        if register == SYSRANGE_START:
            self.regs[register] = value & 0x0E  # bit 0 clears when the start is taken
            if value & 0x01:
                self._measure()
            return
        if register == SYSTEM_INTERRUPT_CLEAR:
            self._ready = False
            if self.regs[SYSRANGE_START] & 0x02:  # back-to-back: the next one is there
                self._measure()
            return
        self.regs[register] = value

    def get(self, register: int) -> int:
        if register == PAGE:
            return self.regs[PAGE]
        if register == NVM_HANDSHAKE:
            return self._page()[register] | 0x10
        if self.regs[PAGE] != 0:
            return self._page()[register]
        if register == RESULT_INTERRUPT_STATUS:
            return NEW_SAMPLE_READY if self._ready else 0
        if RESULT_RANGE_STATUS <= register < RESULT_RANGE_STATUS + 12:
            return self._result[register - RESULT_RANGE_STATUS]
        return self.regs[register]
