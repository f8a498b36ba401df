"""The dashboard in a real headless Chromium, on the emulator: what the page shows follows
the world, and what the page does reaches the robot (or, for a viewer, does not)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from dashboard_support import OPEN_WORLD, served_robot
from helpers import wait_for_more, wait_until

import ego


def _open(page: Any, url: str) -> None:
    page.goto(url)
    page.wait_for_function("document.getElementById('link-status').textContent === 'live'")
    page.wait_for_function("document.getElementById('ray-0') !== null")


def _take_control(page: Any) -> None:
    page.click("#take")
    page.wait_for_function("document.getElementById('role').textContent === 'in control'")


def _ray(page: Any, index: int) -> float:
    length = page.get_attribute(f"#ray-{index}", "data-length")
    return float(length or 0)


def test_the_ray_nearest_the_wall_grows_as_the_robot_drives_up_to_it(
    tmp_path: Path, page: Any
) -> None:
    def approach(robot: ego.Robot) -> None:
        if not robot.proximity.enabled:
            robot.proximity.enable(32)
        near = robot.proximity.has_values and max(robot.proximity.values[:1]) > 2000
        robot.motors.set_speed(*((0, 0) if near else (400, 400)))

    with served_robot(tmp_path, approach) as served:
        _open(page, served.url)
        page.wait_for_function("document.getElementById('ray-0').dataset.value !== ''")
        front, back = [_ray(page, 0)], [_ray(page, 3)]
        assert wait_until(lambda: served.world.speeds == (0, 0) and served.robot.steps > 10, 15)
        # The page's next samples, taken with the robot at the wall, drawn.
        stopped_at = served.robot.steps
        page.wait_for_function(f"view.sample.step >= {stopped_at + 3} && !view.dirty")
        front.append(_ray(page, 0))
        back.append(_ray(page, 3))
        x_end = served.world.snapshot().x_m
    assert x_end > 0.35  # it did drive up to the east wall (at 0.5 m)
    assert front[-1] > front[0] + 20, front  # the front ray grew on the page
    assert abs(back[-1] - back[0]) < 10, back  # the back one, facing nothing, did not


def test_an_arrow_key_drives_the_robot_in_the_world(tmp_path: Path, page: Any) -> None:
    def hold_still(robot: ego.Robot) -> None:
        robot.motors.set_speed(0, 0)  # the controller itself never moves it

    with served_robot(tmp_path, hold_still) as served:
        _open(page, served.url)
        _take_control(page)
        start = served.world.snapshot().x_m
        page.keyboard.down("ArrowUp")
        moved = wait_until(lambda: served.world.snapshot().x_m > start + 0.03, 5)
        page.keyboard.up("ArrowUp")
        assert moved, served.world.snapshot()
        # Released: the drive lapses and the controller's (0, 0) holds again.
        assert wait_until(lambda: served.world.speeds == (0, 0), 2)


def test_the_stop_button_stops_the_robot_whatever_the_controller_asks(
    tmp_path: Path, page: Any
) -> None:
    def drive_on(robot: ego.Robot) -> None:
        robot.motors.set_speed(500, 500)

    with served_robot(tmp_path, drive_on) as served:
        _open(page, served.url)
        _take_control(page)
        assert wait_until(lambda: served.world.speeds == (500, 500), 3)
        page.click("#stop")
        assert wait_until(lambda: served.world.speeds == (0, 0), 0.5)
        x = served.world.snapshot().x_m
        # The controller keeps asking for 500: the stop holds over 15 of its steps.
        assert wait_for_more(lambda: served.robot.steps, 15), "the controller stopped stepping"
        assert served.world.speeds == (0, 0)
        assert abs(served.world.snapshot().x_m - x) < 0.002
        page.click("#resume")
        assert wait_until(lambda: served.world.speeds == (500, 500), 2)


def test_a_viewer_without_control_cannot_drive_or_stop(
    tmp_path: Path, page: Any, browser: Any
) -> None:
    speeds = [(0, 0)]

    def obey(robot: ego.Robot) -> None:
        robot.motors.set_speed(*speeds[0])

    with served_robot(tmp_path, obey) as served:
        _open(page, served.url)
        _take_control(page)
        other = browser.new_context(bypass_csp=True).new_page()
        try:
            _open(other, served.url)
            other.wait_for_function("document.getElementById('take').disabled === true")
            assert other.is_disabled("#stop")
            start = served.world.snapshot().x_m
            # The key held while the page's 100 ms drive repeat has fired 8 times (a
            # counter beside it) and the controller has stepped 25 times.
            other.evaluate("window.ticks = 0; setInterval(() => { window.ticks += 1; }, 100)")
            other.keyboard.down("ArrowUp")
            other.wait_for_function("window.ticks >= 8")
            assert wait_for_more(lambda: served.robot.steps, 25)
            other.keyboard.up("ArrowUp")
            # Around the page's buttons: its own socket, straight to the server.
            other.evaluate("send({type: 'drive', left: 800, right: 800})")
            toast = "document.getElementById('toast').textContent"
            other.wait_for_function(f"{toast}.includes('only views')")
            other.evaluate("send({type: 'stop'})")
            assert wait_for_more(lambda: served.robot.steps, 15)  # steps a drive would move
            assert abs(served.world.snapshot().x_m - start) < 0.001  # never moved
            speeds[0] = (300, 300)  # the controller still drives: no stop was latched
            assert wait_until(lambda: served.world.speeds == (300, 300), 2)
        finally:
            other.context.close()


def test_the_camera_image_on_the_page_changes_as_the_robot_turns(
    tmp_path: Path, page: Any
) -> None:
    def turn(robot: ego.Robot) -> None:
        if not robot.camera.sampling_period:
            robot.camera.enable(64)
        robot.motors.set_speed(-300, 300)

    world = OPEN_WORLD_WITH_BOXES
    assert world != OPEN_WORLD
    with served_robot(tmp_path, turn, world=world) as served:
        _open(page, served.url)
        page.wait_for_function("Number(document.getElementById('camera').dataset.frames || 0) > 2")
        camera = served.robot.camera
        # The page shows the frames at the controller's size (once a frame has decoded).
        page.wait_for_function(
            f"document.getElementById('camera').naturalWidth === {camera.width} && "
            f"document.getElementById('camera').naturalHeight === {camera.height}"
        )
        first = page.locator("#camera").screenshot()
        # The robot turns a good way, then the page shows frames taken since.
        heading = served.world.snapshot().theta_rad

        def turned() -> float:
            return abs(math.remainder(served.world.snapshot().theta_rad - heading, math.tau))

        assert wait_until(lambda: turned() > 0.5, 10)
        frames = int(page.get_attribute("#camera", "data-frames") or 0)
        page.wait_for_function(
            f"Number(document.getElementById('camera').dataset.frames) >= {frames + 2}"
        )
        second = page.locator("#camera").screenshot()
    assert first != second


#: Three coloured boxes around the robot: turning, the camera sees them pass.
OPEN_WORLD_WITH_BOXES = """
[robot]
x_m = 0.0
y_m = 0.0
heading_deg = 0
[[box]]
x_m = 0.25
y_m = 0.0
rgb = [210, 30, 30]
[[box]]
x_m = 0.0
y_m = 0.25
rgb = [30, 160, 40]
"""


def test_a_teleop_controller_runs_unchanged_from_the_browsers_keys(
    tmp_path: Path, page: Any
) -> None:
    """The page's keys reach the controller's Webots Keyboard: arrows drive it, Q ends it."""
    import re
    import select
    import subprocess

    from helpers import ego_command

    teleop = Path(__file__).parents[1] / "faces" / "controllers" / "keyboard_teleop.py"
    proc = subprocess.Popen(
        [*ego_command(), "run", "--port", "sim", "--dashboard-address", "127.0.0.1:0", str(teleop)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
    )  # fmt: skip
    try:
        assert proc.stderr is not None
        url = ""
        while not url and select.select([proc.stderr], [], [], 20)[0]:
            line = proc.stderr.readline()
            if not line:  # the command ended: say why rather than wait on its end
                break
            match = re.search(r"dashboard at (\S+)", line)
            url = match.group(1) if match else ""
        assert url, "no dashboard URL"
        _open(page, url)
        _take_control(page)
        page.wait_for_function("!document.getElementById('keyboard-note').hidden")
        page.keyboard.press("ArrowUp")
        page.wait_for_function("Number(document.getElementById('speed-left').textContent) > 400")
        page.keyboard.press("q")
        out, err = proc.communicate(timeout=20)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert "key 315" in out.splitlines() and "key 81" in out.splitlines()
