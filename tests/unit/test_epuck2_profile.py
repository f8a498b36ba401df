"""The e-puck2's profiles (USB, Bluetooth) on bytes alone: detection from ``V``, the wire
formats of the e-puck1 commands it keeps and of its own, its timings and limits, and the
batch strategy (e-puck1 commands, or the "all sensors" packet where it costs less)."""

from __future__ import annotations

import struct

import pytest

from ego.core.safety import stop_requests
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware
from ego.serial.asercom2 import COMMAND_SIZES, BinaryCommand
from ego.serial.firmware import identify
from ego.serial.link import LinkSettings, reply_timeout_s
from ego.serial.profiles import EPUCK2_BLUETOOTH, EPUCK2_USB, PROFILES
from ego.serial.protocol import encode_batch

V2 = ["v,Version 2.0 January 2018 GCtronic", "HW version: FFF7"]
PACKET = struct.Struct("<3h3f3h3fb8H8HH4H2hHB3BB3H3HB")


def packet(**fields: object) -> bytes:
    """A 103-byte -0x08 reply whose 49 values are their index, but for ``fields`` and
    the SD byte (37) and selector (41), which hold what the firmware sends (1, 8): the
    packet's decoder refuses others (docs/protocol.md)."""
    values: list[object] = [*range(48), 0]
    values[37], values[41] = 1, 8
    for index, value in fields.items():
        values[int(index.removeprefix("v"))] = value
    return PACKET.pack(*values)


# -- detection ---------------------------------------------------------------------------


@pytest.mark.parametrize(("selector", "profile"), [(8, EPUCK2_USB), (None, EPUCK2_USB),
                                                   (3, EPUCK2_BLUETOOTH)])  # fmt: skip
def test_version_2_gctronic_opens_as_an_epuck2(selector: int | None, profile: object) -> None:
    info = identify(V2, selector, "b,3194 (62%)")
    assert info.firmware is Firmware.EPUCK2 and info.profile is profile
    assert info.hardware_version == 0xFFF7  # the e-puck2 has no EEPROM (DataEEPROM.c:3-12)
    assert info.version == "Version 2.0 January 2018 GCtronic"


def test_the_e_puck1_firmwares_are_still_told_apart() -> None:
    assert identify(["v,Version 1.2.2 August 2008 GCtronic"], 10).firmware is Firmware.GCTRONIC
    assert identify(["v,Version 1.5.3 November 2016 (Webots)"]).firmware is Firmware.WEBOTS


def test_the_firmware_is_named_epuck2() -> None:
    assert Firmware("epuck2") is Firmware.EPUCK2 and PROFILES[Firmware.EPUCK2] is EPUCK2_USB


# -- wire formats ------------------------------------------------------------------------


@pytest.mark.parametrize("code", list(BinaryCommand), ids=lambda c: c.name)
def test_the_new_commands_have_the_sizes_of_asercom2(code: BinaryCommand) -> None:
    fmt = EPUCK2_USB.wire_format(Command(code.byte))
    size = COMMAND_SIZES[code]
    assert (fmt.arguments.size, fmt.reply.size) == (size.request_payload, size.reply)


@pytest.mark.parametrize(
    "command", [Command.MAGNETOMETER_ENABLE, Command.PROXIMITY_MODE, Command.TOF_ENABLE]
)
def test_the_enable_commands_answer_one_byte(command: Command) -> None:
    # Corrections box: -0x0F, -0x10, -0x11 each answer one byte (0).
    assert encode_batch([Request(command, (1,))], EPUCK2_USB).reply_size == 1


def test_floor_answers_eight_bytes_three_ground_and_one_cliff() -> None:
    # Corrections box: -'M' returns 8 bytes (3 ground + 1 cliff value).
    assert encode_batch([Request(Command.FLOOR)], EPUCK2_USB).reply_size == 8


def test_the_mic_buffer_is_not_served_it_answers_nothing() -> None:
    # Asercom2.c:964-975: -'U' is commented out; a batch with it would wait for ever.
    assert not EPUCK2_USB.supports(Command.MIC_BUFFER)
    assert not EPUCK2_BLUETOOTH.supports(Command.MIC_BUFFER)


