"""Obstacle avoidance (8 IR, 2 motors, 64 ms steps) for exactly $EGO_BENCH_STEPS steps:
the plain serial controller of the board benchmark (count.sh), run by ``ego run``."""

import os

from controller import Robot

TIME_STEP = 64
NEAR = 80.0
robot = Robot()
sensors = [robot.getDevice(f"ps{i}") for i in range(8)]
for sensor in sensors:
    sensor.enable(TIME_STEP)
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)
for _ in range(int(os.environ["EGO_BENCH_STEPS"])):
    if robot.step(TIME_STEP) == -1:
        break
    ps = [sensor.getValue() for sensor in sensors]
    turn = 3.14 if max(ps[5:]) > NEAR else -3.14 if max(ps[:3]) > NEAR else 0.0
    left.setVelocity(3.14 if turn <= 0 else -3.14)
    right.setVelocity(3.14 if turn >= 0 else -3.14)
if os.environ.get("EGO_BENCH_RSS"):  # count.sh's memory pass: the guest's resident pages
    import sys

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from guest_memory import guest_rss_kb

    parent = guest_rss_kb(str(os.getppid())) if os.environ.get("EGO_BENCH_PARENT") else 0
    print(f"rss_kb {guest_rss_kb()} parent_kb {parent}", flush=True)
