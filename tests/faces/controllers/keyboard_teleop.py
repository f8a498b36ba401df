"""A teleoperation controller as published for the e-puck: arrows drive, S stops.

It prints each key it gets, and ends on Q.
"""

from controller import Keyboard, Robot

robot = Robot()
keyboard = robot.getKeyboard()
keyboard.enable(32)
left = robot.getDevice("left wheel motor")
right = robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)
print("ready", flush=True)
while robot.step(32) != -1:
    key = keyboard.getKey()
    if key == -1:
        continue
    print("key", key, flush=True)
    if key == Keyboard.UP:
        left.setVelocity(3.0)
        right.setVelocity(3.0)
    elif key == Keyboard.LEFT:
        left.setVelocity(-2.0)
        right.setVelocity(2.0)
    elif key == ord("S"):
        left.setVelocity(0.0)
        right.setVelocity(0.0)
    elif key == ord("Q"):
        break
