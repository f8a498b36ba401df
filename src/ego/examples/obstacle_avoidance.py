"""Obstacle avoidance for the e-puck, written for Webots' Python API (runs unchanged under ego).

A Braitenberg vehicle: each proximity sensor pushes the wheels away from what it sees,
and the ring LED nearest an obstacle lights up. The robot's other sensors are sampled
too, for whoever watches (ego demo's dashboard).
"""

from controller import Robot

MAX_SPEED = 6.28
CRUISE = 0.6 * MAX_SPEED
# How strongly ps0..ps7 push the left and right wheels (front sensors the most).
WEIGHTS = [
    (-1.0, 1.0),
    (-0.8, 0.8),
    (-0.4, 0.4),
    (0.0, 0.0),
    (0.0, 0.0),
    (0.4, -0.4),
    (0.8, -0.8),
    (1.0, -1.0),
]
# Which ring LED sits nearest each proximity sensor.
NEAREST_LED = [0, 1, 2, 3, 4, 5, 6, 7]

robot = Robot()
time_step = int(robot.getBasicTimeStep())

sensors = [robot.getDevice(f"ps{i}") for i in range(8)]
for sensor in sensors:
    sensor.enable(time_step)
# Sample the rest of the robot too, more slowly, so that a dashboard (ego demo's) shows it.
OTHERS = ["accelerometer", "left wheel sensor", "right wheel sensor"]
for name in OTHERS + [f"ls{i}" for i in range(8)]:
    robot.getDevice(name).enable(2 * time_step)
leds = [robot.getDevice(f"led{i}") for i in range(8)]
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_motor.setPosition(float("inf"))
right_motor.setPosition(float("inf"))
left_motor.setVelocity(0.0)
right_motor.setVelocity(0.0)

while robot.step(time_step) != -1:
    values = [sensor.getValue() for sensor in sensors]
    # Raw IR is ~70 with nothing in sight and rises steeply within a few centimetres.
    pressure = [max(0.0, (v - 80.0) / 400.0) for v in values]
    left = CRUISE + sum(p * w[0] for p, w in zip(pressure, WEIGHTS)) * MAX_SPEED
    right = CRUISE + sum(p * w[1] for p, w in zip(pressure, WEIGHTS)) * MAX_SPEED
    left_motor.setVelocity(max(-MAX_SPEED, min(MAX_SPEED, left)))
    right_motor.setVelocity(max(-MAX_SPEED, min(MAX_SPEED, right)))
    closest = max(range(8), key=lambda i: values[i])
    for i, led in enumerate(leds):
        led.set(1 if i == NEAREST_LED[closest] and values[closest] > 150 else 0)
