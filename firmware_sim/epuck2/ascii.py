"""run_asercom2's ASCII commands, one line each (MAIN:src/epuck1x/Asercom2.c:1063-1620).

A line is its first byte (upper-cased unless it is ``b`` or ``g``, 1084-1086) and what
follows up to its ``\\r`` or ``\\n``; arguments are parsed with ``sscanf``, so a bad or
missing number leaves the static it would have set as it was. So ``t`` is ``T`` (sound),
``L,8``/``L,9`` go through e_set_led and light every ring LED, ``S`` leaves the body and
front LEDs and the speeds E reports, and ``R`` answers nothing (its code is commented out).
"""

from __future__ import annotations

from collections.abc import Callable

from firmware_sim.epuck2.robot import Epuck2Robot
from firmware_sim.epuck2.state import CAM_DEFAULT, IMAGE_MAX_SIZE, Emission, FirmwareState
from firmware_sim.epuck2.state import sscanf_ints as scan

__all__ = ["HELP_BT", "HELP_USB", "HW_VERSION", "VERSION", "AsciiCommands"]

#: Asercom2.c:1547/1549, then 1551 prints the EEPROM word.
VERSION = "v,Version 2.0 January 2018 GCtronic\r\n"
#: The word ReadEE hands back for the e-puck1's camera slot: the e-puck2 has no EEPROM
#: and one camera, a PO8030 with no rotation (MAIN:src/epuck1x/DataEEPROM.c:3-12).
HW_VERSION = 0xFFF7
#: K: the firmware lights the ring, waits (a 1e6-step loop and 400 ms), clears it, waits
#: 100 ms more (1362-1368), then calibrates: 100 samples of the 100 Hz proximity sampling
#: (proximity.c:26, 210-228), about a second [the loops' time inferred].
K_WAIT_S = 0.5
K_CALIBRATE_S = 1.0
#: Asercom2.c:1275-1310 (USB) and 1234-1273 (UART), isEpuckVersion1_3() being 1 on the
#: e-puck2 (MAIN:src/epuck1x/motor_led/e_init_port.c:43-45).
HELP_USB = "\n" + "".join(s + "\r\n" for s in (
    '"b"       Battery value', '"B,#"       Body led 0=off 1=on 2=inverse',
    '"C"       Selector position', '"D,#,#"   Set motor speed left,right',
    '"E"       Get motor speed left,right', '"F,#"       Front led 0=off 1=on 2=inverse',
    '"G"       IR receiver', '"H"       Help', '"I"         Get camera parameter',
    '"J,#,#,#,#,#,#" Set camera parameter mode,width,heigth,zoom(1,4 or 8),x1,y1',
    '"K"       Calibrate proximity sensors', '"L,#,#"   Led number,0=off 1=on 2=inverse',
    '"M"       Floor sensors', '"N"       Proximity', '"O"       Light sensors',
    '"P,#,#"   Set motor position left,right', '"Q"       Get motor position left,right',
    '"R"       Reset e-puck', '"S"       Stop e-puck and turn off leds',
    '"T,#"       Play sound 1-5 else stop sound', '"U"       Get microphone amplitude',
    '"V"       Version of SerCom', '"W"         Write I2C (mod,reg,val)',
    '"Y"         Read I2C val=(mod,reg)'))  # fmt: skip
HELP_BT = "\n" + "".join(s + "\r\n" for s in (
    '"A"               Accelerometer', '"B,#"             Body led 0=off 1=on 2=inverse',
    '"b"               Battery value', '"C"               Selector position',
    '"D,#,#"           Set motor speed left,right',
    '"E"               Get motor speed left,right',
    '"F,#"             Front led 0=off 1=on 2=inverse', '"G"               IR receiver',
    '"g"               Gyro', '"H"               Help',
    '"I"               Get camera parameter',
    '"J,#,#,#,#,#,#"   Set camera parameter mode,width,heigth,zoom(1,4 or 8),x1,y1',
    '"K"               Calibrate proximity sensors',
    '"L,#,#"           Led number,0=off 1=on 2=inverse', '"M"               Floor sensors',
    '"N"               Proximity', '"O"               Light sensors',
    '"P,#,#"           Set motor position left,right',
    '"Q"               Get motor position left,right', '"R"               Reset e-puck',
    '"S"               Stop e-puck and turn off leds',
    '"T,#"             Play sound 1-5 else stop sound', '"t"               Temperature',
    '"U"               Get microphone amplitude', '"V"               Version of SerCom',
    '"W"               Write I2C (mod,reg,val)',
    '"Y"               Read I2C val=(mod,reg)'))  # fmt: skip


