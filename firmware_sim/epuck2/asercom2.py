"""run_asercom2, the e-puck2 main processor's serial protocol, byte for byte (no I/O, no
clock): MAIN:src/epuck1x/Asercom2.c. Written from the firmware, apart from ego.

Bytes go in with :meth:`Asercom2.feed`; what the firmware then does comes out as a list
of :class:`~firmware_sim.epuck2.state.Emission` (its own time, then bytes to send).

The main loop (Asercom2.c:163-1621) reads one byte ``c``: negative (>= 0x80) starts a
binary batch, positive an ASCII line, 0 is ignored. A binary batch runs commands until a
0, then sends all replies at once if there are any (1043-1061). An ASCII line first
skips ``\\r`` and ``\\n`` (1067-1070) -- blocking for the next byte, whatever it is -- so
a ``\\n`` behind a ``\\r``-ended line makes the next byte, even a binary one, the first of
a new line, which then runs to the next ``\\r`` or ``\\n``.
"""

from __future__ import annotations

import struct
from collections import deque
from collections.abc import Callable

from firmware_sim.epuck2.ascii import AsciiCommands
from firmware_sim.epuck2.camera import SENSOR_WIDTH, frame_rgb565_be
from firmware_sim.epuck2.imu import e_acc_spheric
from firmware_sim.epuck2.motors import uint16
from firmware_sim.epuck2.packet import ACTUATORS_SIZE, all_sensors, set_all_actuators
from firmware_sim.epuck2.robot import Epuck2Robot
from firmware_sim.epuck2.state import Emission, FirmwareState

__all__ = ["Asercom2"]

#: chThdSleepMilliseconds(10) after the USB reads of -0x09, -0x0F, -0x10, -0x11
#: (Asercom2.c:481, 643, 674, 706); the UART (Bluetooth, WiFi bridge) path has none.
USB_READ_SLEEP_S = 0.010
#: get_acc_filtered waits for the IMU thread in steps of 20 ms (MAIN:src/sensors/imu.c,
#: get_acc_filtered: ``while(accAxisFilteringInProgress) chThdSleepMilliseconds(20)``).
FILTER_WAIT_S = 0.020

_IDLE, _SKIP, _LINE, _BATCH, _ARGS, _HUNG = range(6)

Handler = Callable[["Asercom2", bytes], None]


