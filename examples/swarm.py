"""A swarm with Emitter and Receiver: every robot broadcasts its name, listens to the
others, and lights its front LED while it hears someone.

Each robot avoids obstacles (the others included) as it goes. At the end each prints
whom it heard, how often, and the last signal strength (1/distance² in Webots' model).
Run three emulated robots in one world, each controller in its own process, with

    ego swarm --robots 3 --duration 5 examples/swarm.py

The same file runs in Webots, and on real robots served over Zenoh (docs/zenoh.md).
"""

from controller import Robot

TIME_STEP = 32
SPEED = 3.0  # rad/s
NEAR = 150.0  # raw IR: something close in front

robot = Robot()
me = robot.getName()
emitter = robot.getDevice("emitter")
receiver = robot.getDevice("receiver")
receiver.enable(TIME_STEP)
front = [robot.getDevice(name) for name in ("ps0", "ps7")]
for sensor in front:
    sensor.enable(TIME_STEP)
led = robot.getDevice("led8")  # the body LED
left_motor = robot.getDevice("left wheel motor")
right_motor = robot.getDevice("right wheel motor")
for motor in (left_motor, right_motor):
    motor.setPosition(float("inf"))
    motor.setVelocity(0.0)

heard = {}
strength = {}
while robot.step(TIME_STEP) != -1:
    emitter.send(me.encode())
    while receiver.getQueueLength() > 0:
        sender = receiver.getData().decode()
        heard[sender] = heard.get(sender, 0) + 1
        strength[sender] = receiver.getSignalStrength()
        receiver.nextPacket()
    led.set(1 if strength else 0)
    blocked = max(sensor.getValue() for sensor in front) > NEAR
    left_motor.setVelocity(SPEED if not blocked else SPEED / 2)
    right_motor.setVelocity(SPEED if not blocked else -SPEED / 2)

for sender in sorted(heard):
    print(f"{me} heard {sender} {heard[sender]} times, last strength {strength[sender]:.1f}")
