"""A swarm controller as Webots users write them: each robot reads its proximity sensors,
broadcasts its name over its Emitter every step, and counts what its Receiver gets from
the others, with the signal strength of each sender."""

import json
import os

from controller import Robot

robot = Robot()
me = robot.getName()
proximity = [robot.getDevice(f"ps{i}") for i in range(8)]
for sensor in proximity:
    sensor.enable(32)
emitter = robot.getDevice("emitter")
receiver = robot.getDevice("receiver")
receiver.enable(32)
closest = 0.0
heard = {}
strength = {}
# The controllers start one by one: each first waits until it hears every other robot
# (the test says how many there are), so that all count over the same 40 steps.
others = int(os.environ["SWARM_TALK_OTHERS"])
started = set()
for _ in range(1000):
    if len(started) == others or robot.step(32) == -1:
        break
    emitter.send(me)
    while receiver.getQueueLength() > 0:
        started.add(receiver.getString())
        receiver.nextPacket()
for _ in range(40):
    if robot.step(32) == -1:
        break
    closest = max(closest, max(sensor.getValue() for sensor in proximity))
    emitter.send(me)
    while receiver.getQueueLength() > 0:
        sender = receiver.getString()
        heard[sender] = heard.get(sender, 0) + 1
        strength[sender] = receiver.getSignalStrength()
        receiver.nextPacket()
print("RESULT " + json.dumps({"me": me, "closest": closest, "heard": heard,
                              "strength": strength}), flush=True)
