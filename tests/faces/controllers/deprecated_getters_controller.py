"""A Webots e-puck controller from older Webots versions: getDistanceSensor, getMotor, getLED...

It drives slowly forward with every LED on and writes what it saw as JSON to argv[1], or to
$EGO_TEST_RESULT.
"""

import json
import os
import sys

from controller import Robot

robot = Robot()
time_step = int(robot.getBasicTimeStep())

proximity = [robot.getDistanceSensor(f"ps{i}") for i in range(8)]
light = [robot.getLightSensor(f"ls{i}") for i in range(8)]
accelerometer = robot.getAccelerometer("accelerometer")
left_wheel = robot.getPositionSensor("left wheel sensor")
camera = robot.getCamera("camera")  # looked up only: the camera has its own tests
leds = [robot.getLED(f"led{i}") for i in range(10)]
left_motor = robot.getMotor("left wheel motor")
right_motor = robot.getMotor("right wheel motor")

for sensor in [*proximity, *light, accelerometer, left_wheel]:
    sensor.enable(time_step)
for led in leds:
    led.set(1)
left_motor.setPosition(float("inf"))
right_motor.setPosition(float("inf"))
left_motor.setVelocity(2.0)
right_motor.setVelocity(2.0)

start = None
seen = {}
while robot.step(time_step) != -1:
    if start is None:
        start = left_wheel.getValue()
    seen = {
        "proximity": [s.getValue() for s in proximity],
        "light": [s.getValue() for s in light],
        "accelerometer": accelerometer.getValues(),
        "left_wheel": left_wheel.getValue(),
        "leds": [led.get() for led in leds],
    }

result = {
    **seen,
    "left_wheel_start": start,
    "types": [
        type(d).__name__
        for d in (proximity[0], light[0], accelerometer, left_wheel, camera, leds[0], left_motor)
    ],
}
path = sys.argv[1] if len(sys.argv) > 1 else os.environ["EGO_TEST_RESULT"]
with open(path, "w") as out:
    json.dump(result, out)
