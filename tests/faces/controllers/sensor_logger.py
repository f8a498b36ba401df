"""A controller that logs what it reads each step (to the file in its first argument) and
reacts to it: run on the robot with --record, then on the recording with --emulate, the
two logs must be the same."""

import json
import sys

from controller import Robot

robot = Robot()
proximity = [robot.getDevice(f"ps{i}") for i in range(8)]
for sensor in proximity:
    sensor.enable(32)
wheel = robot.getDevice("left wheel sensor")
wheel.enable(32)
accelerometer = robot.getDevice("accelerometer")
accelerometer.enable(64)
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
log = []
while robot.step(32) != -1:
    values = [sensor.getValue() for sensor in proximity]
    log.append([robot.getTime(), values, wheel.getValue(), accelerometer.getValues()])
    turning = max(values) > 150
    left.setVelocity(-3.0 if turning else 4.0)
    right.setVelocity(3.0 if turning else 4.0)
with open(sys.argv[1], "w") as out:
    json.dump(log, out)
print("steps", len(log))
