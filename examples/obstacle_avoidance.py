"""Obstacle avoidance: Webots' classic e-puck controller, unchanged on the real robot.

Drive forward; when an obstacle shows on the front-left proximity sensors, turn right,
and on the front-right ones, turn left. Run it with

    ego run --port sim examples/obstacle_avoidance.py      # on the emulator
    ego run examples/obstacle_avoidance.py                 # on the Overo (/dev/ttyS0)
    ego run --port /dev/rfcomm0 examples/obstacle_avoidance.py   # over Bluetooth

or open it as the controller of an E-puck in Webots.
"""

from controller import Robot

TIME_STEP = 64
MAX_SPEED = 6.28  # rad/s, the e-puck's wheel limit
# Raw IR rises above ~80 when something is a few centimetres away (Webots' e-puck model).
NEAR = 80.0

robot = Robot()
sensors = [robot.getDevice(f"ps{i}") for i in range(8)]
for sensor in sensors:
    sensor.enable(TIME_STEP)
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
for motor in (left_motor, right_motor):
    motor.setPosition(float("inf"))  # velocity control
    motor.setVelocity(0.0)

while robot.step(TIME_STEP) != -1:
    ps = [sensor.getValue() for sensor in sensors]
    # ps0, ps1, ps2 look front-right to right; ps5, ps6, ps7 left to front-left.
    right_obstacle = ps[0] > NEAR or ps[1] > NEAR or ps[2] > NEAR
    left_obstacle = ps[5] > NEAR or ps[6] > NEAR or ps[7] > NEAR
    left_speed = right_speed = 0.5 * MAX_SPEED
    if left_obstacle:
        left_speed, right_speed = 0.5 * MAX_SPEED, -0.5 * MAX_SPEED  # turn right
    elif right_obstacle:
        left_speed, right_speed = -0.5 * MAX_SPEED, 0.5 * MAX_SPEED  # turn left
    left_motor.setVelocity(left_speed)
    right_motor.setVelocity(right_speed)
