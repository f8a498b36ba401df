"""The e-puck2's asercom v2 binary layouts, as data and pure functions (no I/O).

The e-puck2's main processor (an STM32F407) answers the e-puck1's advanced sercom and
adds binary commands ``-0x08`` .. ``-0x11``. The same bytes travel over USB (selector 8),
Bluetooth (selector 3) and, re-framed by the radio module, over WiFi (selector 15; see
``ego.backends.epuck2.wifi_packets``). This module holds:

* :class:`SensorPacket` and :func:`decode_sensors`: the "all sensors" (``-0x08``) reply,
  103 bytes over USB/Bluetooth, 104 over WiFi (:class:`SensorLayout`);
* :class:`Actuators`, :func:`encode_actuators` and :class:`ActuatorEncoder`: the "all
  actuators" (``-0x09``) 19-byte payload, with the one-shot actions (sound, proximity
  calibration, setting the step counters) sent in exactly one payload;
* :data:`COMMAND_SIZES`: each new binary command's request payload and reply size.

Sources, cited below by their short names (line numbers are those of these commits):

* MAIN = ``e-puck2/e-puck2_main-processor@d2e0dbba8f50a0619b01186c5437e3f5ffffae56``
  (the main processor's firmware; ``src/epuck1x/Asercom2.c`` is asercom v2);
* ESP = ``eshjordan/esp-idf@18f3ae6752d73117ebdb1ed7a2e109326d8dbe1b:Projects/ESP32_E-Puck_2/main/``
  (GCtronic's radio-module WiFi firmware, kept in that fork's history).

Every multi-byte field is little-endian: the firmware writes ``n & 0xff`` first, then
``n >> 8`` (MAIN:src/epuck1x/Asercom2.c:307-312), whatever its comment "binary mode (big
endian)" (Asercom2.c:292) says.
"""

from __future__ import annotations

import enum
import struct
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Final

from ego.errors import ExtraBytesError, OutOfRangeError, ProtocolError, ShortReplyError

__all__ = [
    "ACTUATORS_SIZE",
    "COMMAND_SIZES",
    "MAX_SPEED_STEPS",
    "RGB_MAX_PERCENT",
    "SERIAL_SENSORS_SIZE",
    "WIFI_SENSORS_SIZE",
    "ActuatorEncoder",
    "Actuators",
    "BinaryCommand",
    "CommandSize",
    "Rgb",
    "SensorLayout",
    "SensorPacket",
    "Settings",
    "Sound",
    "decode_sensors",
    "encode_actuators",
    "encode_binary_batch",
    "rgb_percent",
]

#: The firmware clamps every speed to +-1100 steps/s (MAIN:src/motors.h:7
#: ``MOTOR_SPEED_LIMIT 1100``, applied in src/motors.c:298-305); ego refuses beyond it.
MAX_SPEED_STEPS: Final = 1100
#: RGB LED channels are percentages (MAIN:src/leds.h:10 ``RGB_MAX_INTENSITY 100``).
RGB_MAX_PERCENT: Final = 100
#: The ``-0x08`` reply over USB and Bluetooth (ESP:uart_e-puck2.h:16 ``RESPONSE_SIZE 103``).
SERIAL_SENSORS_SIZE: Final = 103
#: The WiFi sensor packet's payload (ESP:uart_e-puck2.h:15 ``UART_RX_BUFF_SIZE 104``).
WIFI_SENSORS_SIZE: Final = 104
#: The ``-0x09`` payload: ``rx_buff[19]`` read in one piece (MAIN:Asercom2.c:95, 475, 478).
ACTUATORS_SIZE: Final = 19

#: One RGB LED: red, green, blue, each 0..100 %.
Rgb = tuple[int, int, int]


