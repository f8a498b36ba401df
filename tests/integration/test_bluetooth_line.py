"""The obstacle-avoidance demo through Webots' firmware on its real line: 115200 baud over
Bluetooth, with the few milliseconds each way an SPP link adds (docs/protocol.md, Line)."""

from __future__ import annotations

import subprocess
from importlib import resources
from pathlib import Path

from helpers import ego_command

from firmware_sim import Emulator

#: A Bluetooth SPP link's own delay, each way (inferred: several ms per round trip).
SPP_LATENCY_S = 0.008


def test_the_avoidance_demo_runs_over_an_emulated_bluetooth_line(tmp_path: Path) -> None:
    controller = resources.files("ego.examples") / "obstacle_avoidance.py"
    with Emulator("webots", seed=2, latency_s=SPP_LATENCY_S) as emu:
        assert emu.baud == 115200
        with resources.as_file(controller) as path:
            run = subprocess.run(
                [*ego_command(), "run", "--port", emu.path, "--duration", "3", str(path)],
                cwd=tmp_path,
                capture_output=True,
                text=True,
                timeout=60,
            )
        assert run.returncode == 0, run.stderr
        world = emu.world
        assert world.distance_travelled_m > 0.05  # it drove
        assert world.speeds == (0, 0) and not any(world.leds)  # and stopped at the end
        assert emu.history and all(not r.faults for r in emu.history)
