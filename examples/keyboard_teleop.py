"""Keyboard teleoperation: drive the robot with the arrow keys.

Up and down drive forward and back, left and right turn on the spot, space stops, Q
quits. Under ``ego run`` Webots' Keyboard reads the terminal that runs it (ssh into the
Overo and run it there), or the dashboard's keys (``ego run --dashboard``). Run it with

    ego run --port sim examples/keyboard_teleop.py
"""

from controller import Keyboard, Robot

TIME_STEP = 32
SPEED = 3.0  # rad/s

robot = Robot()
keyboard = robot.getKeyboard()
keyboard.enable(TIME_STEP)
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
for motor in (left_motor, right_motor):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)

# Each key: the left and right wheel velocities it sets.
MOVES = {
    Keyboard.UP: (SPEED, SPEED),
    Keyboard.DOWN: (-SPEED, -SPEED),
    Keyboard.LEFT: (-SPEED / 2, SPEED / 2),
    Keyboard.RIGHT: (SPEED / 2, -SPEED / 2),
    ord(" "): (0.0, 0.0),
}
print("arrows drive, space stops, Q quits", flush=True)
while robot.step(TIME_STEP) != -1:
    key = keyboard.getKey()
    if key == ord("Q"):
        break
    if key in MOVES:
        left, right = MOVES[key]
        left_motor.setVelocity(left)
        right_motor.setVelocity(right)
        print(f"wheels {left:+.1f} {right:+.1f} rad/s", flush=True)
