"""A plain ego script (no ``ego run``): ``with ego.Robot(port)``, looping until killed.

Usage: python plain_robot_script.py PORT. It prints "running" once it has stepped.
"""

import sys

import ego

with ego.Robot(sys.argv[1], handle_signals=True) as robot:
    robot.motors.set_speed(300, -300)
    for led in range(10):
        robot.leds.set(led, 1)
    robot.proximity.enable(32)
    robot.step(32)
    print("running", flush=True)
    while robot.step(32) != -1:
        pass