class BinaryCommand(enum.IntEnum):
    """The e-puck2's new binary commands, by their code; the wire byte is ``-code``.

    Their cases are MAIN:src/epuck1x/Asercom2.c:296 (0x08) to 696 (0x11).
    """

    ALL_SENSORS = 0x08  # Asercom2.c:296-468
    ALL_ACTUATORS = 0x09  # Asercom2.c:470-572
    RGB_LEDS = 0x0A  # Asercom2.c:574-588
    BUTTON = 0x0B  # Asercom2.c:590-592
    MICROPHONES = 0x0C  # Asercom2.c:594-610
    TOF = 0x0D  # Asercom2.c:612-621
    SD_CARD = 0x0E  # Asercom2.c:623-631
    MAGNETOMETER_ENABLE = 0x0F  # Asercom2.c:633-662
    PROXIMITY_MODE = 0x10  # Asercom2.c:664-694
    TOF_ENABLE = 0x11  # Asercom2.c:696-725

    @property
    def byte(self) -> int:
        """The byte sent on the wire: ``(-code) & 0xFF`` (0xF8 for ``-0x08``)."""
        return (-self.value) & 0xFF


@dataclass(frozen=True, slots=True)
class CommandSize:
    """What one binary command adds to a batch: payload bytes after it, reply bytes."""

    request_payload: int
    reply: int


#: Bytes each command takes after its command byte and adds to the batch's reply.
COMMAND_SIZES: Final[Mapping[BinaryCommand, CommandSize]] = MappingProxyType(
    {
        BinaryCommand.ALL_SENSORS: CommandSize(0, SERIAL_SENSORS_SIZE),  # 307-467: 103 bytes
        BinaryCommand.ALL_ACTUATORS: CommandSize(ACTUATORS_SIZE, 0),  # 475/478: reads 19
        BinaryCommand.RGB_LEDS: CommandSize(12, 0),  # 575-583: reads 12
        BinaryCommand.BUTTON: CommandSize(0, 1),  # 591
        BinaryCommand.MICROPHONES: CommandSize(0, 8),  # 595-609: 4 x u16
        BinaryCommand.TOF: CommandSize(0, 2),  # 614-619: u16 mm
        BinaryCommand.SD_CARD: CommandSize(0, 1),  # 625-629
        BinaryCommand.MAGNETOMETER_ENABLE: CommandSize(1, 1),  # 637/640 read 1; 660 "0"
        BinaryCommand.PROXIMITY_MODE: CommandSize(1, 1),  # 668/671 read 1; 692 "0"
        BinaryCommand.TOF_ENABLE: CommandSize(1, 1),  # 700/703 read 1; 723 "0"
    }
)


def encode_binary_batch(items: Sequence[tuple[BinaryCommand, bytes]]) -> tuple[bytes, int]:
    """One binary batch of new commands, ended by 0: its bytes and its reply's size.

    The firmware reads command bytes until a 0 and then sends every answer back to back
    in one piece (MAIN:Asercom2.c:292-295, 1035-1061). Each payload must have the size
    :data:`COMMAND_SIZES` gives, or the firmware would read the next command as data.
    """
    out = bytearray()
    reply = 0
    for command, payload in items:
        size = COMMAND_SIZES[BinaryCommand(command)]
        if len(payload) != size.request_payload:
            raise OutOfRangeError(
                f"command -0x{command:02X} takes {size.request_payload} payload bytes,"
                f" not {len(payload)}"
            )
        out.append(BinaryCommand(command).byte)
        out += payload
        reply += size.reply
    out.append(0)
    return bytes(out), reply


# -- the "all sensors" reply ------------------------------------------------------------


class SensorLayout(enum.Enum):
    """Which framing the ``-0x08`` bytes came through."""

    #: USB or Bluetooth: the firmware's 103 bytes, the last one reserved (always 0).
    SERIAL = SERIAL_SENSORS_SIZE
    #: WiFi: the radio module writes the button into byte 102 and moves the reserved
    #: byte to 103 (ESP:uart_e-puck2.c:137-142).
    WIFI = WIFI_SENSORS_SIZE