class Asercom2:
    """One run of run_asercom2 over ``robot``. ``use_bt``: selector 3 or 15 (the UART to
    the radio: Bluetooth or the WiFi bridge) rather than 8 (USB); Asercom2.c:104-108."""

    def __init__(self, robot: Epuck2Robot, *, use_bt: bool) -> None:
        self.robot = robot
        self.use_bt = use_bt
        self.state = FirmwareState()
        self.ascii = AsciiCommands(robot, self.state, use_bt=use_bt)
        self._mode = _IDLE
        self._line = bytearray()
        self._reply = bytearray()
        self._pending: tuple[int, Handler] | None = None
        self._args = bytearray()
        self._out: list[Emission] = []
        #: Binary batches answered, and ASCII lines run (ground truth).
        self.batches = 0
        self.lines: deque[bytes] = deque(maxlen=10_000)

    def rc5(self, address: int, data: int, check: int = 0) -> None:
        """A TV remote's RC5 frame reaches the IR receiver: G and -0x08 report it.

        It never drives: the firmware's remote-control driving (Asercom2.c:167-290) runs
        only while e_getchar_uart1/2 return 0, and both block in chSequentialStreamRead
        until a byte comes (MAIN:src/epuck1x/uart/e_uart_char.c:16-18, 58-63); only a
        USB link that is not configured returns 0 (e_uart_char.c:64-66), and then there
        is no host to see it.
        """
        self.robot.rc5 = (check & 0xFF, address & 0xFF, data & 0xFF)

    @property
    def hung(self) -> bool:
        """Whether the firmware waits for ever (USB: -'w' reads the radio's UART)."""
        return self._mode == _HUNG

    def feed(self, data: bytes) -> list[Emission]:
        self._out = []
        for byte in data:
            self._byte(byte)
        out, self._out = self._out, []
        return out

    # -- the main loop ----------------------------------------------------------------

    def _byte(self, byte: int) -> None:
        mode = self._mode
        if mode == _HUNG:
            return
        if mode == _IDLE:
            if byte >= 0x80:
                self._mode = _BATCH
                self._command(byte)
            elif byte in (0x0A, 0x0D):
                self._mode = _SKIP  # 1067-1070: wait for the first byte that is not one
            elif byte:
                self._start_line(byte)
        elif mode == _SKIP:
            if byte not in (0x0A, 0x0D):
                self._start_line(byte)  # any byte, even >= 0x80 or 0
        elif mode == _LINE:
            self._line.append(byte)
            if byte in (0x0A, 0x0D):  # 1076-1081
                self._mode = _IDLE
                line, self._line = bytes(self._line), bytearray()
                self.lines.append(line)
                self._out += self.ascii.run(line)
        elif mode == _ARGS:
            self._args.append(byte)
            assert self._pending is not None
            needed, handler = self._pending
            if len(self._args) == needed:
                self._pending = None
                self._mode = _BATCH
                args, self._args = bytes(self._args), bytearray()
                handler(self, args)
        elif byte == 0:  # _BATCH: 1042, `while (c)`
            self._end_batch()
        else:
            self._command(byte)

    def _start_line(self, byte: int) -> None:
        self._mode = _LINE
        self._line = bytearray([byte])

    def _command(self, byte: int) -> None:
        code = (-byte) & 0xFF  # 295: switch ((int8_t)-c)
        entry = _BINARY.get(code)
        if entry is None:
            return  # 1032: default, silently ignored
        needed, handler = entry
        if needed == -1:  # -'w' on USB: e_getchar_uart1 waits on the radio's UART
            if not self.use_bt:
                self._mode = _HUNG
                return
            needed = _W_BYTES
        if needed:
            self._pending = (needed, handler)
            self._mode = _ARGS
        else:
            handler(self, b"")

    def _end_batch(self) -> None:
        self._mode = _IDLE
        self.batches += 1
        if self._reply:  # 1043: `if (i != 0)`
            self._out.append(Emission(bytes(self._reply)))
        self._reply = bytearray()

    def _work(self, seconds: float) -> None:
        self._out.append(Emission(b"", seconds))

    def _usb_read_sleep(self) -> None:
        if not self.use_bt:
            self._work(USB_READ_SLEEP_S)

    # -- binary commands (Asercom2.c:296-1033) -----------------------------------------

    def _all_sensors(self, args: bytes) -> None:
        self._reply += all_sensors(self.robot)

    def _all_actuators(self, args: bytes) -> None:
        self._usb_read_sleep()
        set_all_actuators(self.robot, self.state, args)

    def _rgb(self, args: bytes) -> None:  # 574-588
        for i in range(4):
            self.robot.leds.set_rgb_led(i, *args[3 * i : 3 * i + 3])

    def _button(self, args: bytes) -> None:  # 590-592
        self._reply.append(1 if self.robot.button else 0)

    def _mics(self, args: bytes) -> None:  # 594-610
        self._reply += struct.pack("<4H", *self.robot.microphones.volumes())

    def _tof(self, args: bytes) -> None:  # 612-621
        self._reply += struct.pack("<H", self.robot.tof.distance_mm())

    def _sd(self, args: bytes) -> None:  # 623-631
        self._reply.append(1 if self.robot.sd_card else 0)

    def _magnetometer(self, args: bytes) -> None:  # 633-662: only 1 switches it on
        self._usb_read_sleep()
        if args[0] == 1:
            self.robot.imu.magnetometer_on = True
        self._reply.append(0)

    def _proximity_mode(self, args: bytes) -> None:  # 664-694: 0 off, 1 fast, 2 slow
        self._usb_read_sleep()
        self.robot.proximity.sampling = args[0] in (1, 2)
        self._reply.append(0)

    def _tof_enable(self, args: bytes) -> None:  # 696-725
        self._usb_read_sleep()
        self.robot.tof.running = args[0] != 0
        self._reply.append(0)

    def _acc_filtered(self, args: bytes) -> None:  # 727-746
        self._work(3 * FILTER_WAIT_S)
        self._reply += b"".join(struct.pack("<H", uint16(v))
                                for v in self.robot.imu.e_get_acc_filtered())  # fmt: skip

    def _acc_spheric(self, args: bytes) -> None:  # 748-782
        self._reply += struct.pack("<3f", *e_acc_spheric(*self.robot.imu.e_get_acc()))

    def _battery(self, args: bytes) -> None:  # 784-789
        self._reply += struct.pack("<H", self.robot.battery.raw())

    def _set_speed(self, args: bytes) -> None:  # 791-814: unsigned, then int16 in e_motors
        self.state.speedl = args[0] + (args[1] << 8)
        self.state.speedr = args[2] + (args[3] << 8)
        self.robot.set_speeds(self.state.speedl, self.state.speedr)

    def _get_speed(self, args: bytes) -> None:  # 815-820
        self._reply += struct.pack("<2H", uint16(self.state.speedl), uint16(self.state.speedr))

    def _gyro(self, args: bytes) -> None:  # 822-839
        self._reply += b"".join(struct.pack("<H", uint16(v)) for v in self.robot.imu.gyro())

    def _image(self, args: bytes) -> None:  # 841-851, 1043-1050
        s = self.state
        self._reply += bytes([s.cam_mode & 0xFF, s.cam_width & 0xFF, s.cam_height & 0xFF])
        zoom = s.cam_zoom if s.cam_zoom in (1, 2, 4) else 4  # e_common.c:25-57
        window = min(SENSOR_WIDTH, s.cam_width * zoom)
        frame = frame_rgb565_be(self.robot.world, s.cam_width, s.cam_height, window)
        if s.cam_mode == 0:  # grey: the high byte stands in for the luminance
            frame = frame[0::2]
        self._reply += frame[: s.cam_size]

    def _set_led(self, args: bytes) -> None:  # 852-873: 8 body, 9 front, else e_set_led
        number, value = args
        if number == 8:
            self.robot.leds.set_body_led(value)
        elif number == 9:
            self.robot.leds.set_front_led(value)
        else:
            self.robot.leds.e_set_led(number, value)

    def _floor(self, args: bytes) -> None:  # 874-894: 3 ground + 1 cliff (CLIFF_SENSORS)
        self._reply += struct.pack("<4H", *self.robot.ground.delta()[:4])

    def _proximity(self, args: bytes) -> None:  # 895-901
        self._reply += struct.pack("<8H", *map(uint16, self.robot.proximity.calibrated()))

    def _light(self, args: bytes) -> None:  # 902-908
        self._reply += struct.pack("<8H", *map(uint16, self.robot.proximity.ambient()))

    def _set_position(self, args: bytes) -> None:  # 910-933: unsigned 16-bit values
        self.state.positionl = args[0] + (args[1] << 8)
        self.state.positionr = args[2] + (args[3] << 8)
        self.robot.set_steps(self.state.positionl, self.state.positionr)

    def _get_position(self, args: bytes) -> None:  # 934-941
        self._reply += struct.pack("<2H", *map(uint16, self.robot.steps()))

    def _temperature(self, args: bytes) -> None:  # 943-949: 0 unless on the gumstix
        self._reply.append(0)

    def _mic_volumes(self, args: bytes) -> None:  # 951-963: mic0..mic2
        self._reply += struct.pack("<3H", *self.robot.microphones.volumes()[:3])

    def _nothing(self, args: bytes) -> None:
        """-'U' (964-975: all commented out), -'W' (976-991: an I2C write), -'w' over
        the UART (992-1016: an RGB panel write): no reply."""

    def _i2c_read(self, args: bytes) -> None:  # 1017-1031: no device modelled, reads 0
        self._reply.append(0)


