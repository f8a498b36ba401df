"""Published style: a learning loop's Supervisor puts the robot back between episodes,
reads its true pose, and moves the target box into its way."""

from controller import Supervisor

TIME_STEP = 32
robot = Supervisor()
me = robot.getSelf()
translation, rotation = me.getField("translation"), me.getField("rotation")
target = robot.getFromDef("TARGET")
ps0 = robot.getDevice("ps0")
ps0.enable(TIME_STEP)
left, right = robot.getDevice("left wheel motor"), robot.getDevice("right wheel motor")
for wheel in (left, right):
    wheel.setPosition(float("inf"))
print("start", *me.getPosition(), rotation.getSFRotation()[3])
print("target", *target.getPosition())
print("missing", robot.getFromDef("NO_SUCH_SOLID"))
for episode in range(2):
    translation.setSFVec3f([0.1, -0.2, 0.0])
    rotation.setSFRotation([0, 0, 1, 1.5708])
    me.resetPhysics()
    left.setVelocity(4.0)
    right.setVelocity(4.0)
    for _ in range(20):
        robot.step(TIME_STEP)
    x, y, _ = me.getPosition()
    print("episode", episode, x, y, me.getVelocity()[1])
left.setVelocity(0.0)
right.setVelocity(0.0)
robot.step(TIME_STEP)
x, y, _ = me.getPosition()
target.getField("translation").setSFVec3f([x, y + 0.06, 0.0])  # right in front of it
for _ in range(5):
    robot.step(TIME_STEP)
print("front", ps0.getValue())
robot.simulationReset()
robot.step(TIME_STEP)
print("reset", *me.getPosition(), *target.getPosition())
print("supervisor", robot.getSupervisor(), robot.simulationGetMode())
