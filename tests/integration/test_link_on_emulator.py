"""The link over a real pty against the emulated dsPIC, for both firmware profiles."""

from __future__ import annotations

import struct

import pytest
import serial
from fakes import FAST_LINK

from ego.errors import ExtraBytesError, UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.profile import Command, Firmware
from ego.serial.link import Link
from ego.serial.protocol import encode_batch
from ego.serial.transport import SerialTransport
from firmware_sim import Emulator


def req(letter: str, *args: int) -> Request:
    return Request(Command((-ord(letter)) & 0xFF), tuple(args))


SENSORS = {
    Firmware.WEBOTS: [req(c) for c in "aEMNOQu"],
    Firmware.GCTRONIC: [req(c) for c in "aENOQu"],  # M is refused there
}


@pytest.mark.parametrize(
    ("firmware", "selector"), [("webots", 3), ("gctronic", 10)], ids=["webots", "overo"]
)
def test_v_probe_detects_the_firmware(firmware: str, selector: int) -> None:
    """protocol.md: "The library learns which firmware it talks to at start-up" from V
    (and C for the stock firmware). Default settings, banner at power-on included."""
    with Emulator(firmware, seed=1) as emu:
        link = Link(SerialTransport(emu.path))
        try:
            assert link.info.firmware is Firmware(firmware)
            assert link.info.detected
            assert link.info.hardware_version == 0xFFFF  # Asercom.c: an unwritten EEPROM word
            if firmware == "gctronic":
                assert link.info.selector == selector
        finally:
            link.close()


def test_forced_firmware_is_trusted(overo_emulator: Emulator) -> None:
    link = Link(SerialTransport(overo_emulator.path), firmware="webots", settings=FAST_LINK)
    try:
        assert link.info.firmware is Firmware.WEBOTS
        assert not link.info.detected
        # The wrong profile expects 16 bytes for N where this firmware sends 20: the link
        # refuses them (typed) rather than misparse them.
        with pytest.raises(ExtraBytesError):
            link.exchange(encode_batch([req("N")], link.profile))
    finally:
        link.close()


def test_forced_firmware_matching_the_robot_works(overo_emulator: Emulator) -> None:
    link = Link(SerialTransport(overo_emulator.path), firmware="gctronic")
    try:
        batch = encode_batch([req("N")], link.profile)
        (values,) = batch.decode(link.exchange(batch))
        assert len(values) == 10
    finally:
        link.close()


def test_rev_1_3_overo_refuses_the_accelerometer_it_would_read_as_zeros() -> None:
    """Asercom.c: zeros for a/A in Overo mode on a rev 1.3, told at open by b's reply."""
    with Emulator("gctronic", seed=1, rev13=True) as emu:
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        try:
            assert link.info.firmware is Firmware.GCTRONIC
            assert link.profile.rev13 is True
            with pytest.raises(UnsupportedDeviceError, match=r"rev 1\.3"):
                encode_batch([req("a")], link.profile)
        finally:
            link.close()


@pytest.mark.parametrize("which", ["emulator", "overo_emulator"])
def test_sensor_step_delivers_what_the_dspic_sent(
    which: str, request: pytest.FixtureRequest
) -> None:
    emu: Emulator = request.getfixturevalue(which)
    link = Link(SerialTransport(emu.path), settings=FAST_LINK)
    try:
        batch = encode_batch(SENSORS[link.info.firmware], link.profile)
        reply = link.exchange(batch)
        record = emu.history[-1]
        assert reply == record.reply
        assert record.commands == "".join(r.command.letter for r in batch.requests)
        proximity = batch.decode(reply)[
            [r.command for r in batch.requests].index(Command.PROXIMITY)
        ]
        assert len(proximity) == (8 if link.info.firmware is Firmware.WEBOTS else 10)
    finally:
        link.close()


def test_actuators_reach_the_world(link: Link, emulator: Emulator) -> None:
    link.exchange(encode_batch([req("D", 300, -200), req("L", 8, 1)], link.profile))
    batch = encode_batch([req("E")], link.profile)
    assert batch.decode(link.exchange(batch)) == [(300, -200)]
    assert emulator.world.leds[8] == 1


def test_microphone_buffer_crosses_the_link(link: Link, emulator: Emulator) -> None:
    batch = encode_batch([req("E"), req("U")], link.profile)
    reply = link.exchange(batch)
    assert len(reply) == 605
    assert reply == emulator.history[-1].reply
    speeds, mic = batch.decode(reply)
    assert speeds == (0, 0)
    assert len(mic) == 301
    assert 0 <= mic[-1] < 100


def test_stop_command_stops_the_robot(link: Link, emulator: Emulator) -> None:
    link.exchange(encode_batch([req("D", 500, 500)], link.profile))
    assert link.ascii_command("S") == ["s"]
    assert emulator.world.speeds == (0, 0)


def test_step_counters_follow_the_wheels(link: Link) -> None:
    link.exchange(encode_batch([req("P", 0, 0), req("D", 1000, -1000)], link.profile))
    batch = encode_batch([req("Q")], link.profile)
    counts = [batch.decode(link.exchange(batch))[0] for _ in range(20)]
    left = [c[0] for c in counts]
    right = [c[1] for c in counts]
    assert left == sorted(left)
    assert right == sorted(right, reverse=True)
    assert left[-1] > left[0]


@pytest.mark.slow
def test_thousand_steps_on_the_raw_pty_with_pyserial() -> None:
    """The emulator's pty is a serial port to pyserial: 1,000 steps of `a E M N O Q u`
    (paced at 921600 baud to keep the run short; the link's runs use 230400)."""
    tx = bytes.fromhex("9f bb b3 b2 b1 af 8b 00")
    with (
        Emulator("webots", seed=2, baud=921600) as emulator,
        serial.Serial(emulator.path, 921600, timeout=1.0) as port,
    ):
        port.timeout = 0.2
        while port.read(4096):  # the power-on banner
            pass
        port.timeout = 1.0
        for _ in range(1000):
            port.write(tx)
            reply = port.read(58)
            assert len(reply) == 58
            assert reply == emulator.history[-1].reply
        port.timeout = 0.05
        assert port.read(1) == b""
        assert emulator.dspic.batches == 1000


@pytest.mark.slow
@pytest.mark.parametrize("which", ["emulator", "overo_emulator"])
def test_thousand_clean_steps_over_the_link_with_default_settings(
    which: str, request: pytest.FixtureRequest
) -> None:
    emu: Emulator = request.getfixturevalue(which)
    link = Link(SerialTransport(emu.path))
    try:
        batch = encode_batch(SENSORS[link.info.firmware], link.profile)
        for step in range(1000 if which == "emulator" else 200):
            speeds = (step % 2001 - 1000, 1000 - step % 2001)
            full = encode_batch([req("D", *speeds), *batch.requests], link.profile)
            reply = link.exchange(full)
            assert reply == emu.history[-1].reply
            assert full.decode(reply)[2] == speeds  # E: "last commanded speeds"
        # A clean line needs no retry; a loaded test machine may still stall the emulator's
        # thread past a reply timeout now and then, which the link must (and did) absorb.
        assert link.stats.retries <= 10
        assert set(link.stats.faults) <= {"LinkTimeoutError"}
    finally:
        link.close()


def test_speed_on_the_wire_is_little_endian_signed(link: Link) -> None:
    batch = encode_batch([req("D", -1, -1000), req("E")], link.profile)
    assert batch.tx[:5] == b"\xbc" + struct.pack("<2h", -1, -1000)
    assert batch.decode(link.exchange(batch))[1] == (-1, -1000)
