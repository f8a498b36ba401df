"""Published style: a Robot subclass holding subclassed devices and its own Keyboard,
imported from Webots' per-class submodules."""

from controller.accelerometer import Accelerometer
from controller.distance_sensor import DistanceSensor
from controller.keyboard import Keyboard
from controller.led import LED
from controller.light_sensor import LightSensor
from controller.motor import Motor
from controller.position_sensor import PositionSensor
from controller.robot import Robot

TIME_STEP = 32


class WheelMotor(Motor):
    def __init__(self, name):
        super().__init__(name)
        self.setPosition(float("inf"))
        self.setVelocity(0.0)
        self.velocity = 0.0  # a plain attribute of the user's own


class Proximity(DistanceSensor):
    def __init__(self, name, period):
        super().__init__(name)
        self.enable(period)
        self.side = "front" if name in ("ps0", "ps7") else "side"  # a plain attribute


class Light(LightSensor):
    pass


class Encoder(PositionSensor):
    pass


class Keys(Keyboard):
    def __init__(self, period):
        super().__init__(period)
        self.pressed = []


class Epuck(Robot):
    def __init__(self):
        super().__init__()
        self.keyboard = Keys(TIME_STEP)  # a plain attribute in Webots' Robot
        self.left = WheelMotor("left wheel motor")
        self.right = WheelMotor("right wheel motor")
        self.front = [Proximity(n, TIME_STEP) for n in ("ps0", "ps7")]
        self.light = Light("ls0")  # made by name: enabled at the basic time step
        self.encoder = Encoder("left wheel sensor", TIME_STEP)
        self.accelerometer = Accelerometer("accelerometer")
        self.led = LED("led0")

    def run(self):
        self.led.set(1)
        for wheel in (self.left, self.right):
            wheel.velocity = 3.0
            wheel.setVelocity(wheel.velocity)
        while self.step(TIME_STEP) != -1 and self.getTime() < 1.0:
            pass
        print("front", *(p.side for p in self.front), *(p.getValue() for p in self.front))
        print("light", self.light.getSamplingPeriod(), self.light.getValue())
        print("encoder", self.encoder.getValue())
        print("keyboard", type(self.getKeyboard()).__name__, self.keyboard.pressed)
        print("accelerometer", self.accelerometer.getSamplingPeriod())


Epuck().run()