# Bytes 0..101, the part both layouts share (MAIN:Asercom2.c:307-464):
# 3h acc, 3f magnitude/orientation/inclination, 3h gyro, 3f magnetometer, b temperature,
# 8H proximity, 8H ambient, H ToF, 4H mics, 2h steps, H battery, B SD, 3B TV remote,
# B selector, 3H ground proximity, 3H ground ambient.
_COMMON = struct.Struct("<3h3f3h3fb8H8HH4H2hHB3BB3H3H")
assert _COMMON.size == 102


@dataclass(frozen=True, slots=True)
class SensorPacket:
    """One "all sensors" reply, every field in the firmware's own units.

    Each field names the lines of MAIN:src/epuck1x/Asercom2.c that write it.
    """

    #: x, y, z, i16, **centred on 0**, about 768 counts per g: ``e_get_acc`` takes the
    #: 16-bit IMU value minus its offset and scales it by ``(v>>4) - (v>>6)``
    #: (MAIN:src/epuck1x/a_d/advance_ad_scan/e_acc.c:17-32); 297-312. (ASCII ``A`` and
    #: binary ``-'a'`` add 2048 instead: e_acc.c:48.)
    acceleration: tuple[int, int, int]
    #: ``e_read_acc_spheric``: magnitude (counts), orientation and inclination (degrees),
    #: float32 (e_acc.c:57-74); 314-346.
    acceleration_magnitude: float
    orientation_deg: float
    inclination_deg: float
    #: x, y, z raw rate, i16 minus the calibrated offset (MAIN:src/epuck1x/acc_gyro/
    #: e_lsm330.c:43-49), 131 counts per deg/s at +-250 deg/s (e_lsm330.c:29); 348-364.
    gyro: tuple[int, int, int]
    #: x, y, z in microtesla, float32 bits (MAIN:src/sensors/imu.h:171-178); 366-374.
    magnetic_field_ut: tuple[float, float, float]
    #: degrees Celsius, i8 (``signed char getTemperature``, e_lsm330.c:63-65); 376-381.
    temperature_c: int
    #: ps0..ps7, calibrated, never below 0 (MAIN:src/sensors/proximity.c:385-397); 383-388.
    proximity: tuple[int, int, int, int, int, int, int, int]
    #: ls0..ls7, ambient light ADC counts; 390-395.
    ambient: tuple[int, int, int, int, int, int, int, int]
    #: VL53L0X distance in mm (``uint16_t VL53L0X_get_dist_mm``); 397-405.
    tof_mm: int
    #: volume of mic0..mic3, which are right, left, back, front (MAIN:src/audio/
    #: microphone.h:27-31), scaled ``>> 4`` to 12 bits (e_micro.c:35-39); 407-419.
    microphones: tuple[int, int, int, int]
    #: left, right step counters, i16 (the low 16 bits of an int32 count): 421-427.
    steps: tuple[int, int]
    #: battery ADC counts (``getBatteryValueRaw``); 429-432.
    battery_raw: int
    #: the micro-SD card answered (``!sdio_connect()``, 0 when absent); 434-441.
    sd_card_ok: bool
    #: TV remote: check/toggle bit, address, data (``e_get_check/address/data``); 443-446.
    tv_remote: tuple[int, int, int]
    #: the rotary selector, 0..15; 448-450.
    selector: int
    #: ground module proximity and ambient, left, centre, right; 452-464.
    ground_proximity: tuple[int, int, int]
    ground_ambient: tuple[int, int, int]
    #: the user button: WiFi only (ESP:uart_e-puck2.c:137-138); None over USB/Bluetooth,
    #: whose byte 102 is reserved (Asercom2.c:466-467): ask ``-0x0B`` there.
    button: bool | None


