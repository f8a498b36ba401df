"""A Webots e-puck controller in today's API: getDevice, Motor velocity control, sensors.

It spins in place (left wheel forward, right wheel backward), reads every sensor each step
and writes what it saw as JSON to argv[1], or to $EGO_TEST_RESULT.
"""

import json
import os
import sys

from controller import DistanceSensor, Motor, Robot

robot = Robot()
time_step = int(robot.getBasicTimeStep())

proximity = [robot.getDevice(f"ps{i}") for i in range(8)]
light = [robot.getDevice(f"ls{i}") for i in range(8)]
floor = [robot.getDevice(f"gs{i}") for i in range(3)]
accelerometer = robot.getDevice("accelerometer")
wheels = [robot.getDevice("left wheel sensor"), robot.getDevice("right wheel sensor")]
for sensor in [*proximity, *light, *floor, accelerometer, *wheels]:
    sensor.enable(time_step)
not_yet_sampled = proximity[0].getValue()

left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_motor.setPosition(float("inf"))
right_motor.setPosition(float("inf"))
left_motor.setVelocity(3.0)
right_motor.setVelocity(-3.0)
led = robot.getDevice("led0")
led.set(1)

start = None
seen = {}
steps = 0
while robot.step(time_step) != -1:
    steps += 1
    angles = [w.getValue() for w in wheels]
    if start is None:
        start = angles
    seen = {
        "proximity": [s.getValue() for s in proximity],
        "light": [s.getValue() for s in light],
        "floor": [s.getValue() for s in floor],
        "accelerometer": accelerometer.getValues(),
        "wheels": angles,
        "time": robot.getTime(),
        "led": led.get(),
    }

result = {
    **seen,
    "wheels_start": start,
    "steps": steps,
    "not_yet_sampled": not_yet_sampled,
    "classes": [cls.__module__ for cls in (Robot, Motor, DistanceSensor)],
    "types_match": isinstance(proximity[0], DistanceSensor) and isinstance(left_motor, Motor),
    "basic_time_step": robot.getBasicTimeStep(),
    "sampling_period": proximity[0].getSamplingPeriod(),
    "name": robot.getName(),
    "mode": robot.getMode(),
    "velocities": [left_motor.getVelocity(), right_motor.getVelocity()],
}
path = sys.argv[1] if len(sys.argv) > 1 else os.environ["EGO_TEST_RESULT"]
with open(path, "w") as out:
    json.dump(result, out)
