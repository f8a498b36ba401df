"""A Webots e-puck2 controller in the style of Webots' own e-puck2 samples: it cruises
until the ToF or the front IR sensors see something, then turns on the spot; the RGB
LEDs show green while cruising and red while turning; the gyro measures the turn and the
ground sensors watch the floor. It writes what it saw as JSON to argv[1] once the run
ends (``ego run --duration``), and plays one melody when it first turns.
"""

import json
import sys

from controller import Robot

TURN_BELOW = 100.0
GREEN = 0x00FF00
RED = 0xFF0000

robot = Robot()
timestep = int(robot.getBasicTimeStep())

tof = robot.getDevice("tof")
tof.enable(timestep)
gyro = robot.getDevice("gyro")
gyro.enable(timestep)
ground = [robot.getDevice(f"gs{i}") for i in range(3)]
for sensor in ground:
    sensor.enable(timestep)
proximity = [robot.getDevice(f"ps{i}") for i in range(8)]
for sensor in proximity:
    sensor.enable(timestep)
accelerometer = robot.getDevice("accelerometer")
accelerometer.enable(timestep)
rgb_leds = [robot.getDevice(name) for name in ("led1", "led3", "led5", "led7")]
red_led = robot.getDevice("led0")
speaker = robot.getDevice("speaker")
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
left_motor.setPosition(float("inf"))
right_motor.setPosition(float("inf"))
max_speed = left_motor.getMaxVelocity()

seen = {"tof": [], "gyro_z": [], "ground": [], "ps0": [], "acc_z": [], "turning_steps": 0,
        "colours": [], "played": 0}
while robot.step(timestep) != -1:
    distance = tof.getValue()
    front = max(proximity[0].getValue(), proximity[7].getValue())
    if distance < TURN_BELOW or front > 200:
        left_motor.setVelocity(-0.3 * max_speed)
        right_motor.setVelocity(0.3 * max_speed)
        colour = RED
        if seen["turning_steps"] == 0:
            speaker.playSound(speaker, speaker, "sounds/mario.wav", 1.0, 1.0, 0.0, False)
            seen["played"] += 1
        seen["turning_steps"] += 1
    else:
        left_motor.setVelocity(0.6 * max_speed)
        right_motor.setVelocity(0.6 * max_speed)
        colour = GREEN
    for led in rgb_leds:
        led.set(colour)
    red_led.set(1)
    seen["tof"].append(distance)
    seen["gyro_z"].append(gyro.getValues()[2])
    seen["ground"].append([s.getValue() for s in ground])
    seen["ps0"].append(proximity[0].getValue())
    seen["acc_z"].append(accelerometer.getValues()[2])
    seen["colours"].append(rgb_leds[0].get())

seen["max_velocity"] = max_speed
with open(sys.argv[1], "w") as out:
    json.dump(seen, out)
