"""The emulator answers as the real firmwares do, quirk by quirk (docs/protocol.md, Quirks).

Each test quotes the source it models: GCtronic's `program/DemoGCtronic-complete/Asercom.c`
and its library (`e_acc.c`, `e_led.c`, `e_motors.c`, `e_micro.c`), and Webots'
`projects/robots/gctronic/e-puck/transfer/firmware/firmware.c`.
"""

from __future__ import annotations

import math
import struct
from typing import Any

import pytest

from firmware_sim import Emulator, World
from firmware_sim.dspic import BANNER, Dspic, Emission
from firmware_sim.world import stepping_rate


def make(firmware: str = "webots", **variant: Any) -> Dspic:
    return Dspic(World(seed=3, noise=False), firmware, **variant)


def batch(*letters: str, args: bytes = b"") -> bytes:
    return bytes((-ord(c)) & 0xFF for c in letters) + args + b"\x00"


def reply(out: list[Emission]) -> bytes:
    return b"".join(e.data for e in out if e.kind == "reply")


def test_the_banner_has_no_leading_spaces() -> None:
    """Asercom.c: "\\f\\a" "WELCOME to the SerCom protocol on e-Puck\\r\\n" "the EPFL ..."."""
    assert BANNER.startswith(b"\x0c\x07WELCOME to the SerCom protocol on e-Puck\r\nthe EPFL")


@pytest.mark.parametrize("end", [b"\n", b"\r", b"\r\n"])
def test_a_command_line_ends_at_newline_or_return(end: bytes) -> None:
    """Asercom.c: `do ... while (c != '\\n' && c != '\\r')`; leading \\n/\\r are skipped."""
    out = make().feed(b"C" + end)
    assert [e.data for e in out] == [b"c,3\r\n"]


def test_spherical_acceleration_is_counts_and_firmware_degrees() -> None:
    """e_acc.c calculate_acc_spherical: sqrtf of the counts less their offsets; inclination
    90 - atan2f(z, r) * CST_RADIAN; orientation 0 below 5 degrees of inclination."""
    magnitude, orientation, inclination = struct.unpack("<3f", reply(make().feed(batch("A"))))
    assert 750 < magnitude < 790  # e_acc.h GRAVITY 768: one g, at rest
    assert orientation == 0.0  # inclination < 5
    assert inclination == pytest.approx(90 - 90 * (180 / 3.1415) / (180 / math.pi), abs=0.01)
    assert inclination < 0.01


def test_a_rev_1_3_over_bluetooth_sits_at_2048() -> None:
    """e_acc.c e_get_acc_filtered on a rev 1.3: ((v>>4) - (v>>6)) + 2048, about 750 a g."""
    x, y, z = struct.unpack("<3H", reply(make("gctronic", selector=3, rev13=True).feed(batch("a"))))
    assert abs(x - 2048) < 20 and abs(y - 2048) < 20
    assert abs(z - 2048 - 750) < 20


def test_stock_bluetooth_mode_serves_eight_ir_and_m_with_cliff_values() -> None:
    """Asercom.c use_bt == 1: N loops j < 8; M sends 6 ground + 4 cliff bytes."""
    dspic = make("gctronic", selector=3)
    assert len(reply(dspic.feed(batch("N")))) == 16
    assert len(reply(dspic.feed(batch("M")))) == 10
    dspic.feed(batch("L", args=bytes([8, 1])))
    assert dspic.world.leds[8] == 1  # e_set_body_led works in this mode


def test_no_ground_module_reads_all_ones() -> None:
    """firmware.c 'M': e_i2cp_read with no ACK check; nobody answers, the bus reads 0xFF."""
    assert reply(make(ground_module=False).feed(batch("M"))) == b"\xff" * 6


