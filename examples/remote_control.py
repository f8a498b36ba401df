"""Remote control from a PC: drive a robot that ``ego serve`` serves, with plain ``ego``.

On the robot (the Overo), once:

    ego secret --out ~/.ego-secret          # copy this file to the PC too
    ego serve --listen tcp://0.0.0.0:4242 --secret-file ~/.ego-secret

On the PC:

    EGO_SECRET_FILE=~/.ego-secret python examples/remote_control.py tcp://epuck:4242

The robot drives a square (four sides, four quarter turns, by its wheel encoders),
printing its proximity sensors at every corner. The link is authenticated with the
shared secret both ways; if the PC dies or the network drops, the server stops the
robot within half a second.
"""

import sys

import ego

URL = sys.argv[1] if len(sys.argv) > 1 else "tcp://127.0.0.1:4242"
TIME_STEP = 32  # ms
SPEED = 600  # steps/s; 1000 steps are one wheel turn
SIDE_STEPS = 1000  # one wheel turn: 12.8 cm
TURN_STEPS = 323  # a quarter turn on the spot (wheels 53 mm apart, 41 mm across)


def drive(robot, left, right, steps):
    """Run the wheels at ``left``/``right`` steps/s until they have turned ``steps``,
    slowing down over the last 100 steps so as not to overshoot."""
    start = robot.encoders.values
    while robot.step(TIME_STEP) != -1:
        done = min(abs(now - then) for now, then in zip(robot.encoders.values, start, strict=True))
        remaining = steps - done
        if remaining <= 0:
            break
        scale = max(0.15, min(1.0, remaining / 100))
        robot.motors.set_speed(round(left * scale), round(right * scale))
    robot.motors.set_speed(0, 0)
    robot.step(TIME_STEP)


# The secret comes from EGO_SECRET_FILE (or EGO_SECRET); secret=... passes it directly.
with ego.Robot(URL) as robot:
    print(f"connected to {URL}: {robot.channel.info.firmware} firmware", flush=True)
    robot.encoders.enable(TIME_STEP)
    robot.proximity.enable(TIME_STEP)
    robot.step(TIME_STEP)
    for corner in range(4):
        drive(robot, SPEED, SPEED, SIDE_STEPS)
        drive(robot, -SPEED, SPEED, TURN_STEPS)
        print(f"corner {corner + 1}: proximity {robot.proximity.values}", flush=True)
    print("encoders", *robot.encoders.values, flush=True)
