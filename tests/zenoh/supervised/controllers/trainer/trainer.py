"""A bodiless supervisor in deepbots' emitter/receiver scheme (CSVSupervisorEnv's shape):
each step it sends an action to the robots over its Emitter and reads their observations
off its Receiver; each episode ends with ``reset()`` (simulationReset, then one step).
It checks through getFromDef that the robots moved during an episode (halted at its end)
and stood at their start after each reset, and moves the box by its translation field."""

import json
import math

from controller import Supervisor

EPISODES = 3
STEPS = 25
#: The longest a wait for the robots may last, in steps (about 100 s).
PATIENCE = 3000
ROBOTS = ("EPUCK_A", "EPUCK_B")


class CSVSupervisorEnv:
    """As deepbots' CSVSupervisorEnv: the supervisor, its emitter and receiver."""

    def __init__(self) -> None:
        self.supervisor = Supervisor()
        self.timestep = int(self.supervisor.getBasicTimeStep())
        self.emitter = self.supervisor.getDevice("emitter")
        self.receiver = self.supervisor.getDevice("receiver")
        self.receiver.enable(self.timestep)
        self.heard: dict[str, int] = {}

    def handle_emitter(self, action: list[float]) -> None:
        self.emitter.send(",".join(str(a) for a in action).encode("utf-8"))

    def handle_receiver(self) -> list[str] | None:
        last = None
        while self.receiver.getQueueLength() > 0:
            last = self.receiver.getString().split(",")
            self.heard[last[0]] = self.heard.get(last[0], 0) + 1
            self.receiver.nextPacket()
        return last

    def step(self, action: list[float]) -> list[str] | None:
        if self.supervisor.step(self.timestep) == -1:
            raise SystemExit(1)
        self.handle_emitter(action)
        return self.handle_receiver()

    def reset(self) -> None:
        self.supervisor.simulationReset()
        self.supervisor.simulationResetPhysics()
        self.supervisor.step(self.timestep)


def where(env: CSVSupervisorEnv, name: str) -> list[float]:
    return env.supervisor.getFromDef(name).getField("translation").getSFVec3f()


def until(env: CSVSupervisorEnv, done, action: list[float], what: str) -> None:
    """Step with ``action`` until ``done()``; a failure, not a hang, if it never is."""
    for _ in range(PATIENCE):
        if done():
            return
        env.step(action)
    raise SystemExit(f"trainer: {what} within {PATIENCE} steps: {env.heard}")


env = CSVSupervisorEnv()
starts = {name: where(env, name) for name in ROBOTS}
# Wait until both robots' controllers are up and heard (they start in their own time).
until(env, lambda: all(env.heard.get(name) for name in ROBOTS), [0.0, 0.0],
      "the robots were not heard")
episodes = []
for _ in range(EPISODES):
    env.heard = {}
    for _ in range(STEPS):
        env.step([4.0, 4.0])
    # However late the robots' controllers step, the actions drive them 2 cm at least.
    until(env, lambda: all(math.dist(where(env, n)[:2], starts[n][:2]) >= 0.02
                           for n in ROBOTS), [4.0, 4.0], "the robots did not move 2 cm")
    # The episode ends with the robots halted (however late their controllers step).
    until(env, lambda: not any(any(env.supervisor.getFromDef(n).getVelocity()) for n in ROBOTS),
          [0.0, 0.0], "the robots did not halt")
    moved = {n: math.dist(where(env, n)[:2], starts[n][:2]) for n in ROBOTS}
    env.supervisor.simulationReset()
    back = {n: math.dist(where(env, n)[:2], starts[n][:2]) for n in ROBOTS}
    env.supervisor.simulationResetPhysics()
    env.supervisor.step(env.timestep)
    episodes.append({"heard": dict(env.heard), "moved": moved, "back": back})
box = env.supervisor.getFromDef("BOX")
box.getField("translation").setSFVec3f([0.1, 0.35, 0.0])
box_now = box.getPosition()
# "stop" until the robots have ended (nothing heard from them for 10 steps).
quiet = 0
for _ in range(PATIENCE):
    env.heard = {}
    env.step(["stop"])  # type: ignore[list-item]
    quiet = 0 if env.heard else quiet + 1
    if quiet >= 10:
        break
print("RESULT " + json.dumps({"me": env.supervisor.getName(), "episodes": episodes,
                              "box": box_now, "self": env.supervisor.getSelf().getTypeName(),
                              "names": sorted(env.supervisor.getFromDef(n).getDef()
                                              for n in ROBOTS)}), flush=True)
