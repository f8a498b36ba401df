"""A Webots-style controller for the supervised-run tests: drives, says so, then behaves
as its first argument asks.

- ``forever``: steps until it is ended from outside (SIGKILL, SIGTERM);
- ``hang``: steps a few times, then loops without stepping (a hung controller);
- ``ends``: steps ten times and returns.
"""

import os
import sys
import time

from controller import Robot

robot = Robot()
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
left.setVelocity(2.0)
right.setVelocity(-2.0)
robot.step(32)
print(f"running {os.getpid()}", flush=True)
mode = sys.argv[1]
if mode == "forever":
    while robot.step(32) != -1:
        pass
elif mode == "hang":
    for _ in range(3):
        robot.step(32)
    while True:  # stuck in its own code: no step, no heartbeat
        time.sleep(0.01)
else:
    for _ in range(10):
        robot.step(32)