def _csv(letter: str, values: list[int] | tuple[int, ...]) -> str:
    return letter + "," + ",".join(str(v) for v in values) + "\r\n"


class AsciiCommands:
    """The switch of Asercom2.c:1087-1619 over one robot and the shared statics."""

    def __init__(self, robot: Epuck2Robot, state: FirmwareState, *, use_bt: bool) -> None:
        self.robot = robot
        self.state = state
        self.use_bt = use_bt

    def run(self, line: bytes) -> list[Emission]:
        first = line[0]
        if first not in (ord("b"), ord("g")) and ord("a") <= first <= ord("z"):
            first -= 32  # toupper, C locale: only a-z change
        text = chr(first) + line[1:].decode("latin-1")
        handler = _ASCII.get(chr(first))
        if handler is None:
            return [Emission(b"z,Command not found\r\n")]
        return handler(self, text)

    @staticmethod
    def _say(text: str) -> list[Emission]:
        return [Emission(text.encode("latin-1"))]

    def _accelerometer(self, text: str) -> list[Emission]:  # 1088-1101
        # three get_acc_filtered calls, each waiting on the IMU thread
        values = self.robot.imu.e_get_acc_filtered()
        return [Emission(b"", 0.060), *self._say(_csv("a", values))]

    def _battery(self, text: str) -> list[Emission]:  # 1102-1111
        b = self.robot.battery
        return self._say(f"b,{b.raw()} ({b.percentage()}%)\r\n")

    def _body(self, text: str) -> list[Emission]:  # 1112-1122
        got = scan(text, "B,%d\r")
        if got:
            self.state.led_action = got[0]
        self.robot.leds.set_body_led(self.state.led_action & 0xFFFFFFFF)
        return self._say("b\r\n")

    def _selector(self, text: str) -> list[Emission]:  # 1123-1133
        return self._say(f"c,{self.robot.selector}\r\n")

    def _set_speed(self, text: str) -> list[Emission]:  # 1134-1145
        got = scan(text, "D,%d,%d\r")
        if got:
            self.state.speedl = got[0]
        if len(got) > 1:
            self.state.speedr = got[1]
        self.robot.set_speeds(self.state.speedl, self.state.speedr)
        return self._say("d\r\n")

    def _get_speed(self, text: str) -> list[Emission]:  # 1146-1155: %d of the statics
        return self._say(f"e,{self.state.speedl},{self.state.speedr}\r\n")

    def _front(self, text: str) -> list[Emission]:  # 1156-1166
        got = scan(text, "F,%d\r")
        if got:
            self.state.led_action = got[0]
        self.robot.leds.set_front_led(self.state.led_action & 0xFFFFFFFF)
        return self._say("f\r\n")

    def _ir_receiver(self, text: str) -> list[Emission]:  # 1168-1177
        check, address, data = self.robot.rc5
        return self._say(f"g IR check : 0x{check:x}, address : 0x{address:x}, "
                         f"data : 0x{data:x}\r\n")  # fmt: skip

    def _gyro(self, text: str) -> list[Emission]:  # 1179-1192
        return self._say(_csv("g", self.robot.imu.gyro()))

    def _help(self, text: str) -> list[Emission]:  # 1194-1312
        return self._say(HELP_BT if self.use_bt else HELP_USB)

    def _camera(self, text: str) -> list[Emission]:  # 1313-1322
        s = self.state
        return self._say(_csv("i", (s.cam_mode, s.cam_width, s.cam_height, s.cam_zoom,
                                    s.cam_size)))  # fmt: skip

    def _set_camera(self, text: str) -> list[Emission]:  # 1323-1353
        s = self.state
        got = scan(text, "J,%d,%d,%d,%d,%d,%d\r")
        for name, value in zip(("cam_mode", "cam_width", "cam_height", "cam_zoom"), got,
                               strict=False):  # fmt: skip
            setattr(s, name, value)
        if s.cam_size > IMAGE_MAX_SIZE or s.cam_width <= 0 or s.cam_height <= 0:
            # 1332-1337 (the firmware checks only the size; a size <= 0 is refused here
            # too, where the renderer cannot draw it)
            s.cam_mode, s.cam_width, s.cam_height = CAM_DEFAULT[:3]
        return self._say("j\r\n")

    def _calibrate(self, text: str) -> list[Emission]:  # 1354-1377
        leds = self.robot.leds
        started = Emission(b"k, Starting calibration - Remove any object in sensors range\r\n")
        leds.e_set_led(8, 1)
        wait = Emission(b"", K_WAIT_S)
        leds.clear_leds()
        self.robot.proximity.calibrate()
        return [started, wait, Emission(b"k, Calibration finished\r\n", K_CALIBRATE_S)]

    def _led(self, text: str) -> list[Emission]:  # 1378-1388
        got = scan(text, "L,%d,%d\r")
        if got:
            self.state.led_nbr = got[0]
        if len(got) > 1:
            self.state.led_action = got[1]
        self.robot.leds.e_set_led(self.state.led_nbr, self.state.led_action)
        return self._say("l\r\n")

    def _floor(self, text: str) -> list[Emission]:  # 1389-1399: 3 ground, 2 cliff
        return self._say(_csv("m", self.robot.ground.delta()))

    def _proximity(self, text: str) -> list[Emission]:  # 1420-1431
        return self._say(_csv("n", self.robot.proximity.calibrated()))

    def _light(self, text: str) -> list[Emission]:  # 1432-1443
        return self._say(_csv("o", self.robot.proximity.ambient()))

    def _set_position(self, text: str) -> list[Emission]:  # 1444-1455
        got = scan(text, "P,%d,%d\r")
        if got:
            self.state.positionl = got[0]
        if len(got) > 1:
            self.state.positionr = got[1]
        self.robot.set_steps(self.state.positionl, self.state.positionr)
        return self._say("p\r\n")

    def _get_position(self, text: str) -> list[Emission]:  # 1456-1465: int32, unwrapped
        return self._say(_csv("q", self.robot.steps()))

    def _reset(self, text: str) -> list[Emission]:  # 1466-1473: all commented out
        return []

    def _stop(self, text: str) -> list[Emission]:  # 1474-1485
        self.robot.set_speeds(0, 0)
        self.robot.leds.e_set_led(8, 0)  # every ring LED, not the body or front LED
        return self._say("s\r\n")

    def _sound(self, text: str) -> list[Emission]:  # 1486-1516
        got = scan(text, "T,%d")
        if got:
            self.state.sound = got[0]
        self.state.sound_ready = True
        if 1 <= self.state.sound <= 5:
            self.robot.play(self.state.sound)
        else:
            self.robot.stop_sound()
            self.state.sound_ready = False
        return self._say("t\r\n")

    def _microphones(self, text: str) -> list[Emission]:  # 1533-1542: mic0..mic2
        return self._say(_csv("u", self.robot.microphones.volumes()[:3]))

    def _version(self, text: str) -> list[Emission]:  # 1543-1559
        return self._say(VERSION + f"HW version: {HW_VERSION:X}\r\n")

    def _i2c_write(self, text: str) -> list[Emission]:  # 1560-1572: no device modelled
        return self._say("w\r\n")

    def _i2c_read(self, text: str) -> list[Emission]:  # 1573-1592: reads 0
        got = [*scan(text, "Y,%d,%d\r"), 0, 0]
        return self._say(f"y,{got[0]},{got[1]}\r\ny,0\r\n")

    def _i2c_scan(self, text: str) -> list[Emission]:  # 1593-1609
        # e_i2cp_read returns an unsigned char, so `val >= 0` holds at every address.
        return self._say("".join(f"{j}: 0\r\n" for j in range(2, 255, 2)))


_ASCII: dict[str, Callable[[AsciiCommands, str], list[Emission]]] = {
    "A": AsciiCommands._accelerometer,
    "b": AsciiCommands._battery,
    "B": AsciiCommands._body,
    "C": AsciiCommands._selector,
    "D": AsciiCommands._set_speed,
    "E": AsciiCommands._get_speed,
    "F": AsciiCommands._front,
    "G": AsciiCommands._ir_receiver,
    "g": AsciiCommands._gyro,
    "H": AsciiCommands._help,
    "I": AsciiCommands._camera,
    "J": AsciiCommands._set_camera,
    "K": AsciiCommands._calibrate,
    "L": AsciiCommands._led,
    "M": AsciiCommands._floor,
    "N": AsciiCommands._proximity,
    "O": AsciiCommands._light,
    "P": AsciiCommands._set_position,
    "Q": AsciiCommands._get_position,
    "R": AsciiCommands._reset,
    "S": AsciiCommands._stop,
    "T": AsciiCommands._sound,
    "U": AsciiCommands._microphones,
    "V": AsciiCommands._version,
    "W": AsciiCommands._i2c_write,
    "Y": AsciiCommands._i2c_read,
    "Z": AsciiCommands._i2c_scan,
}
