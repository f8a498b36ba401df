"""A Webots e-puck controller for an e-puck1: Braitenberg-style avoidance on the eight IR
sensors, the ring LEDs chasing, the body LED on; what it read goes to argv[1] as JSON."""

import json
import sys

from controller import Robot

robot = Robot()
timestep = int(robot.getBasicTimeStep())
proximity = [robot.getDevice(f"ps{i}") for i in range(8)]
light = [robot.getDevice(f"ls{i}") for i in range(8)]
for sensor in (*proximity, *light):
    sensor.enable(timestep)
leds = [robot.getDevice(f"led{i}") for i in range(10)]
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_sensor = robot.getDevice("left wheel sensor")
left_sensor.enable(timestep)
for motor in (left_motor, right_motor):
    motor.setPosition(float("inf"))
max_speed = left_motor.getMaxVelocity()

seen = {"ps": [], "ls": [], "left_rad": [], "steps": 0}
while robot.step(timestep) != -1:
    values = [s.getValue() for s in proximity]
    right_obstacle = max(values[0], values[1], values[2]) > 200
    left_obstacle = max(values[5], values[6], values[7]) > 200
    left, right = 0.5 * max_speed, 0.5 * max_speed
    if right_obstacle:
        left, right = -0.5 * max_speed, 0.5 * max_speed
    elif left_obstacle:
        left, right = 0.5 * max_speed, -0.5 * max_speed
    left_motor.setVelocity(left)
    right_motor.setVelocity(right)
    for i in range(8):
        leds[i].set(1 if i == seen["steps"] % 8 else 0)
    leds[8].set(1)
    seen["ps"].append(values)
    seen["ls"].append([s.getValue() for s in light])
    seen["left_rad"].append(left_sensor.getValue())
    seen["steps"] += 1

with open(sys.argv[1], "w") as out:
    json.dump(seen, out)