def test_the_odd_leds_are_rgb_never_sent_as_l() -> None:
    # Corrections box: -'L' on an odd LED sets only its red channel at 10 %.
    for profile in (EPUCK2_USB, EPUCK2_BLUETOOTH):
        assert profile.leds == (0, 2, 4, 6, 8, 9)
        assert profile.rgb_leds == (1, 3, 5, 7)


def test_the_stop_switches_the_rgb_leds_off_too() -> None:
    stop = stop_requests(EPUCK2_USB.leds, EPUCK2_USB.rgb_leds)
    assert Request(Command.RGB_LEDS, (0,) * 12) in stop
    assert all(r.arguments[0] not in (1, 3, 5, 7) for r in stop if r.command is Command.SET_LED)
    assert stop[-1] == Request(Command.GET_SPEED)


def test_ascii_s_leaves_body_front_and_the_echo() -> None:
    # Corrections box: S leaves the body and front LEDs and the speed that E reports.
    assert EPUCK2_USB.ascii_stop.leds == tuple(range(8))
    assert not EPUCK2_USB.ascii_stop.clears_echo


def test_the_speed_limit_is_the_firmwares_clamp_and_the_models_is_higher() -> None:
    # Corrections box: the firmware clamps at 1100 steps/s; Webots' e-puck2 model uses 1200.
    assert EPUCK2_USB.max_speed_steps == EPUCK2_BLUETOOTH.max_speed_steps == 1100
    assert EPUCK2_USB.model_max_velocity_rad_s == 7.536
    assert PROFILES[Firmware.WEBOTS].max_speed_steps == 1000


def test_negative_speeds_go_as_signed_little_endian() -> None:
    batch = encode_batch([Request(Command.SET_SPEED, (-200, 200))], EPUCK2_USB)
    assert batch.tx == bytes([0xBC]) + struct.pack("<hh", -200, 200) + b"\x00"


# -- timings -----------------------------------------------------------------------------


def _timeout(profile: object, requests: list[Request]) -> float:
    class Pty:
        baudrate = 230400
        latency_s = 0.0

    batch = encode_batch(requests, profile)  # type: ignore[arg-type]
    return reply_timeout_s(batch, profile, Pty(), LinkSettings())  # type: ignore[arg-type]


def test_all_actuators_costs_a_10_ms_sleep_over_usb_only() -> None:
    # Asercom2.c:481: over USB each -0x09 sleeps 10 ms after its payload.
    payload = (0, 0, 0, 0, *([0] * 12), 0)
    assert EPUCK2_USB.work_s[Command.ALL_ACTUATORS] == pytest.approx(0.010)
    assert Command.ALL_ACTUATORS not in EPUCK2_BLUETOOTH.work_s
    with_it = _timeout(EPUCK2_USB, [Request(Command.ALL_ACTUATORS, payload)])
    assert with_it - _timeout(EPUCK2_BLUETOOTH, [Request(Command.ALL_ACTUATORS, payload)]) > 0
    assert EPUCK2_USB.cost_s(Command.ALL_ACTUATORS) > 0.010


def test_the_line_rates_usb_unpaced_model_and_bluetooth_uart() -> None:
    assert EPUCK2_BLUETOOTH.line_baud == 115200
    assert EPUCK2_USB.line_baud > 1_000_000  # USB full speed: bytes are nearly free


def test_the_filtered_accelerometer_costs_60_ms() -> None:
    assert EPUCK2_USB.work_s[Command.ACCELEROMETER_RAW] == pytest.approx(0.060)


# -- the batch strategy ------------------------------------------------------------------


def test_a_few_reads_go_as_the_e_puck1_commands() -> None:
    batch = encode_batch([Request(Command.PROXIMITY), Request(Command.GET_STEPS)], EPUCK2_USB)
    assert batch.tx == bytes([Command.PROXIMITY, Command.GET_STEPS, 0])
    assert batch.reply_size == 16 + 4


@pytest.mark.parametrize("profile", [EPUCK2_USB, EPUCK2_BLUETOOTH], ids=["usb", "bt"])
def test_every_read_but_the_accelerometer_still_goes_as_commands(profile: object) -> None:
    reads = [Command.PROXIMITY, Command.LIGHT, Command.GET_STEPS, Command.TOF,
             Command.GYRO_RAW, Command.MICROPHONES_4, Command.BATTERY]  # fmt: skip
    batch = encode_batch([Request(c) for c in reads], profile)  # type: ignore[arg-type]
    assert Command.ALL_SENSORS not in batch.tx


