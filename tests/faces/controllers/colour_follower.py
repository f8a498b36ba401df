"""A colour follower as e-puck courses publish it: scan Webots' 52x39 camera image with the
pixel getters, steer towards the red blob's centre, and stop when it fills the view."""

from controller import Camera, Robot

TIME_STEP = 64
robot = Robot()
camera = robot.getDevice("camera")
camera.enable(TIME_STEP)
left = robot.getDevice("left wheel motor")
right = robot.getDevice("right wheel motor")
for motor in (left, right):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)
width, height = camera.getWidth(), camera.getHeight()
print("camera", width, height, flush=True)

while robot.step(TIME_STEP) != -1:
    image = camera.getImage()
    if not image:
        continue
    count = column_sum = 0
    for y in range(height):
        for x in range(width):
            r = Camera.imageGetRed(image, width, x, y)
            g = Camera.imageGetGreen(image, width, x, y)
            b = Camera.imageGetBlue(image, width, x, y)
            if r > 120 and r > 2 * g and r > 2 * b:
                count += 1
                column_sum += x
    if count == 0:  # nothing red in view: turn on the spot to look for it
        left.setVelocity(-1.5)
        right.setVelocity(1.5)
        continue
    if count > 0.35 * width * height:  # close enough: stop in front of it
        left.setVelocity(0.0)
        right.setVelocity(0.0)
        print("arrived", flush=True)
        break
    offset = (column_sum / count - width / 2) / (width / 2)  # -1 left .. +1 right
    left.setVelocity(3.0 + 2.5 * offset)
    right.setVelocity(3.0 - 2.5 * offset)
