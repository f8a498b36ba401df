"""A Webots controller that never ends by itself: motors turning, every LED on.

It prints "running" once it has stepped, then loops until it is killed.
"""

from controller import Robot

robot = Robot()
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_motor.setPosition(float("inf"))
right_motor.setPosition(float("inf"))
left_motor.setVelocity(2.0)
right_motor.setVelocity(-2.0)
for i in range(10):
    robot.getDevice(f"led{i}").set(1)
ps0 = robot.getDevice("ps0")
ps0.enable(32)

robot.step(32)
print("running", flush=True)
while robot.step(32) != -1:
    pass
