"""The firmware profiles as data: each firmware's wire formats, line rate and work per command.

The dsPIC's binary protocol (docs/protocol.md): a command byte is the negative of an
ASCII letter, ``(-ord(c)) & 0xFF``; the stock GCtronic firmware in Overo mode answers
``N``/``O`` with 20 bytes, not 16, and ``M`` with nothing. Firmware differences live in
the :data:`PROFILES` table, not in ``if`` chains; :mod:`ego.serial.protocol` turns
requests into bytes with one of them.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Mapping, Sequence
from types import MappingProxyType

from ego.seam.profile import DEFAULT_BAUD, AsciiStop, Command, Firmware, Profile, WireFormat
from ego.serial.asercom2 import SensorLayout, decode_sensors

__all__ = [
    "BANNER_END",
    "BANNER_MARKER",
    "BANNER_START",
    "BITS_PER_BYTE",
    "EPUCK2_ACC_ZERO",
    "EPUCK2_BLUETOOTH",
    "EPUCK2_USB",
    "EPUCK2_USB_BAUD",
    "EPUCK2_WIFI",
    "GCTRONIC_BLUETOOTH",
    "MAX_SPEED_STEPS",
    "PROFILES",
    "STEPS_PER_TURN",
    "command_byte",
    "wire_time_s",
]

BITS_PER_BYTE = 10  # 8N1: start + 8 data + stop
STEPS_PER_TURN = 1000
MAX_SPEED_STEPS = 1000
#: Every welcome banner of the firmwares we know contains this; its arrival mid-stream
#: means the dsPIC restarted.
BANNER_MARKER = b"WELCOME"
#: How both firmwares' banner begins (docs/protocol.md): form feed, bell, the marker.
BANNER_START = b"\x0c\x07" + BANNER_MARKER
#: How the banner ends, for every firmware we know (docs/protocol.md: Asercom.c:117-126,
#: Asercom2.c:153-160): once it is in, nothing of the banner is left to come.
BANNER_END = b'"H" for help\r\n'


def command_byte(letter: str) -> int:
    """The binary command byte for an ASCII letter: its negative, modulo 256."""
    if len(letter) != 1 or not letter.isascii():
        raise ValueError(f"a command is one ASCII letter, not {letter!r}")
    return (-ord(letter)) & 0xFF


def wire_time_s(n_bytes: int, baud: int = DEFAULT_BAUD) -> float:
    """How long ``n_bytes`` take on an 8N1 line: 10 bits a byte (43.4 us at 230400)."""
    return n_bytes * BITS_PER_BYTE / baud


def _fmt(arguments: str = "", reply: str = "", prefix: str = "") -> WireFormat:
    return WireFormat(
        struct.Struct("<" + arguments), struct.Struct("<" + reply), struct.Struct("<" + prefix)
    )


_COMMON: dict[Command, WireFormat] = {
    Command.ACCELEROMETER_RAW: _fmt(reply="3H"),
    Command.ACCELEROMETER_SPHERICAL: _fmt(reply="3f"),
    Command.SET_SPEED: _fmt(arguments="2h"),
    Command.GET_SPEED: _fmt(reply="2h"),
    Command.SET_LED: _fmt(arguments="2B"),
    Command.FLOOR: _fmt(reply="3H"),
    Command.PROXIMITY: _fmt(reply="8h"),
    Command.LIGHT: _fmt(reply="8h"),
    Command.SET_STEPS: _fmt(arguments="2h"),
    Command.GET_STEPS: _fmt(reply="2h"),
    Command.MIC_AMPLITUDE: _fmt(reply="3H"),
    Command.MIC_BUFFER: _fmt(reply="B", prefix="300h"),
    Command.BATTERY: _fmt(reply="H"),
}


#: docs/protocol.md, quirk "M": Webots' firmware reads the ground sensors over I2C
#: (about 3 ms), byte by byte; A computes with software floating point on the dsPIC.
_M_WORK_S = 0.003
_A_WORK_S = 0.002

_webots = dict(_COMMON)
# docs/protocol.md, quirk "b": Webots' firmware has no b (the byte is skipped silently).
del _webots[Command.BATTERY]

_overo = dict(_COMMON)
# docs/protocol.md: ps0-ps7 plus the Overo board's long-range IR8 (left) and IR9 (right).
_overo[Command.PROXIMITY] = _fmt(reply="10h")
_overo[Command.LIGHT] = _fmt(reply="10h")
# docs/protocol.md: M returns nothing; the I2C bus is left to the Overo.
del _overo[Command.FLOOR]
#: docs/protocol.md, "The Overo's own I2C bus": in selector 10 the firmware lets the Overo
#: be the I2C master (main_c.c:115-119), so the Overo reads the ground module itself, and,
#: on a rev 1.3, the LSM330 that answers `a` with zeros on the line.
_OVERO_I2C = MappingProxyType(
    {Command.FLOOR: "ground module", Command.ACCELEROMETER_RAW: "LSM330"}
)

_bluetooth = dict(_COMMON)
# docs/protocol.md, quirk "M": the stock firmware is built with its cliff sensors, so
# M answers the three ground sensors and then two cliff values (10 bytes).
_bluetooth[Command.FLOOR] = _fmt(reply="5H")

# -- the e-puck2 (asercom v2 over USB and Bluetooth) -------------------------------------
# docs/protocol.md, "e-puck2"; the firmware is MAIN:src/epuck1x/Asercom2.c (see
# ego.serial.asercom2 for the commit). The e-puck1 commands it keeps, with its formats:
_epuck2 = dict(_COMMON)
# Asercom2.c:964-975: -'U' is commented out, it answers nothing (a batch with it would
# wait for 600 bytes that never come).
del _epuck2[Command.MIC_BUFFER]
# Asercom2.c:874-894 (CLIFF_SENSORS): -'M' answers the three ground sensors and one cliff.
_epuck2[Command.FLOOR] = _fmt(reply="4H")
# Asercom2.c:822-839: the gyro's three raw rates (131.072 counts per deg/s).
_epuck2[Command.GYRO_RAW] = _fmt(reply="3h")
# The new commands, their sizes as ego.serial.asercom2.COMMAND_SIZES gives them
# (tests/unit/test_epuck2_profile.py checks the two agree).
_epuck2.update({
    # 103 bytes, checked by the decoder that reads the WiFi packet (reserved byte, SD...).
    Command.ALL_SENSORS: WireFormat(reply=struct.Struct("<3h3f3h3fb8H8HH4H2hHB3BB3H3HB"),
                                    check=lambda raw: decode_sensors(raw, SensorLayout.SERIAL)),
    Command.ALL_ACTUATORS: _fmt(arguments="Bhh13BB"),  # 19 bytes
    Command.RGB_LEDS: _fmt(arguments="12B"),
    Command.BUTTON: _fmt(reply="B"),
    Command.MICROPHONES_4: _fmt(reply="4H"),
    Command.TOF: _fmt(reply="H"),
    Command.SD_STATE: _fmt(reply="B"),
    Command.MAGNETOMETER_ENABLE: _fmt(arguments="B", reply="B"),
    Command.PROXIMITY_MODE: _fmt(arguments="B", reply="B"),
    Command.TOF_ENABLE: _fmt(arguments="B", reply="B"),
})  # fmt: skip

#: Where the values of the e-puck1 commands lie in the "all sensors" packet's 49 values
#: (Asercom2.c:297-467; ego.serial.asercom2.SensorPacket names each field).
_PACKET_SLICES: Mapping[Command, slice] = MappingProxyType({
    Command.ACCELEROMETER_SPHERICAL: slice(3, 6),
    Command.GYRO_RAW: slice(6, 9),
    Command.PROXIMITY: slice(13, 21),
    Command.LIGHT: slice(21, 29),
    Command.TOF: slice(29, 30),
    Command.MICROPHONES_4: slice(30, 34),
    Command.MIC_AMPLITUDE: slice(30, 33),
    Command.GET_STEPS: slice(34, 36),
    Command.BATTERY: slice(36, 37),
    Command.SD_STATE: slice(37, 38),
})  # fmt: skip
#: ``-'a'`` is centred on 2048, the packet's accelerometer on 0 (e_acc.c:17-50): the
#: packet's value plus 2048 reads as ``a`` does, with the offsets the firmware took at
#: power-on removed.
EPUCK2_ACC_ZERO = 2048


def _take(where: slice) -> Callable[[Sequence[float]], tuple[float, ...]]:
    def take(values: Sequence[float]) -> tuple[float, ...]:
        return tuple(values[where])

    return take


def _acc_raw(values: Sequence[float]) -> tuple[float, ...]:
    return tuple(EPUCK2_ACC_ZERO + v for v in values[0:3])


_EPUCK2_COVER: Mapping[Command, Callable[[Sequence[float]], tuple[float, ...]]] = (
    MappingProxyType(
        {Command.ACCELEROMETER_RAW: _acc_raw, **{c: _take(s) for c, s in _PACKET_SLICES.items()}}
    )
)
#: Asercom2.c:727-746: -'a' filters over three 20 ms waits (imu.c:450-464).
_A_FILTER_S = 0.060
#: Asercom2.c:481 (and 650, 683, 712): over USB, -0x09, -0x0F, -0x10 and -0x11 each
#: sleep 10 ms after reading their payload.
_USB_SLEEP_S = 0.010
#: USB full speed (12 Mbit/s) carries a CDC port's bulk data at about 1 MB/s, whatever
#: rate the host opens it at: ego times replies as if 10 bits a byte ran at 10 Mbit/s
#: [a model: a real port's round trip is dominated by the 1 ms USB frames, not bytes].
EPUCK2_USB_BAUD = 10_000_000

#: The e-puck2 over USB (selector 8).
#:
#: Batch strategy, measured on the emulator (``python -m benchmarks.epuck2_batch``,
#: median round trips; the full table is in docs/protocol.md, "e-puck2"): a step's reads
#: go as the e-puck1 commands (``N``, ``O``, ``Q``, ``g``, ``-0x0D``...) unless the "all
#: sensors" packet ``-0x08`` costs less by :meth:`Profile.cost_s` (bytes at the line
#: rate plus the firmware's work). Its 104 bytes lose to every set of short commands:
#: over Bluetooth ps+enc is 23 B, 3.1 ms against 105 B, 10.1 ms, and even every sensor
#: but the accelerometer (62 B) is 6.4 ms against 10.1; over USB, where bytes are nearly
#: free, 0.8-1.1 ms against 1.1-1.6 ms. But ``-'a'`` filters for 60 ms, so the
#: accelerometer (ps+enc+acc: 60.7 ms as commands, 1.1 ms as the packet over USB; 63.7
#: against 10.1 over Bluetooth), and what only the packet holds (magnetometer,
#: temperature, selector), bring the packet in, and every read it holds then rides in
#: it. The "all actuators" ``-0x09`` is not used: over USB it sleeps 10 ms (Asercom2.c:
#: 481; speeds 10.6 ms against D+E's 0.5 ms), and over Bluetooth it wins (3.2 against
#: 4.6 ms) only when the speeds, six LEDs and the RGB LEDs all change in one step, while
#: a usual step changes the speeds alone (D+E 1.9 ms against 3.2); it would also have to
#: resend every actuator each time. The RGB LEDs go as ``-0x0A`` (13 bytes, no sleep),
#: sound as ASCII ``T``.
EPUCK2_USB = Profile(
    Firmware.EPUCK2,
    MappingProxyType(_epuck2),
    # -'L' 0, 2, 4, 6 the red LEDs, 8 body, 9 front (Asercom2.c:852-873); 1, 3, 5, 7 are
    # RGB: -'L' on them sets only the red channel at 10 % (e_led.c:24-74), so they go
    # as -0x0A (rgb_leds).
    (0, 2, 4, 6, 8, 9),
    "GCtronic e-puck2 asercom v2 over USB, selector 8",
    line_baud=EPUCK2_USB_BAUD,
    work_s=MappingProxyType({
        Command.ACCELEROMETER_RAW: _A_FILTER_S,
        Command.ALL_ACTUATORS: _USB_SLEEP_S,
        Command.MAGNETOMETER_ENABLE: _USB_SLEEP_S,
        Command.PROXIMITY_MODE: _USB_SLEEP_S,
        Command.TOF_ENABLE: _USB_SLEEP_S,
    }),
    # ASCII K: calibrate_ir averages for about a second (Asercom2.c:1354-1377).
    calibration_s=1.5,
    # Asercom2.c:1474-1485: S sets the speeds 0 and e_set_led(8, 0), which is all eight
    # ring LEDs (the RGB ones too); body and front stay, and so do the speeds E echoes.
    ascii_stop=AsciiStop(tuple(range(8)), clears_echo=False),
    acc_zero_counts=EPUCK2_ACC_ZERO,
    acc_counts_per_g=768,  # e_acc.c:17-32: (v>>4) - (v>>6) of 16384 a g
    rev13=True,  # the battery answers an ADC count, as on an e-puck rev 1.3
    max_speed_steps=1100,  # MAIN:src/motors.h:7 MOTOR_SPEED_LIMIT, motors.c:298-305
    model_max_velocity_rad_s=7.536,  # Webots' E-puck.proto, version "2" (1200 steps/s)
    rgb_leds=(1, 3, 5, 7),  # LED2, 4, 6, 8 of the firmware, in -0x0A's order
    all_sensors=_EPUCK2_COVER,
)
#: The e-puck2 over Bluetooth (selector 3): the UART to the radio runs at 115200 baud
#: (MAIN:src/serial_comm.c:44-45), and nothing sleeps (the sleeps are USB's).
EPUCK2_BLUETOOTH = EPUCK2_USB.but(
    description="GCtronic e-puck2 asercom v2 over Bluetooth, selector 3",
    line_baud=115200,
    work_s=MappingProxyType({Command.ACCELEROMETER_RAW: _A_FILTER_S}),
)
#: What the e-puck2's radio serves over WiFi (selector 15; ego.backends.epuck2 answers
#: each command from the streamed sensor packet and folds setters into its command packet):
#: USB's wire formats, so that a family decodes a WiFi reply as a USB one, but -'M' holds
#: the three ground values only (the packet has no cliff value) and nothing else the
#: packet lacks (ASCII, -'U', -'I', the enables -0x0F..-0x11).
_WIFI_SERVED = (
    Command.SET_SPEED, Command.GET_SPEED, Command.SET_LED, Command.SET_STEPS, Command.RGB_LEDS,
    Command.ALL_ACTUATORS, Command.PROXIMITY, Command.LIGHT, Command.GET_STEPS,
    Command.ACCELEROMETER_RAW, Command.ACCELEROMETER_SPHERICAL, Command.GYRO_RAW,
    Command.MIC_AMPLITUDE, Command.MICROPHONES_4, Command.BATTERY, Command.TOF,
    Command.BUTTON, Command.SD_STATE, Command.ALL_SENSORS,
)  # fmt: skip
EPUCK2_WIFI = EPUCK2_USB.but(
    commands=MappingProxyType(
        {
            **{command: EPUCK2_USB.commands[command] for command in _WIFI_SERVED},
            Command.FLOOR: _fmt(reply="3H"),
        }
    ),
    description="GCtronic e-puck2 over WiFi (radio firmware, selector 15)",
    work_s=MappingProxyType({}),
)


PROFILES: Mapping[Firmware, Profile] = MappingProxyType(
    {
        Firmware.GCTRONIC: Profile(
            Firmware.GCTRONIC,
            MappingProxyType(_overo),
            tuple(range(8)),  # L 8 and L 9 (body, front) are ignored in Overo mode
            "stock GCtronic asercom, selector 10",
            line_baud=230400,
            work_s=MappingProxyType({Command.ACCELEROMETER_SPHERICAL: _A_WORK_S}),
            calibration_s=1.0,
            ascii_stop=AsciiStop(tuple(range(8)), clears_echo=False),
            i2c=_OVERO_I2C,
        ),
        Firmware.WEBOTS: Profile(
            Firmware.WEBOTS,
            MappingProxyType(_webots),
            tuple(range(10)),
            "Webots e-puck firmware 1.5.x, Bluetooth",
            line_baud=115200,
            work_s=MappingProxyType(
                {Command.FLOOR: _M_WORK_S, Command.ACCELEROMETER_SPHERICAL: _A_WORK_S}
            ),
            calibration_s=1.5,
            ascii_stop=AsciiStop(tuple(range(10)), clears_echo=True),
        ),
        Firmware.EPUCK2: EPUCK2_USB,
    }
)

#: The stock firmware in any selector but 10: asercom over Bluetooth (UART1, 115200).
GCTRONIC_BLUETOOTH = PROFILES[Firmware.GCTRONIC].but(
    commands=MappingProxyType(_bluetooth),
    leds=tuple(range(10)),
    description="stock GCtronic asercom over Bluetooth",
    line_baud=115200,
    work_s=MappingProxyType({Command.FLOOR: _M_WORK_S, Command.ACCELEROMETER_SPHERICAL: _A_WORK_S}),
    i2c=MappingProxyType({}),  # the dsPIC is the I2C master: M and a read it
)
