"""A line follower as e-puck courses publish it: the ground sensors steer the robot along a
black line (gs0 left, gs1 middle, gs2 right; lower is darker)."""

from controller import Robot

TIME_STEP = 32
robot = Robot()
ground = [robot.getDevice(f"gs{i}") for i in range(3)]
for sensor in ground:
    sensor.enable(TIME_STEP)
left = robot.getDevice("left wheel motor")
right = robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)
while robot.step(TIME_STEP) != -1:
    gs = [sensor.getValue() for sensor in ground]
    if gs[0] != gs[0]:  # NaN: not sampled yet
        continue
    error = (gs[2] - gs[0]) / 1000.0  # the line under the left sensor: turn left
    base = 2.0
    left.setVelocity(max(-6.28, min(6.28, base - 4.0 * error)))
    right.setVelocity(max(-6.28, min(6.28, base + 4.0 * error)))
