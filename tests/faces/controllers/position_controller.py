"""Webots position control: setPosition(2 pi) with setVelocity(3) turns the left wheel once.

It waits until the wheel has settled on the target and writes the wheel's final angle (rad)
as JSON to argv[1], or to $EGO_TEST_RESULT.
"""

import json
import math
import os
import sys

from controller import Robot

robot = Robot()
time_step = int(robot.getBasicTimeStep())
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_wheel = robot.getDevice("left wheel sensor")
left_wheel.enable(time_step)

target = 2 * math.pi
left_motor.setPosition(target)
left_motor.setVelocity(3.0)
right_motor.setPosition(float("inf"))
right_motor.setVelocity(0.0)

settled = 0
angle = float("nan")
while robot.step(time_step) != -1:
    angle = left_wheel.getValue()
    settled = settled + 1 if abs(angle - target) < 0.01 else 0
    if settled == 3:
        break

path = sys.argv[1] if len(sys.argv) > 1 else os.environ["EGO_TEST_RESULT"]
with open(path, "w") as out:
    json.dump({"angle": angle, "settled": settled == 3, "time": robot.getTime()}, out)
