"""A controller that ends with its robot still open (as Webots controllers do) stops the
wheels at exit, on an emulated robot too: the robots are closed before the emulator in
the same process ends (before this, the emulator went first, and the stop waited 3 s for
a pty that was gone, then printed "could not stop the robot's actuators")."""

from __future__ import annotations

import subprocess
import sys
import textwrap


def test_a_robot_left_open_on_the_emulator_stops_its_wheels_at_exit() -> None:
    program = textwrap.dedent("""
        import atexit
        from ego.core.robot import Robot

        robot = Robot("sim", seed=1, handle_signals=False)
        world = robot.ground_truth.world
        robot.motors.set_speed(300, -300)
        robot.step(64)
        print("driving", world.speeds, flush=True)
        # atexit runs after the hooks that end the robots and the emulator's threads.
        atexit.register(lambda: print("at exit", world.speeds, flush=True))
    """)
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                          timeout=60)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["driving (300, -300)", "at exit (0, 0)"]
    assert "could not stop" not in done.stderr, done.stderr
