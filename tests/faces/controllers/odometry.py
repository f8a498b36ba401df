"""An odometry script as e-puck courses publish it: integrate the wheel sensors into a pose.

Drives an arc for 2 s, then prints the estimated displacement (x, y in m, theta in rad).
"""

import math

from controller import Robot

WHEEL_RADIUS = 0.0205
AXLE_LENGTH = 0.052
TIME_STEP = 32

robot = Robot()
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_sensor = left_motor.getPositionSensor()
right_sensor = right_motor.getPositionSensor()
left_sensor.enable(TIME_STEP)
right_sensor.enable(TIME_STEP)
for motor in (left_motor, right_motor):
    motor.setPosition(float("inf"))
left_motor.setVelocity(2.0)
right_motor.setVelocity(3.0)

x = y = theta = 0.0
last = None
while robot.step(TIME_STEP) != -1 and robot.getTime() < 2.0:
    now = (left_sensor.getValue(), right_sensor.getValue())
    if last is not None and not math.isnan(now[0]):
        dl = (now[0] - last[0]) * WHEEL_RADIUS
        dr = (now[1] - last[1]) * WHEEL_RADIUS
        theta += (dr - dl) / AXLE_LENGTH
        x += (dl + dr) / 2 * math.cos(theta)
        y += (dl + dr) / 2 * math.sin(theta)
    if not math.isnan(now[0]):
        last = now
left_motor.setVelocity(0.0)
right_motor.setVelocity(0.0)
robot.step(TIME_STEP)
print(f"odometry {x:.4f} {y:.4f} {theta:.4f}", flush=True)
