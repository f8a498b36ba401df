"""Issue 33: ego's bytes on the Pi-puck's I2C, through smbus2's real ioctls and the
emulator's shim (a child process each), checked against what the emulated firmware took.
Each test fails if ego gets its fact wrong (docs/protocol.md, "The Pi-puck")."""

from __future__ import annotations

import itertools
import struct
from collections.abc import Callable

from pipuck_support import Runner

from firmware_sim.pipuck import PipuckEmulator

OPEN = "robot = ego.Robot('pipuck', camera_device='none')\n"


def test_speeds_are_little_endian_words_in_a_message_whose_checksum_holds(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    seen = runner(emu).script(OPEN + (
        "robot.motors.set_speed(300, -2)\n"
        "robot.step(32)\n"
        "print(json.dumps({'firmware': str(robot.channel.info.firmware)}))\n"
        "robot.close()\n"
    ))  # fmt: skip
    assert seen == {"firmware": "epuck2-i2c"}  # detected from the MPU-9250
    truth = emu.truth
    assert truth.checksum_errors == 0  # a wrong XOR would have been dropped
    assert truth.packets >= 2 and truth.last_was_stop  # the close's stop, valid


def test_the_speeds_reach_the_motors_as_sent(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    run = runner(emu)
    child = run.start_ego("run", "--port", "pipuck", "--no-supervised", "--duration", "30",
                          str(_write(run, "from controller import Robot\n"
                                     "r = Robot(); l = r.getDevice('left wheel motor')\n"
                                     "rr = r.getDevice('right wheel motor')\n"
                                     "for m in (l, rr): m.setPosition(float('inf'))\n"
                                     "l.setVelocity(300 * 6.283185307 / 1000)\n"
                                     "rr.setVelocity(-2 * 6.283185307 / 1000)\n"
                                     "while r.step(32) != -1: pass\n")))  # fmt: skip
    from helpers import wait_until

    assert wait_until(lambda: emu.truth.speeds == (300, -2), 30), emu.truth
    packet = emu.truth.last_packet
    assert packet is not None and packet[:4] == struct.pack("<hh", 300, -2)
    child.terminate()
    child.communicate(timeout=30)
    assert emu.truth.last_was_stop


def _write(run: Runner, code: str) -> str:
    path = run.folder / "spin.py"
    path.write_text(code)
    return str(path)


def test_a_reply_with_a_wrong_checksum_is_asked_again_then_refused(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    run = runner(emu)
    code = OPEN + (
        "robot.proximity.enable(32)\n"
        "robot.step(32)\n"
        "before = robot.channel.stats.retries\n"
        "input()\n"  # the test corrupts the next replies now
        "robot.step(32)\n"
        "print(json.dumps({'retries': robot.channel.stats.retries - before,\n"
        "                  'ps': list(robot.proximity.values)}))\n"
        "robot.close()\n"
    )
    seen = _interactive(run, code, lambda: emu.corrupt_next_reply(2))
    assert seen["retries"] == 2  # two corrupted replies refused, the third taken
    assert len(seen["ps"]) == 8 and all(0 <= v <= 4095 for v in seen["ps"])
    refused = _interactive(run, code, lambda: emu.corrupt_next_reply(3))
    assert refused["error"] == "ChecksumError", refused


def test_a_short_reply_never_reaches_the_controller(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    code = OPEN + (
        "robot.proximity.enable(32)\n"
        "robot.step(32)\n"
        "input()\n"
        "robot.step(32)\n"
        "print(json.dumps({'retries': robot.channel.stats.retries,\n"
        "                  'ps': list(robot.proximity.values)}))\n"
        "robot.close()\n"
    )
    seen = _interactive(runner(emu), code, lambda: emu.short_next_reply(20))
    assert seen["retries"] == 1
    assert all(0 <= v <= 4095 for v in seen["ps"])  # 0xFFFF (the idle bus) would be -1


def _interactive(run: Runner, code: str, between: Callable[[], None]) -> dict[str, object]:
    """Run ``code`` in the emulator's environment; call ``between`` at its ``input()``."""
    import json
    import subprocess
    import sys

    body = "".join(f"    {line}\n" for line in code.splitlines())
    wrapped = ("import json, sys, ego\ntry:\n" + body + "except Exception as exc:\n"
               "    print(json.dumps({'error': type(exc).__name__, 'message': str(exc)}))\n")
    base = run.emu.truth.packets
    child = subprocess.Popen([sys.executable, "-c", wrapped], env=run.env, text=True,
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE)  # fmt: skip
    try:
        assert child.stdin is not None and child.stdout is not None
        # The child reads its line once its first step is done: ``between`` acts after it.
        from helpers import wait_until

        assert wait_until(lambda: run.emu.truth.packets >= base + 2, 30)  # open, first step
        between()
        out, err = child.communicate("go\n", timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    lines = out.strip().splitlines()
    assert lines, err
    result: dict[str, object] = json.loads(lines[-1])
    return result


def test_step_counters_are_int16_and_ego_unwraps_them(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    seen = runner(emu).script(OPEN + (
        "import time\n"
        "robot.encoders.enable(32)\n"
        "robot.encoders.set(32700, 32700)\n"
        "robot.motors.set_speed(1000, 1000)\n"
        "start = time.monotonic()\n"
        "values = []\n"
        "while time.monotonic() - start < 1.5:\n"
        "    robot.step(32)\n"
        "    values.append(list(robot.encoders.values))\n"
        "print(json.dumps({'values': values}))\n"
        "robot.close()\n"
    ))  # fmt: skip
    lefts = [v[0] for v in seen["values"]]
    assert lefts[-1] > 32767 + 500  # counted on past the firmware's int16
    assert all(b >= a for a, b in itertools.pairwise(lefts))  # never a jump back at the wrap
    assert emu.truth.steps[0] < 0  # the firmware's own counter did wrap


def test_speeds_beyond_the_firmwares_limit_are_refused(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    seen = runner(emu).script(OPEN + (
        "robot.motors.set_speed(1100, -1100)\n"
        "robot.step(32)\n"
        "try:\n"
        "    robot.motors.set_speed(1101, 0)\n"
        "    refused = None\n"
        "except ego.errors.OutOfRangeError as exc:\n"
        "    refused = str(exc)\n"
        "robot.step(32)\n"
        "print(json.dumps({'refused': refused}))\n"
        "robot.close()\n"
    ))  # fmt: skip
    assert seen["refused"] is not None and "1100" in seen["refused"]
    assert emu.truth.checksum_errors == 0


def test_a_melody_is_sent_in_exactly_one_message(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    runner(emu).script(OPEN + (
        "robot.proximity.enable(32)\n"
        "robot.step(32)\n"
        "robot.sound.play(1)\n"
        "for _ in range(5):\n"
        "    robot.step(32)\n"
        "print(json.dumps({}))\n"
        "robot.close()\n"
    ))  # fmt: skip
    assert len(emu.truth.sounds) == 1, emu.truth.sounds  # the firmware replays it per message


def test_rgb_leds_are_sent_as_percentages(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck()
    run = runner(emu)
    child = run.start_ego("run", "--port", "pipuck", "--no-supervised", "--duration", "30",
                          _write(run, "from controller import Robot\n"
                                 "r = Robot()\n"
                                 "r.getDevice('led1').set(0xFF8000)\n"
                                 "r.getDevice('led7').set(0x0000FF)\n"
                                 "while r.step(32) != -1: pass\n"))  # fmt: skip
    from helpers import wait_until

    assert wait_until(lambda: emu.truth.rgb_leds[0] == (100, 50, 0), 30), emu.truth.rgb_leds
    assert emu.truth.rgb_leds[3] == (0, 0, 100)
    child.terminate()
    child.communicate(timeout=30)
    assert emu.truth.rgb_leds == ((0, 0, 0),) * 4 and emu.truth.last_was_stop


def test_the_legacy_bus_numbers_are_found(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck(buses="legacy", battery_v=3.8)
    assert emu.robot_bus == 4
    seen = runner(emu).script(OPEN + (
        "robot.battery.enable(32)\n"
        "robot.proximity.enable(32)\n"
        "robot.step(32)\n"
        "print(json.dumps({'bus': robot.channel.bus.path, 'battery': robot.battery.raw}))\n"
        "robot.close()\n"
    ))  # fmt: skip
    assert seen == {"bus": "/dev/i2c-4", "battery": 1900}  # 3.8 V, halved, in mV


def test_the_battery_is_read_from_the_boards_adc(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    emu = pipuck(battery_v=3.7)
    seen = runner(emu).script(OPEN + (
        "robot.battery.enable(32)\n"
        "robot.step(32)\n"
        "print(json.dumps({'battery': robot.battery.raw}))\n"
        "robot.close()\n"
    ))  # fmt: skip
    assert seen == {"battery": 1850}


def test_yorks_step_counters_are_set_as_an_offset_over_its_read_only_registers(
    pipuck: Callable[..., PipuckEmulator], runner: Callable[[PipuckEmulator], Runner]
) -> None:
    """Registers 4 and 5 are read-only (main.c:80-81); ego's encoders still set them back
    after a garbled reading (``P``), so the York path keeps the offset itself."""
    emu = pipuck("epuck")
    seen = runner(emu).script(OPEN + (
        "robot.encoders.enable(32)\n"
        "robot.step(32)\n"
        "robot.encoders.set(1000, -5)\n"
        "robot.step(32)\n"
        "print(json.dumps({'values': list(robot.encoders.values),\n"
        "                  'firmware': str(robot.channel.info.firmware)}))\n"
        "robot.close()\n"
    ))  # fmt: skip
    assert seen == {"values": [1000, -5], "firmware": "york"}
