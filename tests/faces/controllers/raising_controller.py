"""A Webots controller with a bug: motors turning and LEDs on when it raises.

It prints "running" once it has stepped, waits for a line on stdin, then raises.
"""

import sys

from controller import Robot

robot = Robot()
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_motor.setPosition(float("inf"))
right_motor.setPosition(float("inf"))
left_motor.setVelocity(-1.5)
right_motor.setVelocity(1.5)
for i in range(10):
    robot.getDevice(f"led{i}").set(1)

robot.step(32)
print("running", flush=True)
sys.stdin.readline()
raise RuntimeError("a bug in the controller")