def decode_sensors(data: bytes | bytearray | memoryview, layout: SensorLayout) -> SensorPacket:
    """Decode one ``-0x08`` reply (103 bytes) or WiFi sensor payload (104 bytes).

    Raises ShortReplyError or ExtraBytesError for a wrong length, and ProtocolError for
    bytes the firmware never sends (a reserved byte other than 0, a selector above 15, a
    button or SD byte other than 0/1): those mean the stream is out of step.
    """
    raw = bytes(data)
    what = f"the {layout.name.lower()} sensor packet"
    if len(raw) < layout.value:
        raise ShortReplyError(f"{what} is {layout.value} bytes, got only {len(raw)}")
    if len(raw) > layout.value:
        raise ExtraBytesError(f"{what} is {layout.value} bytes, got {len(raw)}")
    v = _COMMON.unpack_from(raw)
    if layout is SensorLayout.WIFI:
        button_byte, reserved = raw[102], raw[103]
    else:
        button_byte, reserved = 0, raw[102]
    _check_byte(reserved == 0, what, "reserved byte", reserved)
    _check_byte(v[41] <= 15, what, "selector", v[41])
    _check_byte(v[37] in (0, 1), what, "SD card byte", v[37])
    _check_byte(button_byte in (0, 1), what, "button byte", button_byte)
    return SensorPacket(
        acceleration=(v[0], v[1], v[2]),
        acceleration_magnitude=v[3],
        orientation_deg=v[4],
        inclination_deg=v[5],
        gyro=(v[6], v[7], v[8]),
        magnetic_field_ut=(v[9], v[10], v[11]),
        temperature_c=v[12],
        proximity=v[13:21],
        ambient=v[21:29],
        tof_mm=v[29],
        microphones=v[30:34],
        steps=(v[34], v[35]),
        battery_raw=v[36],
        sd_card_ok=bool(v[37]),
        tv_remote=(v[38], v[39], v[40]),
        selector=v[41],
        ground_proximity=(v[42], v[43], v[44]),
        ground_ambient=(v[45], v[46], v[47]),
        button=bool(button_byte) if layout is SensorLayout.WIFI else None,
    )


def _check_byte(ok: bool, what: str, name: str, value: int) -> None:
    if not ok:
        raise ProtocolError(f"{what} has {name} {value}, which the firmware never sends")


# -- the "all actuators" payload --------------------------------------------------------


class Settings(enum.IntFlag):
    """Byte 0 of the ``-0x09`` payload (MAIN:Asercom2.c:493-512)."""

    #: ``calibrate_ir()`` (493-495): a one-shot, see :class:`ActuatorEncoder`.
    CALIBRATE_PROXIMITY = 0x01
    #: obstacle avoidance on while set, off while clear (496-500): a state.
    OBSTACLE_AVOIDANCE = 0x02
    #: bytes 1-4 *set the step counters* (``e_set_steps_*`` -> ``left_motor_set_pos``,
    #: MAIN:src/epuck1x/motor_led/advance_one_timer/e_motors.c:129-133, src/motors.c:
    #: 218-224) and the speeds are left as they were (506-512): a one-shot.
    SET_STEP_COUNTERS = 0x04


class Sound(enum.IntFlag):
    """Byte 18 of the ``-0x09`` payload; each set bit acts, in this order (553-571)."""

    MARIO = 0x01  # playMelody(MARIO, ML_FORCE_CHANGE): restarts if sent again
    UNDERWORLD = 0x02
    STAR_WARS = 0x04
    #: ``e_play_sound(7294, ...)``, which is ``dac_play(4000)``: a 4 kHz tone that plays
    #: until STOP (MAIN:src/epuck1x/codec/e_sound.c:43-63, src/audio/audio_thread.c:107).
    TONE_4KHZ = 0x08
    TONE_10KHZ = 0x10  # e_play_sound(11028, ...) = dac_play(10000)
    STOP = 0x20  # e_close_sound() and stopCurrentMelody()


_LED_BITS: Final = (0x01, 0x02, 0x04, 0x08)  # LED1, LED3, LED5, LED7: 515-534
_BODY_LED: Final = 0x10  # 535-539
_FRONT_LED: Final = 0x20  # 540-544
_PAYLOAD: Final = struct.Struct("<Bhh B 12B B")  # 0 settings, 1-4 speeds, 5 LEDs, 6-17, 18
assert _PAYLOAD.size == ACTUATORS_SIZE


