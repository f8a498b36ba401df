"""The e-puck1's dsPIC running York's Pi-puck firmware: an I2C slave at 0x1F with a map
of 16-bit registers.

Written from yorkrobotlab/pi-puck-e-puck1@00417163f55be8f9d922298b4ec57342abb85625,
``pi-puck-e-puck1.X/`` (cited as file:line):

* Slave address 0x1F (i2c_slave.c:31). 256 registers, each a 16-bit union of a low and
  a high byte (i2c_slave.h:6-17, i2c_slave.c:7), zero at start (main.c:17-19).
* A write's first byte is the register (i2c_slave.c:59-64); the next byte is its low
  byte and clears the high byte (:65-71); the byte after is the high byte (:72-76);
  any further bytes are ignored. A read sends the low then the high byte of the last
  register named (:78-87); the pointer never steps.
* The main loop (main.c:44-115) then acts on what changed and refreshes the sensors:
  register 0 the outer LEDs, bit i LED i (its high byte cleared; leds.c:30-40);
  register 1 bit 0 front, bit 1 body (masked to 0x0003; leds.c:42-46); registers 2 and
  3 the left and right speeds, signed, clamped to +-1000 and written back clamped
  (main.c:59-78); registers 4 and 5 the step counters, unsigned 16-bit, wrapping
  (main.c:80-81, motors.c:30-31, 232-244); register 6 bit 0 starts or stops the IR
  sampling (masked to 0x0001; main.c:83-94); registers 7-14 the reflected IR
  (ambient less lit, so higher is closer) and 15-22 the ambient IR as 4095 less the
  ADC value (so higher is brighter) (main.c:96-112, ir_sensors.c:155-176). Before the
  first start the IR values are 0 and 4095 (the ADC arrays start at 0); stopped, they
  hold.
* A wheel steps at (FCY / 256) / PR5 Hz with PR5 = (FCY / 256) / |speed| truncated,
  FCY = 7.3728 MHz * 8 / 4 (motors.c:173-195, system.h:6-8), so 57600 / (57600 // v).

[inferred]: a read past the second byte gets 0xFF (the slave loads nothing more);
the main loop runs once before each transaction and once after each write, so a
written value is acted on at once and a read sees fresh sensors.
"""

from __future__ import annotations

from collections import deque

from firmware_sim.world import World

__all__ = ["YORK_ADDRESS", "YorkEpuck1", "york_stepping_rate"]

YORK_ADDRESS = 0x1F
MAX_SPEED = 1000
TIMER_HZ = 57600  # FCY / 256 with FCY = 7.3728e6 * 8 / 4


def york_stepping_rate(speed_steps: int) -> float:
    """Steps a second a wheel makes at ``speed_steps`` (motors.c:173-195)."""
    v = max(-MAX_SPEED, min(MAX_SPEED, int(speed_steps)))
    if v == 0:
        return 0.0
    rate = TIMER_HZ / (TIMER_HZ // abs(v))
    return rate if v > 0 else -rate


def _s16(value: int) -> int:
    return ((value + 0x8000) & 0xFFFF) - 0x8000


class YorkEpuck1:
    """The dsPIC's registers over a firmware_sim World (an I2C ``Target``)."""

    address = YORK_ADDRESS

    def __init__(self, world: World) -> None:
        self.world = world
        world.max_speed_steps = MAX_SPEED
        world.motor_rate = york_stepping_rate
        self.regs = [0] * 256  # each the union's 16-bit value
        self.pointer = 0
        self._leds_outer = 0
        self._leds_front_body = 0
        self._motor = [0, 0]
        self._ir_control = 0
        self._reflected = [0] * 8
        self._ambient_adc = [0] * 8
        #: Register writes received (ground truth): (register, low, high or None), the
        #: last 10,000, and how many in all.
        self.writes: deque[tuple[int, int, int | None]] = deque(maxlen=10_000)
        self.write_count = 0
        self.main_loop()

    # -- i2c_slave.c ----------------------------------------------------------------

    def write(self, data: bytes) -> None:
        self.main_loop()
        if not data:
            return
        self.pointer = data[0]
        if len(data) >= 2:
            self.regs[self.pointer] = data[1]  # u_low, u_high = 0
        if len(data) >= 3:
            self.regs[self.pointer] = data[1] | data[2] << 8
        if len(data) >= 2:
            self.writes.append((self.pointer, data[1], data[2] if len(data) >= 3 else None))
            self.write_count += 1
            self.main_loop()

    def read(self, count: int) -> bytes:
        self.main_loop()
        value = self.regs[self.pointer]
        return bytes([value & 0xFF, value >> 8][:count]).ljust(count, b"\xff")

    def stop(self) -> None:
        pass

    # -- main.c ---------------------------------------------------------------------

    def main_loop(self) -> None:
        """One pass of main.c's loop (main.c:44-115)."""
        regs = self.regs
        if self._leds_outer != regs[0] & 0xFF:
            regs[0] &= 0xFF
            self._leds_outer = regs[0]
            for i in range(8):
                self.world.set_led(i, self._leds_outer >> i & 1)
        if self._leds_front_body != regs[1] & 0xFF:
            regs[1] &= 0x0003
            self._leds_front_body = regs[1]
            self.world.set_led(9, regs[1] & 1)  # front
            self.world.set_led(8, regs[1] >> 1 & 1)  # body
        for side in (0, 1):
            value = _s16(regs[2 + side])
            if self._motor[side] != value:
                value = max(-MAX_SPEED, min(MAX_SPEED, value))
                regs[2 + side] = value & 0xFFFF
                self._motor[side] = value
                self.world.set_speeds(*self._motor)
        left, right = self.world.step_counts()
        regs[4], regs[5] = int(left // 1) & 0xFFFF, int(right // 1) & 0xFFFF
        if self._ir_control != regs[6] & 0xFF:
            regs[6] &= 0x0001
            self._ir_control = regs[6]
        if self._ir_control & 1:
            self._reflected = self.world.proximity()
            self._ambient_adc = self.world.light()
        for i in range(8):
            regs[7 + i] = self._reflected[i] & 0xFFFF
            regs[15 + i] = (4095 - self._ambient_adc[i]) & 0xFFFF

    # -- ground truth -----------------------------------------------------------------

    @property
    def speeds(self) -> tuple[int, int]:
        return self._motor[0], self._motor[1]

    @property
    def ir_enabled(self) -> bool:
        return bool(self._ir_control & 1)
