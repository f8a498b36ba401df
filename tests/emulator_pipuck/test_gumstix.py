"""The e-puck2's gumstix I2C mode over the shim: one 20-byte write and one 47-byte read
in a combined transaction, each ending in an XOR (e-puck2_main-processor, branch
gumstix, src/gumstix.c; firmware_sim/pipuck/PROTOCOL_NOTES.md)."""

from __future__ import annotations

import struct
import time

from pipuck_harness import quiet_world

from firmware_sim.pipuck import PipuckEmulator
from firmware_sim.world import Block, Pose


def xor(data: list[int]) -> int:
    check = 0
    for byte in data:
        check ^= byte
    return check


def decode(reply: list[int]) -> dict[str, object]:
    """The 47-byte reply as gumstix.c:111-160 builds it, little-endian words."""
    raw = bytes(reply)
    return {
        "prox": struct.unpack_from("<8H", raw, 0),
        "ambient": struct.unpack_from("<8H", raw, 16),
        "mics": struct.unpack_from("<4H", raw, 32),
        "selector": raw[40] & 0x0F,
        "button": raw[40] >> 4 & 1,
        "steps": struct.unpack_from("<2h", raw, 41),
        "tv": raw[45],
    }


def test_a_combined_transaction_applies_the_command_and_answers_47_bytes(epuck2, client_of):
    client = client_of(epuck2)
    rgb = (100, 0, 0, 0, 100, 0, 0, 0, 100, 50, 50, 50)
    reply = client(f"exchange(12, packet(300, -400, red=0b1010, rgb={rgb}))")
    assert len(reply) == 47 and xor(reply[:46]) == reply[46]
    fields = decode(reply)
    assert fields["selector"] == 10 and fields["button"] == 0  # gumstix mode, main.c:178
    truth = epuck2.truth
    assert truth.speeds == (300, -400)
    assert truth.red_leds == (False, True, False, True)  # LED3, LED7
    assert truth.rgb_leds == ((100, 0, 0), (0, 100, 0), (0, 0, 100), (50, 50, 50))
    assert truth.packets == 1 and truth.checksum_errors == 0 and not truth.last_was_stop
    assert epuck2.world.leds[:8] == (0, 1, 1, 1, 0, 1, 1, 1)  # red LED3/7, RGB lit


def test_words_are_little_endian(epuck2, client_of):
    # Ambient light reads in the thousands: both bytes matter.
    client = client_of(epuck2)
    fields = decode(client("exchange(12, packet())"))
    ambient = epuck2.machine.epuck2.proximity.ambient()
    assert list(fields["ambient"]) == ambient and max(ambient) > 255
    prox = epuck2.machine.epuck2.proximity.calibrated()
    assert list(fields["prox"]) == prox  # uncalibrated at power-on: the raw deltas


def test_a_wrong_checksum_drops_the_command_but_not_the_reply(epuck2, client_of):
    client = client_of(epuck2)
    client("exchange(12, packet(200, 200))")
    good = packet_checksum(200, 200)
    reply = client(f"exchange(12, packet(900, 900, red=15, checksum={good ^ 1}))")
    assert len(reply) == 47 and xor(reply[:46]) == reply[46]
    truth = epuck2.truth
    assert truth.speeds == (200, 200) and truth.red_leds == (False,) * 4
    assert truth.packets == 2 and truth.checksum_errors == 1


def packet_checksum(left: int, right: int) -> int:
    return xor(list(struct.pack("<hh", left, right)) + [0] * 15)


def test_speeds_are_clamped_to_1100(epuck2, client_of):
    client = client_of(epuck2)
    client("exchange(12, packet(2000, -32768))")
    assert epuck2.truth.speeds == (1100, -1100)  # motors.c:195-200


def test_rgb_bytes_are_taken_as_sent_on_the_0_to_100_scale(epuck2, client_of):
    # gumstix.c:226-229 passes each byte to set_rgb_led: 100 is full, and nothing scales
    # or clamps a 255 (a client sending 0-255 gets 2.55 times too much).
    client = client_of(epuck2)
    client(f"exchange(12, packet(rgb={(255, 100, 1) + (0,) * 9}))")
    assert epuck2.truth.rgb_leds[0] == (255, 100, 1)


