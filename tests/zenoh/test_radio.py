"""Webots' radio over Zenoh: what a receiver makes of a packet (sans I/O), and the
Emitter and Receiver devices of the Webots face, refusing what Webots would."""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

import pytest
from helpers import ego_command

from ego.zenoh_net.keys import BROADCAST, radio_key, radio_keys
from ego.zenoh_net.radio import attachment, received


def test_a_packet_from_elsewhere_has_the_strength_and_direction_of_the_two_poses() -> None:
    # The emitter 0.5 m ahead and 0.5 m to the left of a receiver facing +y.
    sent = attachment("a", -1.0, [0.0, 1.0, 0.0])
    packet = received(b"hi", sent, 1, "b", [0.5, 0.5, math.pi / 2])
    assert packet is not None and packet.data == b"hi" and packet.sender == "a"
    assert packet.signal_strength == pytest.approx(1 / 0.5)  # 1 / d², d² = 0.5
    x, y, z = packet.direction
    assert (x, y, z) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5), 0.0))  # ahead, left


def test_own_packets_packets_beyond_range_and_foreign_ones_are_not_received() -> None:
    assert received(b"x", attachment("me", -1.0, None), 1, "me", None) is None
    assert received(b"x", attachment("a", 0.3, [0.0, 0.0, 0.0]), 1, "b", [0.4, 0.0, 0.0]) is None
    assert received(b"x", attachment("a", 0.5, [0.0, 0.0, 0.0]), 1, "b", [0.4, 0.0, 0.0])
    assert received(b"x", b"not json", 1, "b", None) is None


def test_without_poses_strength_and_direction_are_unavailable() -> None:
    packet = received(b"x", attachment("a", 0.1, None), 1, "b", [0.0, 0.0, 0.0])
    assert packet is not None  # no pose: the range cannot be judged, the packet comes
    assert math.isnan(packet.signal_strength) and all(map(math.isnan, packet.direction))


def test_channels_map_to_keys() -> None:
    assert radio_key(1) == "ego/radio/1" and radio_key(BROADCAST) == "ego/radio/all"
    assert radio_keys(3) == ["ego/radio/3", "ego/radio/all"]
    assert radio_keys(BROADCAST) == ["ego/radio/*"]


def _run(
    tmp_path: Path, body: str, env: dict[str, str] | None = None
) -> subprocess.CompletedProcess[str]:
    controller = tmp_path / "radio.py"
    controller.write_text("from controller import Robot\nrobot = Robot()\n" + body)
    import os

    return subprocess.run(
        [*ego_command(), "run", "--port", "sim", str(controller)], capture_output=True,
        text=True, timeout=60, cwd=tmp_path, env={**os.environ, **(env or {})},
    )  # fmt: skip


def test_the_webots_face_has_a_radio_that_refuses_what_webots_would(tmp_path: Path) -> None:
    result = _run(tmp_path, (
        "emitter, receiver = robot.getDevice('emitter'), robot.getDevice('receiver')\n"
        "print(type(emitter).__name__, type(receiver).__name__, emitter.getChannel())\n"
        "for bad in (lambda: emitter.setChannel(-2), lambda: emitter.send(3.5),\n"
        "            lambda: emitter.setRange(-0.5), lambda: receiver.getData(),\n"
        "            lambda: receiver.enable(0)):\n"
        "    try:\n"
        "        bad()\n"
        "    except Exception as exc:\n"
        "        print(type(exc).__name__)\n"
        "receiver.enable(32); robot.step(32)\n"
        "print('queue', receiver.getQueueLength())\n"
    ))  # fmt: skip
    assert result.returncode == 0, result.stderr
    lines = result.stdout.split("\n")
    assert lines[0] == "Emitter Receiver 1"
    assert lines[1:6] == ["OutOfRangeError", "DeviceError", "OutOfRangeError", "DeviceError",
                          "OutOfRangeError"]  # fmt: skip
    assert lines[6] == "queue 0"


def test_without_a_radio_the_devices_are_absent_the_webots_way(tmp_path: Path) -> None:
    result = _run(tmp_path, "print(robot.getDevice('emitter'))\n", env={"EGO_RADIO": "none"})
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "None"
    assert 'Device "emitter" was not found on robot "e-puck"' in result.stderr
