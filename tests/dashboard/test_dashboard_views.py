"""What the dashboard draws, looked at in a real headless Chromium: the plot's legend,
units and whole numbers (and Webots' rad/s beside steps/s under a Webots controller);
the map's floor marks drawn unlike its walls, and both paths (the odometry drifts from
the true pose, as on a real robot); a replay that shows no live badge and no STOP."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path
from typing import Any

from dashboard_support import OPEN_WORLD, LineReader, served_robot
from helpers import ego_command

import ego
from ego.app.replay import ReplayFeed
from ego.recording.reader import Recording
from ego.servers.dashboard.server import DashboardServer

LOGGER = Path(__file__).parents[1] / "faces" / "controllers" / "sensor_logger.py"


def _open(page: Any, url: str, status: str = "live") -> None:
    page.goto(url)
    page.wait_for_function(f"document.getElementById('link-status').textContent === '{status}'")
    page.wait_for_function("document.getElementById('ray-0') !== null")


def _plot(page: Any, series: str) -> dict[str, Any]:
    """Show ``series`` in the plot; its legend, y tick labels and units as drawn."""
    page.select_option("#plot-series", series)
    page.wait_for_function(
        f"document.getElementById('plot-legend').children.length > 0 && "
        f"document.getElementById('plot-series').value === '{series}'"
    )
    # A few samples more, drawn.
    seen = page.evaluate("view.sample.step")
    page.wait_for_function(f"view.sample.step >= {seen + 3} && !view.dirty")
    return {
        "legend": page.eval_on_selector_all(
            "#plot-legend li", "(li) => li.map((i) => i.textContent)"
        ),
        "ticks": json.loads(page.get_attribute("#plot", "data-y-ticks") or "[]"),
        "units": page.get_attribute("#plot", "data-units"),
    }


def _sense_and_drive(robot: ego.Robot) -> None:
    if not robot.proximity.enabled:
        robot.proximity.enable(32)
        robot.encoders.enable(32)
    robot.motors.set_speed(300, 300)


def test_the_plot_has_a_legend_units_and_whole_numbers(tmp_path: Path, page: Any) -> None:
    with served_robot(tmp_path, _sense_and_drive) as served:
        _open(page, served.url)
        page.wait_for_function("view.history.length > 10")
        proximity = _plot(page, "proximity")
        speed = _plot(page, "speed")
        encoders = _plot(page, "encoders")
        rad_shown = page.is_visible("#speed-left-rad")
    assert proximity["legend"] == [f"ps{i}" for i in range(8)]
    assert proximity["units"] == "raw counts"
    # Whole counts read as whole numbers ("53", never "53.00").
    assert proximity["ticks"] and all(re.fullmatch(r"-?\d+", t) for t in proximity["ticks"])
    assert speed["legend"] == ["left", "right"] and speed["units"] == "steps/s"
    assert encoders["legend"] == ["left", "right"] and encoders["units"] == "steps"
    assert all(re.fullmatch(r"-?\d+", t) for t in encoders["ticks"])
    assert not rad_shown  # no Webots controller here: the robot's own units only


def test_under_a_webots_controller_rad_per_s_shows_beside_steps_per_s(
    tmp_path: Path, page: Any
) -> None:
    controller = tmp_path / "spin.py"
    controller.write_text(
        "from controller import Robot\n"
        "robot = Robot()\n"
        "left, right = robot.getDevice('left wheel motor'), robot.getDevice('right wheel motor')\n"
        "for m in (left, right):\n"
        "    m.setPosition(float('inf'))\n"
        "left.setVelocity(3.0); right.setVelocity(-3.0)\n"
        "while robot.step(32) != -1:\n"
        "    pass\n"
    )
    proc = subprocess.Popen(
        [*ego_command(), "run", "--port", "sim", "--duration", "30", "--dashboard-address",
         "127.0.0.1:0", str(controller)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert proc.stderr is not None
    reader = LineReader(proc.stderr)
    try:
        url = reader.find(r"dashboard at (\S+)", timeout_s=20)
        _open(page, url)
        page.wait_for_function("document.getElementById('speed-left').textContent !== '0'")
        steps = page.inner_text("#speed-left")
        rad = page.inner_text("#speed-left-rad")
        unit = page.inner_text("#speed-unit")
        speed = _plot(page, "speed")
    finally:
        proc.kill()
        proc.wait()
        reader.close()
    assert steps == "477" and rad == "3.00"  # setVelocity(3.0): 477 steps/s, 3.00 rad/s
    assert unit == "steps/s (rad/s)"
    assert speed["units"] == "steps/s | rad/s"


def _pixel(page: Any, x_m: float, y_m: float, dx_px: float = 0.0) -> list[int]:
    """The map's colour where it draws the world's point (x, y), shifted dx_px right."""
    return list(page.evaluate(
        """([x, y, dx]) => {
            const canvas = document.getElementById('map');
            const [px, py] = mapPoint(x, y);
            const dpr = canvas.width / canvas.clientWidth;
            const d = canvas.getContext('2d').getImageData(Math.round((px + dx) * dpr),
                Math.round(py * dpr), 1, 1).data;
            return [d[0], d[1], d[2]];
        }""",
        [x_m, y_m, dx_px],
    ))  # fmt: skip


def _hold_still(robot: ego.Robot) -> None:
    robot.motors.set_speed(0, 0)


def test_the_floor_stripe_is_drawn_unlike_a_wall(tmp_path: Path, page: Any) -> None:
    with served_robot(tmp_path, _hold_still) as served:  # the default floor: a stripe at y 0.2
        _open(page, served.url)
        page.wait_for_function("view.floorImage !== null && !view.mapDirty")  # and drawn
        stripe = _pixel(page, -0.3, 0.2)
        floor = _pixel(page, -0.3, 0.1)
        wall = _pixel(page, 0.5, 0.0, dx_px=3)  # the east wall, drawn just outside the floor
        legend = page.inner_text("#map-legend")
    assert sum(stripe) < sum(floor)  # the stripe shows on the floor ...
    assert sum(stripe) > sum(wall) + 200, (stripe, wall)  # ... far lighter than a wall
    assert "floor marks" in legend and "walls" in legend


#: A wide arena: the robot drives a long curve without meeting a wall.
WIDE = OPEN_WORLD.replace("size_m = 1.0", "size_m = 3.0").replace("x_m = 0.2", "x_m = -0.8")


def _curve(robot: ego.Robot) -> None:
    if not robot.encoders.enabled:
        robot.encoders.enable(32)
    robot.motors.set_speed(700, 560)


def test_both_paths_show_and_the_odometry_drifts_from_the_true_pose(
    tmp_path: Path, page: Any
) -> None:
    with served_robot(tmp_path, _curve, world=WIDE) as served:
        _open(page, served.url)
        page.wait_for_function("view.truth.length > 60 && view.odometry.length > 60", timeout=40000)
        page.wait_for_function("view.sample.t > 7", timeout=40000)
        odometry, truth = page.evaluate("[view.odometry.at(-1), view.truth.at(-1)]")
        colours = page.evaluate(
            """() => {
                const c = document.getElementById('map');
                const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
                const dpr = c.width / c.clientWidth;
                const [lx, ly] = mapPoint(...view.hello.world.lamp).map((v) => v * dpr);
                let orange = 0, blue = 0;
                for (let i = 0; i < d.length; i += 4) {
                    const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
                    const [x, y] = [(i / 4) % c.width, Math.floor(i / 4 / c.width)];
                    if (Math.hypot(x - lx, y - ly) < 12 * dpr) continue;  // the lamp is yellow
                    if (r > 200 && r - b > 100 && g > 110 && g < 185) orange++;
                    if (b > 180 && b - r > 100) blue++;
                }
                return [orange, blue];
            }"""
        )
        legend = page.inner_text("#map-legend")
    drift_m = ((odometry[0] - truth[0]) ** 2 + (odometry[1] - truth[1]) ** 2) ** 0.5
    assert drift_m > 0.005, (odometry, truth)  # about a metre driven: centimetres apart
    assert colours[0] > 60 and colours[1] > 60, colours  # both traces on the map
    assert "odometry" in legend and "true pose" in legend


def test_a_replay_shows_no_live_badge_and_no_stop(tmp_path: Path, page: Any) -> None:
    run = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--seed", "4", "--duration", "2", "--record",
         "run.mcap", str(LOGGER), "robot.json"],
        capture_output=True, text=True, cwd=tmp_path, timeout=60,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    feed = ReplayFeed(Recording.open(tmp_path / "run.mcap"))
    with DashboardServer(feed, "127.0.0.1", 0) as server:
        feed.server = server
        feed.start()
        try:
            _open(page, server.url, status="replay")
            page.wait_for_function("document.getElementById('h-time').textContent !== '–'")
            status = page.inner_text("#link-status")
            hidden = {name: page.is_hidden(name) for name in
                      ("#stop", "#take", "#release", "#resume", "#role", "#controls")}  # fmt: skip
            bar = page.is_visible("#replay-bar")
        finally:
            feed.close()
    assert "live" not in status.lower() and status == "replay"
    assert all(hidden.values()), hidden
    assert bar
