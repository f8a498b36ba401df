"""An emulated e-puck dsPIC on a pseudo-terminal, with a world behind it, for tests and demo."""

from firmware_sim.dspic import BANNER, BatchRecord, Dspic
from firmware_sim.faults import FAULT_KINDS, FaultSpec, FaultTimings, parse_fault
from firmware_sim.server import Emulator
from firmware_sim.world import World

__all__ = [
    "BANNER",
    "FAULT_KINDS",
    "BatchRecord",
    "Dspic",
    "Emulator",
    "FaultSpec",
    "FaultTimings",
    "World",
    "parse_fault",
]
