"""A controller that ends with its e-puck2 still open over WiFi (Webots controllers never
close theirs) exits, and the robot stands still: before this, the connection's reader
thread kept Python waiting at exit for ever, and the wheels kept their last speeds."""

from __future__ import annotations

import subprocess
import sys
import textwrap

from helpers import wait_until

from firmware_sim.epuck2.emulator import Epuck2Emulator


def test_a_controller_that_leaves_its_e_puck2_open_exits_and_stops_it(
    wifi: Epuck2Emulator, url: str
) -> None:
    program = textwrap.dedent(f"""
        import ego

        robot = ego.Robot({url!r}, handle_signals=False)
        robot.motors.set_speed(400, 400)
        robot.step(32)
        print("driving", flush=True)
    """)
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                          timeout=60)  # fmt: skip
    assert (done.returncode, done.stdout) == (0, "driving\n"), done.stderr
    assert wait_until(lambda: wifi.world.speeds == (0, 0)), wifi.world.speeds