def _check_int(name: str, value: object, low: int, high: int, unit: str = "") -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise OutOfRangeError(f"{name} must be an integer, not {value!r}")
    if not low <= value <= high:
        raise OutOfRangeError(f"{name} {value}{unit} is outside {low}..{high}")
    return value


def _check_flags(name: str, values: object, count: int) -> None:
    if not isinstance(values, tuple) or len(values) != count:
        raise OutOfRangeError(f"{name} must be a tuple of {count} booleans, not {values!r}")
    for value in values:
        if not isinstance(value, bool):
            raise OutOfRangeError(f"{name} must hold booleans, not {value!r}")


@dataclass(frozen=True, slots=True)
class Actuators:
    """The state the ``-0x09`` payload sets, checked when made (OutOfRangeError).

    ``speed_left``/``speed_right`` are steps/s within +-:data:`MAX_SPEED_STEPS`;
    ``red_leds`` are LED1, LED3, LED5, LED7 (Webots' led0, led2, led4, led6);
    ``rgb_leds`` are LED2, LED4, LED6, LED8 (Webots' led1, led3, led5, led7), each
    (red, green, blue) in 0..100 %, sent in that order (MAIN:Asercom2.c:547-550, and
    ``set_rgb_led(led, red, green, blue)`` in src/leds.c:45-52)::

        Actuators(speed_left=-200, rgb_leds=((100, 0, 0),) + ((0, 0, 0),) * 3)
    """

    speed_left: int = 0
    speed_right: int = 0
    red_leds: tuple[bool, bool, bool, bool] = (False, False, False, False)
    body_led: bool = False
    front_led: bool = False
    rgb_leds: tuple[Rgb, Rgb, Rgb, Rgb] = ((0, 0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0))
    obstacle_avoidance: bool = False

    def __post_init__(self) -> None:
        for side in ("left", "right"):
            speed = getattr(self, f"speed_{side}")
            _check_int(f"{side} speed", speed, -MAX_SPEED_STEPS, MAX_SPEED_STEPS, " steps/s")
        _check_flags("red_leds", self.red_leds, 4)
        for name in ("body_led", "front_led", "obstacle_avoidance"):
            if not isinstance(getattr(self, name), bool):
                raise OutOfRangeError(f"{name} must be a boolean, not {getattr(self, name)!r}")
        leds = self.rgb_leds
        if not isinstance(leds, tuple) or len(leds) != 4:
            raise OutOfRangeError(f"rgb_leds must be 4 (red, green, blue) tuples, not {leds!r}")
        for index, rgb in enumerate(leds):
            if not isinstance(rgb, tuple) or len(rgb) != 3:
                raise OutOfRangeError(f"RGB LED {index} must be (red, green, blue), not {rgb!r}")
            for channel, value in zip(("red", "green", "blue"), rgb, strict=True):
                _check_int(f"RGB LED {index} {channel}", value, 0, RGB_MAX_PERCENT, " %")


def rgb_percent(color: int) -> Rgb:
    """A Webots ``0xRRGGBB`` colour as the firmware's (red, green, blue) percentages.

    Each 0..255 byte becomes ``round(byte * 100 / 255)`` (255 -> 100, 128 -> 50), the
    nearest percentage [the rounding is ego's choice; the firmware only says 0..100].
    """
    _check_int("colour", color, 0, 0xFFFFFF)

    def percent(byte: int) -> int:
        return (byte * 200 + 255) // 510  # round(byte * 100 / 255); no byte lands on .5

    return (percent(color >> 16), percent((color >> 8) & 0xFF), percent(color & 0xFF))


