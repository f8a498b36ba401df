"""Published style: a deepbots 1.0.0 ``RobotSupervisorEnv`` e-puck environment.

deepbots (PyPI, needs gym 0.21, which no longer installs) is reproduced here by its
call sequence, in our own words: its ``reset()`` calls ``simulationReset()``,
``simulationResetPhysics()``, then steps once through ``Robot.step`` (``super(Supervisor,
self).step``) before it observes; its ``step(action)`` applies the action, steps, and
``exit()``s on -1. The environment drives the e-puck's wheels by velocity and
observes its true pose. Each episode prints the pose its ``reset()`` observed, and
the state of a wheel.
"""

import math

from controller import Supervisor


class Env:
    """What gym.Env gives a deepbots environment: nothing ego needs."""


class DeepbotsSupervisorEnv(Supervisor, Env):
    def reset(self):
        self.simulationReset()
        self.simulationResetPhysics()
        super(Supervisor, self).step(int(self.getBasicTimeStep()))
        return self.get_default_observation()


class RobotSupervisorEnv(DeepbotsSupervisorEnv):
    def __init__(self, timestep=None):
        super().__init__()
        self.timestep = int(self.getBasicTimeStep()) if timestep is None else timestep

    def step(self, action):
        self.apply_action(action)
        if super(Supervisor, self).step(self.timestep) == -1:
            exit()
        return self.get_observations(), self.get_reward(action), self.is_done(), {}


class EpuckEnv(RobotSupervisorEnv):
    """Drive to the right of the start; the observation is the true pose."""

    def __init__(self):
        super().__init__()
        self.robot = self.getSelf()
        self.wheels = [self.getDevice(f"{side} wheel motor") for side in ("left", "right")]
        for sensor in ("ps0", "ps7"):
            self.getDevice(sensor).enable(self.timestep)
        self.counter = self.getDevice("left wheel sensor")
        self.counter.enable(self.timestep)
        self.steps = 0

    def get_default_observation(self):
        self.steps = 0
        return self.get_observations()

    def get_observations(self):
        x, y, _ = self.robot.getPosition()
        yaw = self.robot.getField("rotation").getSFRotation()[3]
        return [x, y, yaw]

    def apply_action(self, action):
        speeds = {0: (6.0, 6.0), 1: (6.0, -2.0), 2: (-2.0, 6.0)}[action]
        for wheel, speed in zip(self.wheels, speeds, strict=True):
            wheel.setPosition(float("inf"))
            wheel.setVelocity(speed)

    def get_reward(self, action):
        return -abs(self.get_observations()[1])

    def is_done(self):
        self.steps += 1
        return self.steps >= 25


env = EpuckEnv()
for episode in range(5):
    start = env.reset()
    print("episode", episode, *start)
    left = env.wheels[0]
    print(
        "motor",
        episode,
        left.getTargetPosition(),
        left.getVelocity() == left.getMaxVelocity(),
        env.counter.getValue(),
    )
    done, action = False, episode % 3
    while not done:
        observation, reward, done, _ = env.step(action)
        action = (action + 1) % 3 if env.steps % 7 == 0 else action
    moved = math.hypot(observation[0] - start[0], observation[1] - start[1])
    print("moved", episode, moved)
