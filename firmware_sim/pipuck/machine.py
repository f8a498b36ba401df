"""A Pi-puck's I2C buses with one robot's devices on them, and the kernel in front.

Which device answers where is data (:data:`DEVICES`): the e-puck2's main processor in
gumstix mode, IMU, time-of-flight sensor, the e-puck1's dsPIC with York's firmware and
(revision 1.3) its LSM330, and the optional ground-sensor module. Everything here runs
under one lock, held for a whole transaction, as the physical bus is.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from firmware_sim.epuck2.robot import Epuck2Robot
from firmware_sim.pipuck.board import (
    ADC_ADDRESS,
    FT903_ADDRESS,
    MUX_ADDRESS,
    PI_BUS,
    Ft903,
    channel_bus,
)
from firmware_sim.pipuck.bus import Bus, Target
from firmware_sim.pipuck.ground import GroundSensors
from firmware_sim.pipuck.gumstix import GumstixMcu
from firmware_sim.pipuck.i2cdev import I2cDev
from firmware_sim.pipuck.lsm330 import lsm330_accelerometer, lsm330_gyro
from firmware_sim.pipuck.mpu9250 import Mpu9250
from firmware_sim.pipuck.registers import RegisterTarget
from firmware_sim.pipuck.vl53l0x import Vl53l0x
from firmware_sim.pipuck.wire import Session
from firmware_sim.pipuck.york import YorkEpuck1
from firmware_sim.world import World

__all__ = ["ROBOTS", "PipuckMachine"]

ROBOTS = ("epuck2", "epuck")
NUMBERINGS = ("current", "legacy")
#: A wide seed stream of this package's own, apart from the world's noise.
_STREAM = 0x70697075


@dataclass(frozen=True, slots=True)
class Options:
    """What is fitted: the ground-sensor module, an e-puck1's revision 1.3 IMU, the
    address the MPU-9250's AD0 pin gives it (0x68 or 0x69)."""

    ground_module: bool = True
    rev13: bool = True
    imu_address: int = 0x68
    #: The Pi's I2C clock (dtparam i2c_arm_baudrate; 100 kHz by default), and whether a
    #: transaction takes its wire time in real time (the socket's thread sleeps).
    bus_hz: int = 100_000
    paced: bool = False


class PipuckMachine:
    """The buses of one Pi-puck carrying ``robot`` ("epuck2" or "epuck") in ``world``."""

    def __init__(self, robot: str, numbering: str, world: World, seed: int | None,
                 options: Options) -> None:  # fmt: skip
        if robot not in ROBOTS:
            raise ValueError(f"robot {robot!r} is not one of {', '.join(ROBOTS)}")
        if numbering not in NUMBERINGS:
            raise ValueError(f"bus numbering {numbering!r} is not one of {', '.join(NUMBERINGS)}")
        self.robot_kind = robot
        self.numbering = numbering
        self.world = world
        self.options = options
        self.lock = threading.RLock()
        self.rng = np.random.default_rng(None if seed is None else [seed, _STREAM])
        self.robot_bus = channel_bus(numbering, 1)
        self.board_bus = channel_bus(numbering, 0)
        self.mcu: Any = None
        self.devices: dict[int, Target] = {}
        if robot == "epuck2":
            self._fit_epuck2(seed)
        else:
            self._fit_epuck1()
        self.buses = self._buses()
        #: Fault state: bus numbers whose node is gone; opens refused with EACCES.
        self.missing: set[int] = set()
        self.access_denied = False
        self.dev = I2cDev(self.lookup, lambda: self.access_denied)

    def _fit_epuck2(self, seed: int | None) -> None:
        self.epuck2 = Epuck2Robot(self.world, seed=seed, selector=10,
                                  ground_module=self.options.ground_module)  # fmt: skip
        self.mcu = GumstixMcu(self.epuck2)
        self.devices[self.mcu.address] = self.mcu
        self.devices[self.options.imu_address] = Mpu9250(self.world, self.epuck2.imu)
        self.devices[Vl53l0x.address] = Vl53l0x(self.epuck2.tof)
        if self.options.ground_module:
            self.devices[GroundSensors.address] = GroundSensors(self.world)

    def _fit_epuck1(self) -> None:
        self.mcu = YorkEpuck1(self.world)
        self.devices[self.mcu.address] = self.mcu
        if self.options.rev13:
            for chip in (lsm330_accelerometer(self.world), lsm330_gyro(self.world, self.rng)):
                self.devices[chip.address] = chip
        if self.options.ground_module:
            self.devices[GroundSensors.address] = GroundSensors(self.world)

    def _buses(self) -> dict[int, Bus]:
        mux: dict[int, Target] = {MUX_ADDRESS: RegisterTarget()}
        buses = {PI_BUS: Bus(PI_BUS, "bcm2835 (i2c@7e804000)", mux, frozenset(mux))}
        for channel in range(8):
            number = channel_bus(self.numbering, channel)
            buses[number] = Bus(number, f"i2c-{PI_BUS}-mux (chan_id {channel})")
        board = buses[self.board_bus]
        board.targets.update({FT903_ADDRESS: Ft903(), ADC_ADDRESS: RegisterTarget()})
        board.bound = frozenset({ADC_ADDRESS})
        buses[self.robot_bus].targets.update(self.devices)
        for bus in buses.values():
            bus.clock_hz = self.options.bus_hz
            bus.on_wire = time.sleep if self.options.paced else None
        return buses

    def lookup(self, number: int) -> Bus | None:
        return None if number in self.missing else self.buses.get(number)

    def session(self) -> Session:
        return Session(self.dev, self.lock)
