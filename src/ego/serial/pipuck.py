"""What each Pi-puck path serves, as ego's profiles (data): the e-puck2's I2C packet and
York's e-puck1 register map, with the chips and the battery the Pi reads beside them.

Each profile lists the wire commands ego's families may ask, in the formats they decode
(the USB formats of the same commands, so a reading means what it means over USB). The
channel (:mod:`ego.backends.pipuck.channel`) answers each from the packet, the
registers, a chip or sysfs. A family whose command is not listed is refused at once
(UnsupportedDeviceError naming the firmware and what serves it instead): over the
e-puck2's packet, the magnetometer, the temperature, the ASCII commands and the tones;
over York's map, the microphones, the selector, the button and the speaker.
"""

from __future__ import annotations

import struct
from collections.abc import Mapping
from types import MappingProxyType
from typing import Final

from ego.seam.profile import AsciiStop, Command, Firmware, Profile, WireFormat
from ego.serial.profiles import EPUCK2_USB

__all__ = ["EPUCK2_I2C_PROFILE", "I2C_BITS_PER_BYTE", "PIPUCK_PROFILES", "YORK_PROFILE"]

#: An I2C byte is 8 data bits and the acknowledge bit.
I2C_BITS_PER_BYTE: Final = 9


def _fmt(arguments: str = "", reply: str = "") -> WireFormat:
    return WireFormat(struct.Struct("<" + arguments), struct.Struct("<" + reply))


_USB = EPUCK2_USB.commands
#: Read beside the microcontroller on both robots: the IMU, the ToF, the ground module
#: (three values: no cliff), the battery (sysfs).
_BESIDE: Final = {
    Command.ACCELEROMETER_RAW: _USB[Command.ACCELEROMETER_RAW],
    Command.GYRO_RAW: _USB[Command.GYRO_RAW],
    Command.TOF: _USB[Command.TOF],
    Command.FLOOR: _fmt(reply="3H"),
    Command.BATTERY: _USB[Command.BATTERY],
}
_MOTION: Final = {
    Command.SET_SPEED: _USB[Command.SET_SPEED],
    Command.GET_SPEED: _USB[Command.GET_SPEED],
    Command.SET_LED: _USB[Command.SET_LED],
    Command.PROXIMITY: _USB[Command.PROXIMITY],
    Command.LIGHT: _USB[Command.LIGHT],
    Command.GET_STEPS: _USB[Command.GET_STEPS],
}
_PACKET_ONLY: Final = (
    Command.SET_STEPS, Command.RGB_LEDS, Command.MIC_AMPLITUDE, Command.MICROPHONES_4,
    Command.BUTTON, Command.ALL_SENSORS,
)  # fmt: skip

#: The e-puck2 through a Pi-puck, selector 10 (GCtronic's gumstix branch).
EPUCK2_I2C_PROFILE: Final[Profile] = EPUCK2_USB.but(
    firmware=Firmware.EPUCK2_I2C,
    commands=MappingProxyType(
        {**_MOTION, **{c: _USB[c] for c in _PACKET_ONLY}, **_BESIDE}
    ),
    # The packet has LED1, 3, 5, 7 as on/off (ego's led0, 2, 4, 6) and LED2, 4, 6, 8 as RGB
    # (led1, 3, 5, 7); no body or front LED (gumstix.c:221-229).
    leds=(0, 2, 4, 6),
    description="GCtronic e-puck2 through a Pi-puck, I2C, selector 10 (gumstix firmware)",
    # The robot's I2C bus at its 100 kHz (gumstix.c:39-45), 9 bits a byte.
    line_baud=100_000 * 10 // I2C_BITS_PER_BYTE,
    work_s=MappingProxyType({}),
    calibration_s=1.5,  # calibrate_ir averages for about a second, as over USB
    ascii_stop=AsciiStop((), clears_echo=False),
    all_sensors=MappingProxyType({}),  # the packet is read whole every step anyway
)
#: An e-puck1 with York's firmware through a Pi-puck.
YORK_PROFILE: Final[Profile] = Profile(
    Firmware.YORK,
    # SET_STEPS: registers 4 and 5 are read-only; ego keeps the offset (york_side.py).
    MappingProxyType({**_MOTION, Command.SET_STEPS: _USB[Command.SET_STEPS], **_BESIDE}),
    tuple(range(10)),  # 0..7 the ring (register 0), 8 body, 9 front (register 1)
    "York's e-puck1 firmware through a Pi-puck, I2C registers",
    line_baud=100_000 * 10 // I2C_BITS_PER_BYTE,
    calibration_s=0.0,
    ascii_stop=AsciiStop((), clears_echo=False),
    acc_zero_counts=2048,
    acc_counts_per_g=768,
    rev13=True,  # the battery is a count (the Pi-puck's ADC), as on a rev 1.3
    max_speed_steps=1000,  # main.c:59-78
)

#: The profiles by firmware: what a served robot's client, a recording's replay and the
#: backend agree on (ego.serial.firmware.profile_for).
PIPUCK_PROFILES: Final[Mapping[Firmware, Profile]] = MappingProxyType(
    {Firmware.EPUCK2_I2C: EPUCK2_I2C_PROFILE, Firmware.YORK: YORK_PROFILE}
)