#: -'w' reads 24 + 3 + 8 bytes (Asercom2.c:995-1003).
_W_BYTES = 35

_BINARY: dict[int, tuple[int, Handler]] = {
    0x08: (0, Asercom2._all_sensors),
    0x09: (ACTUATORS_SIZE, Asercom2._all_actuators),
    0x0A: (12, Asercom2._rgb),
    0x0B: (0, Asercom2._button),
    0x0C: (0, Asercom2._mics),
    0x0D: (0, Asercom2._tof),
    0x0E: (0, Asercom2._sd),
    0x0F: (1, Asercom2._magnetometer),
    0x10: (1, Asercom2._proximity_mode),
    0x11: (1, Asercom2._tof_enable),
    ord("a"): (0, Asercom2._acc_filtered),
    ord("A"): (0, Asercom2._acc_spheric),
    ord("b"): (0, Asercom2._battery),
    ord("D"): (4, Asercom2._set_speed),
    ord("E"): (0, Asercom2._get_speed),
    ord("g"): (0, Asercom2._gyro),
    ord("I"): (0, Asercom2._image),
    ord("L"): (2, Asercom2._set_led),
    ord("M"): (0, Asercom2._floor),
    ord("N"): (0, Asercom2._proximity),
    ord("O"): (0, Asercom2._light),
    ord("P"): (4, Asercom2._set_position),
    ord("Q"): (0, Asercom2._get_position),
    ord("t"): (0, Asercom2._temperature),
    ord("u"): (0, Asercom2._mic_volumes),
    ord("U"): (0, Asercom2._nothing),
    ord("W"): (3, Asercom2._nothing),
    ord("w"): (-1, Asercom2._nothing),
    ord("Y"): (2, Asercom2._i2c_read),
}
