"""A controller for Webots' old DifferentialWheels e-puck: setSpeed in steps/s, encoders.

It sets the encoders, drives an arc, and writes what it saw as JSON to argv[1], or to
$EGO_TEST_RESULT.
"""

import json
import os
import sys

from controller import DifferentialWheels

robot = DifferentialWheels()
time_step = int(robot.getBasicTimeStep())

robot.enableEncoders(time_step)
not_yet_sampled = robot.getLeftEncoder()
front = robot.getDistanceSensor("ps0")
front.enable(time_step)
robot.setEncoders(1000, -1000)
robot.setSpeed(300, -200)

first = None
last = None
proximity = None
speeds = None
while robot.step(time_step) != -1:
    last = [robot.getLeftEncoder(), robot.getRightEncoder()]
    if first is None:
        first = last
    proximity = front.getValue()
    speeds = [robot.getLeftSpeed(), robot.getRightSpeed()]

result = {
    "not_yet_sampled": not_yet_sampled,
    "first": first,
    "last": last,
    "proximity": proximity,
    "speeds": speeds,
    "max_speed": robot.getMaxSpeed(),
    "speed_unit": robot.getSpeedUnit(),
    "encoders_period": robot.getEncodersSamplingPeriod(),
}
path = sys.argv[1] if len(sys.argv) > 1 else os.environ["EGO_TEST_RESULT"]
with open(path, "w") as out:
    json.dump(result, out)