def _pack(state: Actuators, settings: Settings, first: int, second: int, sound: Sound) -> bytes:
    leds = sum(bit for bit, on in zip(_LED_BITS, state.red_leds, strict=True) if on)
    leds |= _BODY_LED if state.body_led else 0
    leds |= _FRONT_LED if state.front_led else 0
    if state.obstacle_avoidance:
        settings |= Settings.OBSTACLE_AVOIDANCE
    rgb = [value for led in state.rgb_leds for value in led]
    return _PAYLOAD.pack(int(settings), first, second, leds, *rgb, int(sound))


def encode_actuators(state: Actuators) -> bytes:
    """The 19-byte ``-0x09`` payload setting ``state``, with no one-shot in it.

    Byte 0 settings, 1-2 left speed i16, 3-4 right speed i16, 5 LED bits, 6-17 the
    RGB LEDs R,G,B, 18 sound (MAIN:Asercom2.c:493-571). Sound, calibration and setting
    the step counters go through :class:`ActuatorEncoder`, which sends each once.
    """
    return _pack(state, Settings(0), state.speed_left, state.speed_right, Sound(0))


class ActuatorEncoder:
    """Payloads for a link, each one-shot action in exactly one of them.

    Over WiFi the radio re-sends the last command to the main processor every loop
    (ESP:socket_e-puck2.c:188 and uart_e-puck2.c:35-47, 93-113), so a sound bit left set
    restarts its melody each time, a calibration bit recalibrates, and a set-counters
    bit pins the counters. Here an action is queued, goes out in the next payload only,
    and the payload after it clears it; :attr:`needs_follow_up` says a payload carried
    one, so a WiFi link sends the next one at once::

        encoder = ActuatorEncoder(Actuators(speed_left=300, speed_right=300))
        encoder.play(Sound.MARIO)
        first = encoder.next_payload()    # byte 18 = 0x01
        second = encoder.next_payload()   # byte 18 = 0x00
    """

    def __init__(self, state: Actuators | None = None) -> None:
        self.state = state if state is not None else Actuators()
        self._sound = Sound(0)
        self._calibrate = False
        self._counters: tuple[int, int] | None = None
        self._follow_up = False

    @property
    def state(self) -> Actuators:
        """The lasting state every payload carries."""
        return self._state

    @state.setter
    def state(self, state: Actuators) -> None:
        if not isinstance(state, Actuators):
            raise OutOfRangeError(f"state must be an Actuators, not {state!r}")
        self._state = state

    def play(self, sound: Sound) -> None:
        """Queue ``sound`` (bits add up) for the next payload only."""
        if isinstance(sound, bool) or not isinstance(sound, int) or not 0 < sound < 0x40:
            raise OutOfRangeError(f"sound {sound!r} is not a combination of Sound flags")
        self._sound |= Sound(sound)

    def calibrate_proximity(self) -> None:
        """Queue one proximity calibration (settings bit 0) for the next payload."""
        self._calibrate = True

    def set_step_counters(self, left: int, right: int) -> None:
        """Queue setting the step counters (settings bit 2); that payload keeps the speeds."""
        self._counters = (
            _check_int("left step counter", left, -32768, 32767),
            _check_int("right step counter", right, -32768, 32767),
        )

    @property
    def pending(self) -> bool:
        """Whether a one-shot action waits for the next payload."""
        return bool(self._sound) or self._calibrate or self._counters is not None

    @property
    def needs_follow_up(self) -> bool:
        """The last payload carried a one-shot: send another to stop the robot repeating it."""
        return self._follow_up

    def next_payload(self) -> bytes:
        """The next 19-byte payload; the queued one-shots go in it and are then forgotten."""
        settings = Settings(0)
        first, second = self._state.speed_left, self._state.speed_right
        if self._calibrate:
            settings |= Settings.CALIBRATE_PROXIMITY
        if self._counters is not None:
            settings |= Settings.SET_STEP_COUNTERS
            first, second = self._counters
        payload = _pack(self._state, settings, first, second, self._sound)
        self._follow_up = self.pending
        self._sound, self._calibrate, self._counters = Sound(0), False, None
        return payload
