"""The core's batches on the e-puck2's WiFi link, as data and pure functions (no I/O).

Over WiFi the robot takes only the 19-byte ``-0x09`` payload (in a 21-byte command) and
answers only with the 104-byte sensor packet (``ego.backends.epuck2.wifi_packets``). A
Robot speaks batches of :class:`~ego.seam.batch.Request`, so a batch is translated:

* setters (speeds, LEDs, RGB LEDs, the whole ``-0x09`` payload, the step counters)
  fold into the :class:`~ego.serial.asercom2.ActuatorEncoder` whose payload the next
  command carries; the one-shots among them (sound, proximity calibration, setting the
  step counters) go out in exactly one command;
* getters are answered from the newest sensor packet, packed in the wire format of
  :data:`WIFI_PROFILE` (the USB bytes of the same command where the packet holds the
  same value), so the device families decode them as over USB.

:data:`WIFI_COMMANDS` is the table: a command the WiFi robot cannot serve is not in it,
so the families refuse it at once (UnsupportedDeviceError naming the transport). Not
served over WiFi: the microphone buffer ``U`` (the e-puck2 answers nothing to it), the
camera's ``I`` (the image comes in its own packets, see the camera source), the
magnetometer, proximity-mode and ToF switches ``-0x0F``..``-0x11`` (the radio's
firmware sets them at start, MAIN:src/main.c:852), and every ASCII command.

[Provisional] The e-puck2 profile proper (``Firmware "epuck2"``) is being written in
``ego.seam.profile``/``ego.serial.protocol``; until it lands this profile is built on the
stock firmware's, with this table's wire formats.
"""

from __future__ import annotations

import struct
from collections.abc import Callable, Mapping
from dataclasses import replace
from types import MappingProxyType
from typing import Final

from ego.errors import OutOfRangeError, UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile, WireFormat
from ego.serial.asercom2 import (
    ActuatorEncoder,
    Actuators,
    Rgb,
    SensorPacket,
    Settings,
    Sound,
)
from ego.serial.profiles import EPUCK2_WIFI

__all__ = [
    "ANSWERS",
    "WIFI_COMMANDS",
    "WIFI_PROFILE",
    "answer",
    "fold",
    "translate",
]


def _fmt(arguments: str = "", reply: str = "") -> WireFormat:
    return WireFormat(struct.Struct("<" + arguments), struct.Struct("<" + reply))


#: The commands the WiFi robot serves, in the e-puck2 profile's wire formats
#: (:data:`ego.serial.profiles.EPUCK2_WIFI`).
WIFI_COMMANDS: Final[Mapping[Command, WireFormat]] = EPUCK2_WIFI.commands

_USB_SENSORS: Final = WIFI_COMMANDS[Command.ALL_SENSORS].reply

#: -'a''s 0 g (MAIN:src/epuck1x/a_d/advance_ad_scan/e_acc.c:48 adds 2048).
ACC_ZERO_COUNTS: Final = 2048

#: The e-puck2 over WiFi: red LEDs 0, 2, 4, 6, RGB LEDs 1, 3, 5, 7, body 8, front 9.
WIFI_PROFILE: Final[Profile] = EPUCK2_WIFI

#: How each getter is answered from a sensor packet: the values, in the reply's order.
ANSWERS: Final[Mapping[Command, Callable[[SensorPacket, bytes], tuple[object, ...]]]] = (
    MappingProxyType(
        {
            Command.PROXIMITY: lambda p, _: p.proximity,
            Command.LIGHT: lambda p, _: p.ambient,
            Command.GET_STEPS: lambda p, _: p.steps,
            # e_get_acc's values stay within +-1536 (e_acc.c:17-32): 512..3584 here.
            Command.ACCELEROMETER_RAW: lambda p, _: tuple(
                v + ACC_ZERO_COUNTS for v in p.acceleration
            ),
            Command.ACCELEROMETER_SPHERICAL: lambda p, _: (
                p.acceleration_magnitude,
                p.orientation_deg,
                p.inclination_deg,
            ),
            Command.GYRO_RAW: lambda p, _: p.gyro,
            Command.MIC_AMPLITUDE: lambda p, _: p.microphones[:3],
            Command.MICROPHONES_4: lambda p, _: p.microphones,
            Command.BATTERY: lambda p, _: (p.battery_raw,),
            Command.FLOOR: lambda p, _: p.ground_proximity,
            Command.TOF: lambda p, _: (p.tof_mm,),
            Command.BUTTON: lambda p, _: (1 if p.button else 0,),
            Command.SD_STATE: lambda p, _: (1 if p.sd_card_ok else 0,),
            # ESP:uart_e-puck2.c:137-142 put the button in 102 and the reserved byte in 103:
            # the USB layout's 103 bytes, read back as the profile's typed fields.
            Command.ALL_SENSORS: lambda _, raw: _USB_SENSORS.unpack(raw[:102] + raw[103:104]),
        }
    )
)