def test_the_accelerometer_brings_the_packet_and_the_rest_ride_in_it() -> None:
    requests = [Request(Command.SET_SPEED, (300, -300)), Request(Command.PROXIMITY),
                Request(Command.ACCELEROMETER_RAW), Request(Command.GET_STEPS),
                Request(Command.GET_SPEED)]  # fmt: skip
    batch = encode_batch(requests, EPUCK2_USB)
    assert batch.tx == (bytes([Command.SET_SPEED]) + struct.pack("<hh", 300, -300)
                        + bytes([Command.ALL_SENSORS, Command.GET_SPEED, 0]))  # fmt: skip
    assert batch.reply_size == 103 + 4
    reply = packet(v0=-3, v1=5, v2=768, v34=-7, v35=9) + struct.pack("<hh", 300, -300)
    speeds, proximity, acc, steps, echo = batch.decode(reply)
    assert speeds == ()
    assert proximity == tuple(range(13, 21))
    assert acc == (2045, 2053, 2816)  # the packet's 0-centred counts, as -'a' gives them
    assert steps == (-7, 9)
    assert echo == (300, -300)


def test_a_routed_batchs_own_values_are_rewritten_and_the_packets_are_refused() -> None:
    """Batch.with_values (a served robot held stopped answers the speed echo as asked)."""
    requests = [Request(Command.SET_SPEED, (300, -300)), Request(Command.PROXIMITY),
                Request(Command.ACCELEROMETER_RAW), Request(Command.GET_SPEED)]  # fmt: skip
    batch = encode_batch(requests, EPUCK2_USB)
    reply = packet(v0=-3) + struct.pack("<hh", 0, 0)
    rewritten = batch.with_values(reply, 3, (300, -300))
    assert batch.decode(rewritten)[3] == (300, -300)
    assert batch.decode(rewritten)[:3] == batch.decode(reply)[:3]  # the rest as it was
    with pytest.raises(ValueError, match="cannot be rewritten"):
        batch.with_values(reply, 1, (0,) * 8)  # the proximity rides in the packet


def test_families_only_the_packet_serves_share_one_packet() -> None:
    requests = [Request(Command.ALL_SENSORS), Request(Command.ALL_SENSORS),
                Request(Command.LIGHT)]  # fmt: skip
    batch = encode_batch(requests, EPUCK2_USB)
    assert batch.tx == bytes([Command.ALL_SENSORS, 0]) and batch.reply_size == 103
    first, second, light = batch.decode(packet(v12=31))
    assert first == second and first[12] == 31 and len(first) == 49
    assert light == tuple(range(21, 29))


def test_e_puck1_profiles_never_ask_the_packet() -> None:
    requests = [Request(Command.ACCELEROMETER_RAW), Request(Command.PROXIMITY)]
    batch = encode_batch(requests, PROFILES[Firmware.WEBOTS])
    assert batch.tx == bytes([Command.ACCELEROMETER_RAW, Command.PROXIMITY, 0])



def test_a_step_that_sets_every_actuator_sends_no_all_actuators() -> None:
    # Over USB each -0x09 sleeps 10 ms: ego's families set speeds with D, LEDs with L and
    # the RGB LEDs with -0x0A, whatever changed in the step.
    from ego.devices.base import PHASE
    from ego.devices.families import make_families, pick
    from ego.devices.leds import Leds
    from ego.devices.motors import Motors

    families = make_families(EPUCK2_USB)
    pick(families, "motors", Motors).set_speed(-1100, 1100)
    leds = pick(families, "leds", Leds)
    for index in range(10):
        leds.set(index, 0x123456 if index in EPUCK2_USB.rgb_leds else 1)
    plan = [r for family in families.values() for part in family.parts for r in part.plan(0)]
    batch = encode_batch(sorted(plan, key=lambda r: PHASE[r.command]), EPUCK2_USB)
    commands = [r.command for r in batch.requests]
    assert Command.ALL_ACTUATORS not in commands and Command.RGB_LEDS in commands
    assert [r.arguments[0] for r in batch.requests if r.command is Command.SET_LED] == [
        0, 2, 4, 6, 8, 9
    ]
    assert Request(Command.RGB_LEDS, (7, 20, 34) * 4) in batch.requests
