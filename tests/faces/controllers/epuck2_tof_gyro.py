"""A Webots e-puck2 controller, written as Webots' own e-puck2 samples are.

It cruises until the time-of-flight sensor sees something within 10 cm, then turns on
the spot until the way is clear; the four RGB LEDs show green while cruising and red
while turning, and the gyro measures the turn. It writes what it saw as JSON to argv[1]
(or $EGO_TEST_RESULT) once Webots (here ``ego run``) ends the run.
"""

import json
import os
import sys

from controller import Robot

TURN_BELOW = 100.0  # the tof's value (about mm) below which the robot turns
GREEN = 0x00FF00
RED = 0xFF0000

robot = Robot()
timestep = int(robot.getBasicTimeStep())

tof = robot.getDevice("tof")
tof.enable(timestep)
gyro = robot.getDevice("gyro")
gyro.enable(timestep)
rgb_leds = [robot.getDevice(name) for name in ("led1", "led3", "led5", "led7")]
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_motor.setPosition(float("inf"))
right_motor.setPosition(float("inf"))
max_speed = left_motor.getMaxVelocity()

seen = {"tof": [], "gyro_z": [], "turning_steps": 0, "colours": []}
while robot.step(timestep) != -1:
    distance = tof.getValue()
    turn_rate = gyro.getValues()[2]
    if distance < TURN_BELOW:
        left_motor.setVelocity(-0.3 * max_speed)
        right_motor.setVelocity(0.3 * max_speed)
        colour = RED
        seen["turning_steps"] += 1
    else:
        left_motor.setVelocity(0.6 * max_speed)
        right_motor.setVelocity(0.6 * max_speed)
        colour = GREEN
    for led in rgb_leds:
        led.set(colour)
    seen["tof"].append(distance)
    seen["gyro_z"].append(turn_rate)
    seen["colours"].append(rgb_leds[0].get())

seen["lookup_table"] = tof.getLookupTable()
seen["aperture"] = tof.getAperture()
seen["max_velocity"] = max_speed
seen["gyro_lookup_table"] = gyro.getLookupTable()
path = sys.argv[1] if len(sys.argv) > 1 else os.environ["EGO_TEST_RESULT"]
with open(path, "w") as out:
    json.dump(seen, out)
