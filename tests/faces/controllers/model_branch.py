"""A controller that branches on the robot model, as shared e-puck/e-puck2 code does, and
asks more than the maximum velocity (Webots clamps it and says so)."""

from controller import Robot

robot = Robot()
max_speed = 6.28 if robot.getModel() == "GCtronic e-puck" else 7.536
print("model", robot.getModel(), flush=True)
left = robot.getDevice("left wheel motor")
right = robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
left.setVelocity(2 * max_speed)  # too fast: clamped
right.setVelocity(-2 * max_speed)
for _ in range(10):
    robot.step(32)
print("running", flush=True)
while robot.step(32) != -1:
    pass
