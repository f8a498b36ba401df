"""Line following with the ground sensors: stay on a black line drawn on a white floor.

gs0 (left), gs1 (middle) and gs2 (right) look at the floor; a darker floor reads lower.
The robot steers towards the darker side, proportionally to the difference. The ground
sensors are a module under the robot (fitted on most e-pucks); on the Overo's line the
stock firmware cannot read them (docs/guide/overo.md says how ego reads them there).
Run it on the emulator's line track with

    ego run --port sim --world line-track examples/line_following.py
"""

from controller import Robot

TIME_STEP = 32
BASE_SPEED = 2.0  # rad/s
GAIN = 4.0  # rad/s per 1000 counts of difference between gs2 and gs0
MAX_SPEED = 6.28

robot = Robot()
ground = [robot.getDevice(f"gs{i}") for i in range(3)]
for sensor in ground:
    sensor.enable(TIME_STEP)
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
for motor in (left_motor, right_motor):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)


def clamp(speed):
    return max(-MAX_SPEED, min(MAX_SPEED, speed))


while robot.step(TIME_STEP) != -1:
    gs = [sensor.getValue() for sensor in ground]
    if gs[0] != gs[0]:  # NaN: no sample yet (the first step)
        continue
    # The line under the left sensor makes gs0 low: error > 0, turn left.
    error = (gs[2] - gs[0]) / 1000.0
    left_motor.setVelocity(clamp(BASE_SPEED - GAIN * error))
    right_motor.setVelocity(clamp(BASE_SPEED + GAIN * error))