def test_a_sound_plays_once_per_packet_that_asks(epuck2, client_of):
    client = client_of(epuck2)
    client("exchange(12, packet(speaker=1))")
    client("exchange(12, packet())")
    assert epuck2.truth.sounds == ("mario",)
    client("exchange(12, packet(speaker=3))")
    client("exchange(12, packet(speaker=3))")  # held: asked again
    client("exchange(12, packet(speaker=4))")  # not a melody (gumstix.c:217)
    assert epuck2.truth.sounds == ("mario", "starwars", "starwars")


def test_the_step_counters_wrap_as_int16(epuck2, client_of):
    client = client_of(epuck2)
    # Settings bit 2: the words set the step counters (gumstix.c:240-242).
    client("exchange(12, packet(32760, -32760, settings=4))")
    client("exchange(12, packet(1000, -1000))")
    epuck2.advance(0.1)  # about 100 steps each way
    steps = decode(client("exchange(12, packet(0, 0))"))["steps"]
    assert steps[0] < -32000 and steps[1] > 32000, steps
    assert epuck2.truth.steps == steps


def test_stop_is_recognised_and_a_read_alone_repeats_the_last_reply(epuck2, client_of):
    client = client_of(epuck2)
    client("exchange(12, packet(100, 100, speaker=2))")
    assert not epuck2.truth.last_was_stop
    first = client("exchange(12, packet())")
    assert epuck2.truth.last_was_stop and epuck2.truth.speeds == (0, 0)
    assert client("read_only(12)") == first  # gumstix.c:196-198
    assert epuck2.truth.packets == 2


def test_reply_faults_corrupt_the_checksum_or_cut_the_reply(epuck2, client_of):
    client = client_of(epuck2)
    epuck2.corrupt_next_reply()
    bad = client("exchange(12, packet())")
    assert xor(bad[:46]) != bad[46]
    good = client("exchange(12, packet())")
    assert xor(good[:46]) == good[46]
    epuck2.short_next_reply(20)
    short = client("exchange(12, packet())")
    assert short[20:] == [0xFF] * 27 and short[:20] == good[:20]


def test_proximity_and_the_world_agree(epuck2, client_of):
    client = client_of(epuck2)
    far = decode(client("exchange(12, packet())"))["prox"]
    epuck2.world.blocks.append(Block(0.06, 0.0, 0.02, (200, 60, 60)))  # a wall just ahead
    epuck2.world.place(Pose(0.0, 0.0, 0.0))
    near = decode(client("exchange(12, packet())"))["prox"]
    assert near[0] > far[0] + 500 and near[7] > far[7] + 500  # the two front sensors
    assert near[3] == far[3]  # the back one sees nothing new
    # Settings bit 0 calibrates: what the sensors see now becomes their zero.
    client("exchange(12, packet(settings=1))")
    assert max(decode(client("exchange(12, packet())"))["prox"]) == 0


def test_the_wire_time_of_a_step_at_100_and_400_khz(client_of):
    # Per message a start, the address and its acknowledge (10 bits), 9 bits a byte;
    # one stop: 10 + 180 + 10 + 423 + 1 = 624 bit times.
    for hz, expected in ((100_000, 6.24e-3), (400_000, 1.56e-3)):
        with PipuckEmulator("epuck2", world=quiet_world(), virtual_time=True, bus_hz=hz) as emu:
            client_of(emu)("exchange(12, packet())")
            assert abs(emu.truth.wire_s - expected) < 1e-9


def test_a_paced_bus_spends_the_wire_time(client_of):
    with PipuckEmulator("epuck2", world=quiet_world(), bus_hz=1_000, paced=True) as emu:
        client = client_of(emu)
        start = time.monotonic()
        client("exchange(12, packet())")
        assert time.monotonic() - start >= 0.624  # a lower bound: sleeps never end early