def test_battery_is_a_flag_or_a_count_and_absent_on_webots() -> None:
    """Asercom.c 'b': BATT_LOW and 0, or getBatteryValueRaw() on a rev 1.3; firmware.c has none."""
    assert reply(make("gctronic").feed(batch("b"))) == bytes([1, 0])
    (raw,) = struct.unpack("<H", reply(make("gctronic", rev13=True).feed(batch("b"))))
    assert 0 < raw < 4096
    assert reply(make("webots").feed(batch("b", "E"))) == bytes(4)  # only E answers


@pytest.mark.parametrize(
    ("firmware", "echo", "leds"),
    [("gctronic", (300, 300), (0,) * 8 + (1, 1)), ("webots", (0, 0), (0,) * 10)],
)
def test_ascii_stop_differs_between_the_firmwares(
    firmware: str, echo: tuple[int, int], leds: tuple[int, ...]
) -> None:
    """Asercom.c 'S': e_set_speed_*(0) and e_set_led(8, 0) (all ring LEDs), speedl/speedr kept;
    Webots' S also clears what E echoes and the body and front LEDs."""
    dspic = make(firmware, selector=3)
    dspic.feed(batch("D", args=struct.pack("<2h", 300, 300)))
    for i in range(10):
        dspic.feed(batch("L", args=bytes([i, 1])))
    dspic.feed(b"S\n")
    assert dspic.world.speeds == (0, 0)
    assert struct.unpack("<2h", reply(dspic.feed(batch("E")))) == echo
    assert dspic.world.leds == leds


def test_led_values_above_one_toggle() -> None:
    """e_led.c e_set_led: 0 off, 1 on, anything else toggles."""
    dspic = make()
    dspic.feed(batch("L", args=bytes([2, 7])))
    assert dspic.world.leds[2] == 1
    dspic.feed(batch("L", args=bytes([2, 200])))
    assert dspic.world.leds[2] == 0


def test_microphone_index_is_the_next_slot_and_samples_sit_at_mid_scale() -> None:
    """Asercom.c 'U': e_mic_scan then e_last_mic_scan_id, the slot e_ad_conv.c writes next."""
    world = World(seed=3, noise=False)
    buffers, next_slot = world.microphone_buffer()
    assert all(0 <= v <= 4095 for b in buffers for v in b)
    assert all(abs(sum(b) / len(b) - 2048) < 100 for b in buffers)
    # Slot next_slot - 1 is the newest: one sample after it (in time) is the oldest.
    assert 0 <= next_slot < 100


@pytest.mark.parametrize(("asked", "rate"), [(1000, 1000), (950, 1000), (600, 625), (-600, -625)])
def test_wheels_step_at_the_timer_quantised_rate(asked: int, rate: float) -> None:
    """e_motors.c: a step every 10000 / |v| ticks of the 10 kHz timer, in whole ticks."""
    assert stepping_rate(asked) == pytest.approx(rate)
    world = World(seed=1, noise=False)
    now = [0.0]
    world.use_clock(lambda: now[0])  # the world's own clock: no time passes between lines
    world.set_speeds(asked, asked)
    now[0] = 2.0
    world.advance()
    left, _ = world.steps_int16()
    assert left == pytest.approx(2 * rate, abs=2)


def test_rc5_remote_drives_even_in_overo_mode_and_e_echoes_it() -> None:
    """Asercom.c: the IR receiver's keys set speedl/speedr in both UART loops."""
    dspic = make("gctronic")
    dspic.rc5_key(2)
    assert dspic.world.speeds == (600, 600)
    assert struct.unpack("<2h", reply(dspic.feed(batch("E")))) == (600, 600)


def test_the_emulator_paces_each_firmware_at_its_own_line() -> None:
    """Webots' firmware: UART1 at 115200; stock: UART2 at 230400 in selector 10."""
    with Emulator("webots", seed=1) as webots, Emulator("gctronic", seed=1) as stock:
        assert (webots.baud, stock.baud) == (115200, 230400)
    with Emulator("gctronic", seed=1, selector=3, latency_s=0.008) as bluetooth:
        assert (bluetooth.baud, bluetooth.latency_s) == (115200, 0.008)
