"""The e-puck2's "all actuators" (-0x09) payload and the other new binary commands.

Expected bytes are written out by hand from MAIN = e-puck2/e-puck2_main-processor@d2e0dbb,
src/epuck1x/Asercom2.c:470-572, where the firmware reads them as ``rx_buff[0..18]``.
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ego.errors import OutOfRangeError
from ego.serial.asercom2 import (
    COMMAND_SIZES,
    ActuatorEncoder,
    Actuators,
    BinaryCommand,
    Sound,
    encode_actuators,
    encode_binary_batch,
    rgb_percent,
)

OFF = (0, 0, 0)


def firmware_speed(low: int, high: int) -> int:
    """Asercom2.c:503 ``speedl = rx_buff[1] + (rx_buff[2] << 8)``, then e_set_speed_left's
    ``(int16_t)motor_speed`` (motor_led/advance_one_timer/e_motors.c:81-84)."""
    value = low + (high << 8)
    return value - 0x10000 if value & 0x8000 else value


def test_negative_speeds_are_i16_little_endian() -> None:
    payload = encode_actuators(Actuators(speed_left=-200, speed_right=300))
    # -200 = 0xFF38, low byte first; 300 = 0x012C.
    assert payload[1:5] == bytes([0x38, 0xFF, 0x2C, 0x01])
    assert firmware_speed(payload[1], payload[2]) == -200
    assert firmware_speed(payload[3], payload[4]) == 300


def test_the_whole_payload_byte_by_byte() -> None:
    state = Actuators(
        speed_left=-1100,
        speed_right=1100,
        red_leds=(True, False, True, False),
        body_led=True,
        front_led=True,
        rgb_leds=((100, 0, 0), (0, 100, 0), (0, 0, 100), (10, 20, 30)),
        obstacle_avoidance=True,
    )
    expected = bytes(
        [
            0x02,  # settings: bit 1 obstacle avoidance (496-500)
            0xB4, 0xFB,  # -1100 = 0xFBB4 (503)
            0x4C, 0x04,  # 1100 = 0x044C (504)
            0x01 | 0x04 | 0x10 | 0x20,  # LED1, LED5, body, front (515-544)
            100, 0, 0,  # LED2 R,G,B (547)
            0, 100, 0,  # LED4 (548)
            0, 0, 100,  # LED6 (549)
            10, 20, 30,  # LED8 (550): red at rx_buff[15], where Webots writes 16
            0x00,  # no sound (553-571)
        ]
    )  # fmt: skip
    assert encode_actuators(state) == expected


def test_rgb_leds_are_red_green_blue_in_percent() -> None:
    # set_rgb_led(led, red, green, blue) (src/leds.c:45-52), RGB_MAX_INTENSITY 100
    # (src/leds.h:10). Webots' builder sends B,G,R in 0..255: not this.
    payload = encode_actuators(Actuators(rgb_leds=(rgb_percent(0xFF8000), OFF, OFF, OFF)))
    assert payload[6:9] == bytes([100, 50, 0])
    assert rgb_percent(0x0000FF) == (0, 0, 100)
    assert rgb_percent(0x010203) == (0, 1, 1)


@pytest.mark.parametrize("value", [101, 255, -1])
def test_an_rgb_value_outside_0_to_100_percent_is_refused(value: int) -> None:
    with pytest.raises(OutOfRangeError, match=f"RGB LED 2 green {value} % is outside 0..100"):
        Actuators(rgb_leds=(OFF, OFF, (0, value, 0), OFF))


@pytest.mark.parametrize("speed", [1101, -1101, 5000])
def test_a_speed_beyond_the_firmware_clamp_is_refused(speed: int) -> None:
    # MOTOR_SPEED_LIMIT 1100 (src/motors.h:7): the firmware would clamp it silently.
    with pytest.raises(OutOfRangeError, match=f"right speed {speed} steps/s is outside"):
        Actuators(speed_right=speed)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"speed_left": 1.5},
        {"speed_left": True},
        {"red_leds": (True, False)},
        {"red_leds": (1, 0, 0, 0)},
        {"body_led": 1},
        {"rgb_leds": (OFF, OFF, OFF)},
        {"rgb_leds": (OFF, OFF, OFF, (1, 2))},
        {"rgb_leds": (OFF, OFF, OFF, (1.0, 2, 3))},
    ],
)
def test_malformed_state_is_refused(kwargs: dict[str, object]) -> None:
    with pytest.raises(OutOfRangeError):
        Actuators(**kwargs)  # type: ignore[arg-type]


def test_the_sound_goes_out_in_one_payload_only() -> None:
    encoder = ActuatorEncoder(Actuators(speed_left=100))
    encoder.play(Sound.MARIO)
    first = encoder.next_payload()
    assert first[18] == 0x01 and encoder.needs_follow_up
    second = encoder.next_payload()
    assert second[18] == 0x00 and not encoder.needs_follow_up
    assert second[:18] == first[:18]  # the lasting state is untouched
    assert encoder.next_payload()[18] == 0x00


def test_the_plain_encoder_never_carries_a_one_shot() -> None:
    payload = encode_actuators(Actuators(obstacle_avoidance=False))
    assert payload[0] == 0 and payload[18] == 0


def test_sounds_queued_together_go_out_together_once() -> None:
    encoder = ActuatorEncoder()
    encoder.play(Sound.TONE_4KHZ)
    encoder.play(Sound.STOP)
    assert encoder.next_payload()[18] == 0x08 | 0x20
    assert encoder.next_payload()[18] == 0


@pytest.mark.parametrize("sound", [0, 0x40, 0x80, -1, True])
def test_an_unknown_sound_is_refused(sound: int) -> None:
    with pytest.raises(OutOfRangeError, match="not a combination of Sound flags"):
        ActuatorEncoder().play(sound)  # type: ignore[arg-type]


def test_calibration_is_a_one_shot() -> None:
    encoder = ActuatorEncoder(Actuators(obstacle_avoidance=True))
    encoder.calibrate_proximity()
    assert encoder.next_payload()[0] == 0x01 | 0x02  # calibrate_ir() (493-495)
    assert encoder.next_payload()[0] == 0x02


def test_setting_the_step_counters_sends_them_once_in_place_of_the_speeds() -> None:
    # Bit 2: e_set_steps_left/right (506-508) -> left_motor_set_pos (src/motors.c:218-224);
    # the speeds are left as they were, so the next payload carries them again.
    encoder = ActuatorEncoder(Actuators(speed_left=-200, speed_right=200))
    encoder.set_step_counters(-1, 1000)
    first = encoder.next_payload()
    assert first[0] == 0x04
    assert first[1:5] == bytes([0xFF, 0xFF, 0xE8, 0x03])
    assert encoder.needs_follow_up
    second = encoder.next_payload()
    assert second[0] == 0 and second[1:5] == bytes([0x38, 0xFF, 0xC8, 0x00])


def test_a_step_counter_outside_i16_is_refused() -> None:
    with pytest.raises(OutOfRangeError, match="left step counter 32768 is outside"):
        ActuatorEncoder().set_step_counters(32768, 0)


@given(left=st.integers(-1100, 1100), right=st.integers(-1100, 1100))
def test_any_valid_speed_reads_back_through_the_firmware_decoding(left: int, right: int) -> None:
    payload = encode_actuators(Actuators(speed_left=left, speed_right=right))
    assert len(payload) == 19
    assert firmware_speed(payload[1], payload[2]) == left
    assert firmware_speed(payload[3], payload[4]) == right


# -- the other new commands ----------------------------------------------------------------


def test_the_enable_commands_take_one_byte_and_answer_one_byte() -> None:
    # 0x0F/0x10/0x11 read rx_buff[0] (637/668/700) and answer "buffer[i++] = 0" (660/692/723).
    for code in (0x0F, 0x10, 0x11):
        size = COMMAND_SIZES[BinaryCommand(code)]
        assert (size.request_payload, size.reply) == (1, 1)


@pytest.mark.parametrize(
    ("code", "payload", "reply"),
    [(0x08, 0, 103), (0x09, 19, 0), (0x0A, 12, 0), (0x0B, 0, 1), (0x0C, 0, 8), (0x0D, 0, 2),
     (0x0E, 0, 1)],
)  # fmt: skip
def test_command_sizes(code: int, payload: int, reply: int) -> None:
    size = COMMAND_SIZES[BinaryCommand(code)]
    assert (size.request_payload, size.reply) == (payload, reply)


def test_a_batch_as_the_radio_module_sends_it() -> None:
    # ESP:uart_e-puck2.c:88-91: {0xF8, 0xF7, 19 actuator bytes, 0x00}, 22 bytes.
    payload = encode_actuators(Actuators())
    data, reply = encode_binary_batch(
        [(BinaryCommand.ALL_SENSORS, b""), (BinaryCommand.ALL_ACTUATORS, payload)]
    )
    assert data == b"\xf8\xf7" + bytes(19) + b"\x00"
    assert reply == 103


def test_a_batch_payload_of_the_wrong_size_is_refused() -> None:
    with pytest.raises(OutOfRangeError, match="-0x11 takes 1 payload bytes, not 2"):
        encode_binary_batch([(BinaryCommand.TOF_ENABLE, b"\x01\x00")])