_SETTERS: Final = frozenset(
    {
        Command.SET_SPEED,
        Command.SET_LED,
        Command.SET_STEPS,
        Command.RGB_LEDS,
        Command.ALL_ACTUATORS,
    }
)
#: USB's -'L' on an RGB LED (LED2, 4, 6, 8) sets only its red channel, at 10 %
#: (/work/shared/spec/epuck2.md, corrections box): the same here.
_L_ON_RGB: Final[Rgb] = (10, 0, 0)


def _led(state: Actuators, index: int, value: int) -> Actuators:
    """``L index value`` (value 0 off, 1 on, 2 and up toggles, as e_set_led) on the
    e-puck2: even indices the red LEDs, odd ones the RGB LEDs' red, 8 body, 9 front."""
    if not 0 <= index <= 9:
        raise OutOfRangeError(f"LED {index} is outside 0..9")
    if index == 8:
        return replace(state, body_led=not state.body_led if value > 1 else bool(value))
    if index == 9:
        return replace(state, front_led=not state.front_led if value > 1 else bool(value))
    if index % 2 == 0:
        red = list(state.red_leds)
        red[index // 2] = not red[index // 2] if value > 1 else bool(value)
        return replace(state, red_leds=(red[0], red[1], red[2], red[3]))
    rgb = list(state.rgb_leds)
    on = rgb[index // 2] == (0, 0, 0) if value > 1 else bool(value)
    rgb[index // 2] = _L_ON_RGB if on else (0, 0, 0)
    return replace(state, rgb_leds=(rgb[0], rgb[1], rgb[2], rgb[3]))


def _rgb(values: tuple[int, ...]) -> tuple[Rgb, Rgb, Rgb, Rgb]:
    leds = [(values[i], values[i + 1], values[i + 2]) for i in range(0, 12, 3)]
    return (leds[0], leds[1], leds[2], leds[3])


def _payload(encoder: ActuatorEncoder, payload: bytes) -> None:
    """A whole ``-0x09`` payload: its state kept, its one-shots queued once."""
    settings, left, right, leds, *rest = struct.unpack("<Bhh B 12B B", payload)
    rgb, sound = tuple(rest[:12]), rest[12]
    counters = bool(settings & Settings.SET_STEP_COUNTERS)
    state = Actuators(
        speed_left=encoder.state.speed_left if counters else left,
        speed_right=encoder.state.speed_right if counters else right,
        red_leds=(bool(leds & 1), bool(leds & 2), bool(leds & 4), bool(leds & 8)),
        body_led=bool(leds & 0x10),
        front_led=bool(leds & 0x20),
        rgb_leds=_rgb(rgb),
        obstacle_avoidance=bool(settings & Settings.OBSTACLE_AVOIDANCE),
    )
    encoder.state = state
    if counters:
        encoder.set_step_counters(left, right)
    if settings & Settings.CALIBRATE_PROXIMITY:
        encoder.calibrate_proximity()
    if sound:
        encoder.play(Sound(sound))


def fold(encoder: ActuatorEncoder, command: Command, arguments: tuple[int, ...]) -> None:
    """Fold one setter into ``encoder`` (OutOfRangeError for a value the robot refuses)."""
    state = encoder.state
    if command is Command.SET_SPEED:
        encoder.state = replace(state, speed_left=arguments[0], speed_right=arguments[1])
    elif command is Command.SET_LED:
        encoder.state = _led(state, arguments[0], arguments[1])
    elif command is Command.SET_STEPS:
        encoder.set_step_counters(arguments[0], arguments[1])
    elif command is Command.RGB_LEDS:
        encoder.state = replace(state, rgb_leds=_rgb(arguments))
    else:  # the whole -0x09 payload, as the profile's format packs it
        _payload(encoder, WIFI_COMMANDS[Command.ALL_ACTUATORS].arguments.pack(*arguments))


def translate(
    requests: tuple[Request, ...], encoder: ActuatorEncoder, transport: str
) -> tuple[Command, ...]:
    """Fold the batch's setters into ``encoder``; the getters it asks, in order.

    A request this link cannot serve raises UnsupportedDeviceError naming ``transport``.
    """
    getters: list[Command] = []
    for request in requests:
        command, arguments = request.command, request.arguments
        if command in _SETTERS:
            fold(encoder, command, arguments)
        elif command in ANSWERS or command is Command.GET_SPEED:
            getters.append(command)
        else:
            raise UnsupportedDeviceError(
                f"{transport}: the e-puck2's WiFi link cannot serve command "
                f"{command.letter!r} ({command.name.lower()})"
            )
    return tuple(getters)


def answer(
    getters: tuple[Command, ...], packet: SensorPacket, raw: bytes, speeds: tuple[int, int]
) -> bytes:
    """The reply bytes of ``getters``, back to back in order, from one sensor packet
    (``raw``: its 104 bytes) and the speeds the robot was commanded."""
    out = bytearray()
    for command in getters:
        values = speeds if command is Command.GET_SPEED else ANSWERS[command](packet, raw)
        fmt = WIFI_COMMANDS[command]
        try:
            out += fmt.reply.pack(*values)
        except struct.error as exc:  # a value outside the USB field (never, on a sound packet)
            raise UnsupportedDeviceError(
                f"the WiFi packet's {command.name.lower()} {values!r} does not fit "
                f"{fmt.reply.format!r}"
            ) from exc
    return bytes(out)
