"""The Robot's device families: wiring them to the channel's profile, and finding them by name."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ego.devices.accelerometer import Accelerometer
from ego.devices.base import Device, Sensor
from ego.devices.battery import Battery
from ego.devices.button import Button
from ego.devices.encoders import Encoders
from ego.devices.families import make_families, pick
from ego.devices.floor import FloorSensors
from ego.devices.gyro import Gyro
from ego.devices.leds import Leds
from ego.devices.light import LightSensors
from ego.devices.magnetometer import Magnetometer
from ego.devices.microphones import Microphones
from ego.devices.motors import Motors
from ego.devices.proximity import ProximitySensors
from ego.devices.selector import Selector
from ego.devices.sound import Speaker
from ego.devices.temperature import Temperature
from ego.devices.tof import TofSensor
from ego.errors import LinkLostError, UnknownDeviceError

if TYPE_CHECKING:
    from ego.i2c.side import OveroI2C
    from ego.seam.channel import ChannelBase

__all__ = ["DeviceWiring"]


class DeviceWiring:
    """The part of :class:`~ego.core.robot.Robot` that holds its device families."""

    port: str
    channel: ChannelBase
    i2c: OveroI2C
    _closed: bool
    _lost: bool
    motors: Motors
    leds: Leds
    encoders: Encoders
    accelerometer: Accelerometer
    proximity: ProximitySensors
    floor: FloorSensors
    light: LightSensors
    microphones: Microphones
    battery: Battery
    tof: TofSensor
    gyro: Gyro
    magnetometer: Magnetometer
    temperature: Temperature
    button: Button
    selector: Selector
    sound: Speaker
    families: tuple[Device, ...]
    _families: dict[str, Device]
    _step_parts: tuple[Device, ...]

    def _wire_devices(self) -> None:
        """One object per family, for the channel's profile, its sensors bound to the I2C bus."""
        # One of each family the device table names (ego.devices.table), by its name.
        self._families = made = make_families(self.channel.profile)
        self.motors = pick(made, "motors", Motors)
        self.leds = pick(made, "leds", Leds)
        self.encoders = pick(made, "encoders", Encoders)
        self.accelerometer = pick(made, "accelerometer", Accelerometer)
        self.proximity = pick(made, "proximity", ProximitySensors)
        self.floor = pick(made, "floor", FloorSensors)
        self.light = pick(made, "light", LightSensors)
        self.microphones = pick(made, "microphones", Microphones)
        self.battery = pick(made, "battery", Battery)
        # The e-puck2's (empty of members on an e-puck1: enabling them is refused).
        self.tof = pick(made, "tof", TofSensor)
        self.gyro = pick(made, "gyro", Gyro)
        self.magnetometer = pick(made, "magnetometer", Magnetometer)
        self.temperature = pick(made, "temperature", Temperature)
        self.button = pick(made, "button", Button)
        self.selector = pick(made, "selector", Selector)
        self.sound = pick(made, "sound", Speaker)
        self.proximity.bind_calibration(self.calibrate_proximity)
        self.sound.bind_ascii(self.ascii_command)
        #: The device families, in the order Webots names their devices.
        self.families = tuple(made.values())
        #: What each step's transaction runs over (ego.core.transaction).
        self._step_parts = tuple(part for family in self.families for part in family.parts)
        for part in self._step_parts:
            if isinstance(part, Sensor):
                part.bind_i2c(self.i2c)

    def device(self, name: str) -> Device:
        """The family serving the Webots device ``name`` ("ps3", "left wheel motor"...).

        The device table (:mod:`ego.devices.table`) says which family; the family says
        whether the connected firmware has it (ps8, ps9: the Overo's only).
        """
        from ego.devices.table import CAMERA, find

        found = find(name)
        if found is not None and found.webots_device and found.family != CAMERA:
            family = self._families.get(found.family)
            if family is not None and name in family.member_names:
                return family
        raise UnknownDeviceError(
            f"no device named {name!r}; valid names: {', '.join(self.device_names)}"
        )

    def family(self, name: str) -> Device:
        """The family the device table calls ``name``: ``robot.family("proximity")`` is
        ``robot.proximity``; a family added to the table is reached so."""
        found = self._families.get(name)
        if found is None:
            raise UnknownDeviceError(
                f"no device family {name!r}; valid families: {', '.join(self._families)}"
            )
        return found

    @property
    def device_names(self) -> tuple[str, ...]:
        """Every Webots device name this robot answers to, by family, camera last."""
        from ego.devices.table import CAMERA, DEVICES

        rank = {id(family): i for i, family in enumerate(self.families)}
        served = sorted(
            (rank[id(family)], s.index, s.name)
            for s in DEVICES
            if (family := self._families.get(s.family)) is not None
            and s.name in family.member_names
        )
        return (*(name for _, _, name in served), *(s.name for s in DEVICES if s.family == CAMERA))

    # -- ASCII commands --------------------------------------------------------------

    def calibrate_proximity(self) -> None:
        """Calibrate the IR proximity sensors (``K``); see ProximitySensors.calibrate."""
        self._require_open()
        self.channel.calibrate_proximity()

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        """Send one ASCII command to the dsPIC and return its reply lines.

        ``S`` (stop) differs between the firmwares (docs/protocol.md, quirk "S"): the
        stock one stops the wheels and the ring LEDs but keeps echoing the old speeds in
        ``E``; Webots' also clears that echo and the body and front LEDs. ego's own view of
        the motors and LEDs follows what the connected firmware did, and on the stock
        firmware a ``D 0 0`` goes with the next batch so that ``E`` echoes the truth:
        otherwise ego's speed check would see a mismatch and send the old speeds again.
        """
        self._require_open()
        replies = self.channel.ascii_command(letter, lines)
        if letter.upper() == "S":
            stop = self.channel.profile.ascii_stop
            self.motors.stopped_by_firmware(resend=not stop.clears_echo)
            self.leds.switched_off(stop.leds)
        return replies

    def _require_open(self) -> None:
        if self._closed or self._lost:
            raise LinkLostError(f"{self.port}: the robot is {'closed' if self._closed else 'lost'}")
