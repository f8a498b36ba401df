"""Issue 32, item 4: over WiFi, the reads only the "all sensors" packet holds (selector,
temperature, magnetometer) beside the e-puck1's reads. The profile routes covered reads
through one ``-0x08``; the WiFi channel answers what the batch put on the wire
(``Batch.wire``), so its reply is the one the batch decodes. Before, it answered the
requests as asked and every step raised ExtraBytesError (222 bytes where 103 were asked)."""

from __future__ import annotations

import ego
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.profiles import EPUCK2_WIFI
from ego.serial.protocol import encode_batch
from firmware_sim.epuck2 import Epuck2Emulator


def test_selector_and_temperature_beside_other_reads_step_over_wifi(
    url: str, wifi: Epuck2Emulator
) -> None:
    with ego.Robot(url) as robot:
        robot.selector.enable(32)
        robot.temperature.enable(32)
        robot.proximity.enable(32)
        robot.tof.enable(32)
        robot.battery.enable(32)
        for _ in range(5):
            robot.step(32)
        assert robot.selector.position == wifi.robot.selector == 15
        assert robot.temperature.celsius == wifi.robot.imu.temperature()
        assert robot.tof.distance_mm == wifi.robot.tof.distance_mm()
        assert list(robot.proximity.values) == list(wifi.robot.proximity.calibrated())


def test_the_batch_says_what_goes_on_the_wire() -> None:
    """The routing is declared once (the profile's ``all_sensors``): ``Batch.wire`` is
    what ``tx`` holds, and its replies add up to ``reply_size``."""
    profile = EPUCK2_WIFI
    asked = [Request(Command.ALL_SENSORS), Request(Command.PROXIMITY),
             Request(Command.ALL_SENSORS), Request(Command.SET_SPEED, (1, 2))]  # fmt: skip
    batch = encode_batch(asked, profile)
    assert [r.command for r in batch.wire] == [Command.ALL_SENSORS, Command.SET_SPEED]
    sizes = sum(profile.wire_format(r.command).reply.size for r in batch.wire)
    assert sizes == batch.reply_size == 103
