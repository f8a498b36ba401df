"""The Pi-puck's I2C beside the e-puck's other links, in one run: the time one full step
takes on the bus at 100 kHz and at 400 kHz, modelled from the bytes ego puts on the
emulated bus, beside ego's CPU per step and the serial and WiFi links' own time.

What is measured: a robot on the emulated Pi-puck (``firmware_sim.pipuck``: smbus2's
real ioctls through the shim, in a child process) steps with the avoidance step's
families (the speeds set, the proximity read) and with a full step's (proximity, light,
encoders, microphones, accelerometer, gyro, ToF, ground sensors); the channel counts
every byte of every transfer, addresses and register numbers included
(``ego.backends.pipuck.bus.RobotBus.wire_bytes``). An I2C byte is nine clocks (eight
bits and the acknowledge), so a step's bus time is ``bytes x 9 / rate``, start and stop
conditions aside. The e-puck2 firmware's slave runs at 100 kHz (gumstix.c:39-45); 400 kHz
is what the bus could do if the firmware were built for it. ego's CPU per step is the
child's ``time.process_time`` per step (the emulator runs in another process).

Beside them, in the same run, from ``benchmarks.epuck2_link``: ego's serial Link on the
emulated e-puck1's pty (its CPU per step, and the line time of the avoidance batch at
230400 baud, the Overo's), the same batch at 115200 (Bluetooth), and the e-puck2's WiFi
channel (its CPU per step and the floor of two 10 ms radio loops a sensor packet).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

from benchmarks.common import Table, fmt
from ego.serial import Command, Firmware, Request, encode_batch
from ego.serial.profiles import PROFILES, wire_time_s

__all__ = ["run"]

I2C_RATES = (100_000, 400_000)
I2C_CLOCKS_PER_BYTE = 9


def _child(which: str, steps: int) -> dict[str, float]:
    from firmware_sim.pipuck import PipuckEmulator

    with PipuckEmulator(robot="epuck2", buses="current") as emu:
        env = {**os.environ, **emu.environ()}
        done = subprocess.run(
            [sys.executable, "-m", "benchmarks._pipuck_steps", which, str(steps)],
            env=env, capture_output=True, text=True, timeout=600, check=True,
        )  # fmt: skip
    result: dict[str, float] = json.loads(done.stdout.strip().splitlines()[-1])
    return result


def run(quick: bool = False) -> list[Table]:
    from benchmarks.epuck2_link import _epuck1, _epuck2_wifi

    steps = 20 if quick else 200
    table = Table(
        key="pipuck_i2c",
        title="The Pi-puck's I2C: one step's bus time beside ego's CPU and the other links",
        columns=["link", "step", "bytes/step", "link ms/step (modelled)", "ego CPU us/step"],
    )
    for which in ("avoidance", "full"):
        measured = _child(which, steps)
        for rate in I2C_RATES:
            bus_s = measured["wire_bytes"] * I2C_CLOCKS_PER_BYTE / rate
            table.rows.append([f"Pi-puck I2C at {rate // 1000} kHz", which,
                               measured["wire_bytes"], bus_s * 1000,
                               measured["cpu_s"] * 1e6])  # fmt: skip
    serial = _epuck1(steps)
    table.rows.append(["e-puck1 serial (Overo UART) at 230400 baud", "avoidance",
                       serial.bytes_per_step, serial.modelled_s * 1000,
                       serial.cpu_s * 1e6])  # fmt: skip
    batch = encode_batch([Request(Command.SET_SPEED, (200, -200)), Request(Command.PROXIMITY)],
                         PROFILES[Firmware.WEBOTS])  # fmt: skip
    size = len(batch.tx) + batch.reply_size
    table.rows.append(["e-puck1 Bluetooth at 115200 baud", "avoidance", size,
                       wire_time_s(size, 115200) * 1000, "-"])  # fmt: skip
    for wifi in _epuck2_wifi(max(5, steps // 4))[:1]:
        table.rows.append(["e-puck2 WiFi (radio loops)", "avoidance", fmt(wifi.bytes_per_step),
                           wifi.modelled_s * 1000, wifi.cpu_s * 1e6])  # fmt: skip
    table.notes.append(
        f"{steps} steps a row on the emulated Pi-puck (a child process, smbus2's ioctls "
        "through the shim). Bus time: the bytes ego put on the bus, 9 clocks each, at the "
        "rate; the e-puck2 firmware's slave runs at 100 kHz. Serial: ego's Link on the "
        "emulator's pty (its CPU; the line time of the batch's bytes at 10 bits a byte); "
        "Bluetooth: the same batch's bytes at 115200 baud. WiFi: the radio's two 10 ms loops a "
        "sensor packet, and the client's CPU over loopback (benchmarks/epuck2_link.py)."
    )
    return [table]
