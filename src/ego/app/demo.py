"""``ego demo``: an obstacle-avoiding Webots controller drives the emulated robot, shown live."""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field
from importlib import resources
from typing import Any, TextIO

from ego.app.observers import observe_run
from ego.app.runner import run_controller
from ego.controller.camera import WEBOTS_CAMERA_SIZE
from ego.core.ports import default_baud
from ego.core.robot import Robot
from ego.faces import runtime
from ego.seam.profile import Firmware

__all__ = ["DemoReport", "run_demo", "run_pipuck_demo"]

_BARS = " ▁▂▃▄▅▆▇█"
#: How often the demo's camera takes a frame for the dashboard (ms).
CAMERA_PERIOD_MS = 64


def _bar(value: int) -> str:
    """A proximity value as a one-character gauge (log scale: 60..4095)."""
    level = (math.log(max(value, 60)) - math.log(60)) / (math.log(4095) - math.log(60))
    return _BARS[min(len(_BARS) - 1, max(0, round(level * (len(_BARS) - 1))))]


@dataclass
class DemoReport:
    steps: int = 0
    overruns: int = 0
    controller_time_s: float = 0.0
    wall_time_s: float = 0.0
    distance_m: float = 0.0
    closest_approach_mm: float = math.inf
    robots: list[Robot] = field(default_factory=list)


class _Progress:
    """Prints the sensor ring and wheel speeds a few times a second."""

    def __init__(
        self, out: TextIO, report: DemoReport, every_s: float = 0.25,
        camera_size: tuple[int, int] | None = None,
    ) -> None:  # fmt: skip
        self.camera_size = camera_size
        self.out = out
        self.report = report
        self.every_s = every_s
        self.next_s = 0.0
        self.tty = out.isatty()

    def attach(self, robot: Robot) -> None:
        self.report.robots.append(robot)
        robot.add_step_listener(self.on_step)
        if self.camera_size is not None:  # for the dashboard: the emulator's camera
            robot.camera.set_size(*self.camera_size)
            robot.camera.enable(CAMERA_PERIOD_MS)

    def on_step(self, robot: Robot) -> None:
        if robot.time_s < self.next_s:
            return
        self.next_s = robot.time_s + (self.every_s if self.tty else 1.0)
        ring = (
            "".join(_bar(v) for v in robot.proximity.values) if robot.proximity.has_values else "-"
        )
        left, right = robot.motors.speed
        truth = robot.ground_truth
        world = truth.true_world if truth is not None else None
        clearance = f"  closest {world.closest_approach_m * 1000:5.1f} mm" if world else ""
        line = (
            f"t={robot.time_s:5.1f} s  ps0-7 [{ring}]  speed L {left:+5d} R {right:+5d} steps/s"
            f"  steps {robot.steps:5d}  overruns {robot.overruns}{clearance}"
        )
        self.out.write(("\r" + line) if self.tty else (line + "\n"))
        self.out.flush()


def run_demo(
    duration_s: float = 20.0,
    firmware: str = "webots",
    seed: int | None = 1,
    out: TextIO = sys.stdout,
    world: str | None = None,
    dashboard: str | None = None,
    record: str | None = None,
    robot: str | None = None,
) -> DemoReport:
    """Run the bundled obstacle-avoidance controller on the built-in emulator, with a
    live dashboard at ``dashboard`` (HOST:PORT) and a recording to ``record`` if asked;
    ``robot`` "epuck2" emulates an e-puck2 on its USB link instead of an e-puck."""
    report = DemoReport()
    # With a dashboard, the emulated camera is shown at Webots' e-puck size.
    progress = _Progress(out, report, camera_size=WEBOTS_CAMERA_SIZE if dashboard else None)
    options = runtime.RunOptions(
        port="sim",
        firmware=None if robot == "epuck2" else firmware,  # the e-puck2 is found by its V
        duration_s=duration_s,
        seed=seed,
        world=world,
        robot=robot,
        on_robot=[progress.attach],
    )
    if robot == "epuck2":
        link = "its asercom v2 over a USB pty"
    else:
        link = f"{firmware} firmware, {default_baud('sim', Firmware.choose(firmware))} baud pty"
    out.write(
        f"ego demo: a Webots obstacle-avoidance controller drives the emulated "
        f"{'e-puck2' if robot == 'epuck2' else 'e-puck'} ({link}) for {duration_s:g} s\n"
    )
    controller = resources.files("ego.examples") / "obstacle_avoidance.py"
    started = time.monotonic()
    with resources.as_file(controller) as path, observe_run(
        options, dashboard=dashboard, record=record, out=out
    ):
        run_controller(path, options)
    report.wall_time_s = time.monotonic() - started
    if report.robots:
        driven = report.robots[0]
        report.steps = driven.steps
        report.overruns = driven.overruns
        report.controller_time_s = driven.time_s
        truth = driven.ground_truth
        true_world = truth.true_world if truth is not None else None
        if true_world is not None:
            report.distance_m = true_world.distance_travelled_m
            report.closest_approach_mm = true_world.closest_approach_m * 1000
    if progress.tty:
        out.write("\n")
    out.write(
        "summary: "
        f"{report.steps} steps in {report.controller_time_s:.1f} s of controller time "
        f"({report.wall_time_s:.1f} s wall), {report.overruns} overruns, "
        f"travelled {report.distance_m:.2f} m, closest approach to a wall or block "
        f"{report.closest_approach_mm:.1f} mm; motors stopped, LEDs off\n"
    )
    return report


def run_pipuck_demo(
    duration_s: float = 20.0,
    robot: str | None = None,
    seed: int | None = 1,
    world: str | None = None,
    dashboard: str | None = None,
    out: TextIO = sys.stdout,
) -> int:
    """The same controller on an emulated Pi-puck (``robot`` "epuck2" by default, or
    "epuck"): a child ``ego run --port pipuck`` whose environment reaches the emulator's
    I2C buses through its shim, as a real Pi's ``/dev/i2c-N``; its exit status."""
    import subprocess

    from ego.core.registry import find_backend

    backend: Any = find_backend("sim")  # the emulator's bridge; ego never imports it
    which = robot or "epuck2"
    out.write(f"ego demo: a Webots obstacle-avoidance controller drives an emulated {which} "
              f"on a Pi-puck, over its I2C bus, for {duration_s:g} s\n")  # fmt: skip
    out.flush()
    controller = resources.files("ego.examples") / "obstacle_avoidance.py"
    command = [sys.executable, "-m", "ego", "run", "--port", "pipuck", "--robot", which,
               "--duration", f"{duration_s:g}"]  # fmt: skip
    if dashboard is not None:
        command += ["--dashboard-address", dashboard]
    with resources.as_file(controller) as path, backend.pipuck_environment(
        robot, seed, world
    ) as environment:
        status = subprocess.call([*command, str(path)], env=environment)
    if status == 0:
        out.write("summary: the controller ran its time on the Pi-puck; motors stopped, "
                  "LEDs off\n")  # fmt: skip
    return int(status)

