"""The dashboard and the recordings pick the e-puck2 up from the device table: its new
sensors are offered and drawn, its RGB LEDs shown in their colour (real Chromium), and a
recorded e-puck2 run reads back with them."""

from __future__ import annotations

import os
import subprocess
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from helpers import ego_command

import ego
from ego.core.telemetry import describe_robot
from ego.nursery import Nursery
from ego.recording.reader import Recording
from ego.servers.dashboard.live import RobotDashboard

CONTROLLER = Path(__file__).parents[1] / "faces" / "controllers" / "epuck2_tof_gyro.py"
#: The sensors only the e-puck2 has, by the device table's family names.
NEW_SENSORS = ("tof", "gyro", "magnetometer", "temperature", "button", "selector")


@contextmanager
def served_epuck2(controller: Callable[[ego.Robot], None]) -> Iterator[tuple[ego.Robot, str]]:
    """An emulated e-puck2 stepped by ``controller`` in a thread, with its dashboard."""
    robot = ego.Robot("sim", robot="epuck2", seed=1)
    dashboard = RobotDashboard("127.0.0.1:0", None, out=open(os.devnull, "w"))  # noqa: SIM115
    dashboard.attach(robot)
    stop = threading.Event()
    failures: list[BaseException] = []

    def loop() -> None:
        try:
            while not stop.is_set():
                controller(robot)
                if robot.step(32) == -1:
                    return
        except BaseException as exc:  # reported by the test
            failures.append(exc)

    threads = Nursery("the test's controller", join_s=10)
    threads.start_thread(loop, name="test-controller")
    try:
        assert dashboard.server is not None
        yield robot, dashboard.server.url
    finally:
        stop.set()
        threads.close()
        dashboard.close()
        robot.close()
        dashboard.out.close()
    assert not failures, failures


def test_the_page_is_told_the_new_sensors_and_the_rgb_leds() -> None:
    with ego.Robot("sim", robot="epuck2", seed=1) as robot:
        hello = describe_robot(robot)
    assert set(NEW_SENSORS) <= set(hello["families"])
    assert {"tof", "gyro", "magnetometer"} <= {s["key"] for s in hello["series"]}
    assert hello["rgb_leds"] == [1, 3, 5, 7] and hello["led_count"] == 10
    with ego.Robot("sim", seed=1) as e_puck:
        hello = describe_robot(e_puck)
    assert not set(NEW_SENSORS) & set(hello["families"]) and hello["rgb_leds"] == []


def test_the_rgb_leds_are_drawn_in_their_colour(page: Any) -> None:
    def light_up(robot: ego.Robot) -> None:
        if not robot.tof.enabled:
            robot.tof.enable(32)
            robot.gyro.enable(32)
            robot.leds.set("led1", 0xFF8000)
            robot.leds.set("led5", 0x0040FF)
            robot.leds.set("led0", 1)

    with served_epuck2(light_up) as (robot, url):
        page.goto(url)
        page.wait_for_function("document.getElementById('link-status').textContent === 'live'")
        page.wait_for_function("document.getElementById('led-1') !== null")
        page.wait_for_function(
            "document.getElementById('led-1').getAttribute('fill') === '#ff8000'", timeout=10000
        )
        assert page.get_attribute("#led-5", "fill") == "#0040ff"
        assert page.get_attribute("#led-0", "fill") == "#ff3b30"  # a red LED stays red
        assert page.get_attribute("#led-3", "fill") == "#5a1b1b"  # an RGB LED off is dark
        for family in NEW_SENSORS:
            assert page.query_selector(f"#sensor-{family}") is not None, family
        page.wait_for_function("document.getElementById('sensor-tof').checked === true")
        assert robot.steps > 0


def test_a_recorded_e_puck2_run_reads_back_with_its_sensors(tmp_path: Path) -> None:
    done = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--robot", "epuck2", "--seed", "2",
         "--duration", "1", "--record", "run.mcap", str(CONTROLLER), "seen.json"],
        cwd=tmp_path, capture_output=True, text=True, timeout=60, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    recording = Recording.open(tmp_path / "run.mcap")
    assert recording.metadata["firmware"] == "epuck2"
    last = recording.samples[-1]
    assert last["tof"] is not None and 0 < last["tof"][0] < 8191
    assert last["gyro"] is not None and len(last["gyro"]) == 3
    assert last["magnetometer"] is None  # the controller never enabled it
    # The RGB LEDs went in as their colours (green or red, as the controller set them).
    assert last["leds"][1] in (0x00FF00, 0xFF0000) and last["leds"][1] == last["leds"][7]
