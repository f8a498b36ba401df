"""The robots' side of a deepbots-shaped emitter/receiver pair (CSVRobot's scheme): each
step, take the supervisor's action (``"left,right"`` wheel speeds, rad/s) off the
Receiver and answer with an observation over the Emitter (``"NAME,PS0,PS7"``), on the
channel its world file gives it (``emitter_channel 2``: to the supervisor only). It is a
Supervisor too, as a swarm robot may be: it names itself and finds the other robot."""

import json

from controller import Supervisor


class CSVRobot(Supervisor):
    """As deepbots' CSVRobot: handle_receiver, then handle_emitter, every step."""

    def __init__(self) -> None:
        super().__init__()
        self.timestep = int(self.getBasicTimeStep())
        self.emitter = self.getDevice("emitter")
        self.receiver = self.getDevice("receiver")
        self.receiver.enable(self.timestep)
        self.left = self.getDevice("left wheel motor")
        self.right = self.getDevice("right wheel motor")
        for motor in (self.left, self.right):
            motor.setPosition(float("inf"))
            motor.setVelocity(0.0)
        self.ps = [self.getDevice(f"ps{i}") for i in (0, 7)]
        for sensor in self.ps:
            sensor.enable(self.timestep)
        self.me = self.getSelf().getDef()
        self.done = False
        self.actions = 0

    def create_message(self) -> list[object]:
        return [self.me, *(round(s.getValue(), 1) for s in self.ps)]

    def use_message_data(self, message: list[str]) -> None:
        if message[0] == "stop":
            self.done = True
            return
        self.actions += 1
        self.left.setVelocity(float(message[0]))
        self.right.setVelocity(float(message[1]))

    def handle_receiver(self) -> None:
        while self.receiver.getQueueLength() > 0:
            self.use_message_data(self.receiver.getString().split(","))
            self.receiver.nextPacket()

    def handle_emitter(self) -> None:
        self.emitter.send(",".join(str(v) for v in self.create_message()).encode("utf-8"))

    def run(self) -> None:
        while not self.done and self.step(self.timestep) != -1:
            self.handle_receiver()
            self.handle_emitter()


robot = CSVRobot()
other = "EPUCK_B" if robot.me == "EPUCK_A" else "EPUCK_A"
other_x = robot.getFromDef(other).getPosition()[0]
robot.run()
print("RESULT " + json.dumps({"me": robot.me, "other": other, "other_x": other_x,
                              "kind": robot.getSelf().getTypeName(),
                              "actions": robot.actions}), flush=True)
