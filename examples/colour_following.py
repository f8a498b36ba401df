"""Colour following with the camera: find the red object, turn towards it, drive up to it.

Each step reads the camera's BGRA image (Webots' format: 52x39 on the e-puck unless the
world says otherwise), marks the pixels that are clearly red, and steers towards their
centre; with nothing red in view it turns on the spot to look; when red fills a third of
the view it stops. NumPy does the per-pixel work (a Python loop over every pixel is too
slow on the Overo's ARM). Run it with

    ego run --port sim --world examples/red_box.toml examples/colour_following.py
"""

import numpy as np
from controller import Robot

TIME_STEP = 64
CRUISE = 3.0  # rad/s
STEER = 2.5  # rad/s at the image's edge
SEARCH = 1.5  # rad/s, turning on the spot
ARRIVED = 0.35  # stop when this share of the image is red

robot = Robot()
camera = robot.getDevice("camera")
camera.enable(TIME_STEP)
width, height = camera.getWidth(), camera.getHeight()
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
for motor in (left_motor, right_motor):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)
print(f"camera {width}x{height}", flush=True)

while robot.step(TIME_STEP) != -1:
    image = camera.getImage()
    if not image:
        continue  # no frame yet
    bgra = np.frombuffer(image, np.uint8).reshape(height, width, 4).astype(np.int16)
    blue, green, red = bgra[:, :, 0], bgra[:, :, 1], bgra[:, :, 2]
    mask = (red > 120) & (red > 2 * green) & (red > 2 * blue)
    share = mask.mean()
    if share == 0:  # nothing red in view: look for it
        left_motor.setVelocity(-SEARCH)
        right_motor.setVelocity(SEARCH)
        continue
    if share > ARRIVED:
        left_motor.setVelocity(0.0)
        right_motor.setVelocity(0.0)
        print("arrived", flush=True)
        break
    columns = np.nonzero(mask)[1]
    offset = (columns.mean() - width / 2) / (width / 2)  # -1 (left) .. +1 (right)
    left_motor.setVelocity(CRUISE + STEER * offset)
    right_motor.setVelocity(CRUISE - STEER * offset)
