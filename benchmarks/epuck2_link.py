"""The e-puck2's links beside the e-puck1's, in one run: a step's round trip and the step
rate over emulated USB (a pty) and WiFi (loopback TCP), the WiFi with and without the
camera (38400 bytes a frame).

What is measured, per link, over back-to-back steps (no pacing: each step starts when the
last one's answer is in): one avoidance step's batch, the wheel speeds set and the eight
proximity sensors read, from the moment it is handed to the link until its answer is
back (the round trip), its inverse (the step rate), the client process's CPU per step
(``time.process_time``: the emulator runs in its own process, so this is the client's
cost alone, a WiFi channel's reader thread included), and the bytes the client received
per step (over WiFi the robot streams whether asked or not).

The emulators model the firmware's own time, which is not ego's cost: the e-puck1's pty
carries bytes at 230400 baud (10 bits each); the e-puck2's USB pty is unpaced but its
main processor sleeps 10 ms after reading a ``-0x09`` payload (Asercom2.c:481); its radio
waits 10 ms between the states of its loop (socket_e-puck2.c:279), so a sensor packet
comes every two loops (about 20 ms) and, with the image, every three. The "modelled"
column gives that floor; the rest of a round trip is the links' and the clients' own.

Clients: ego's own channels (the e-puck1's serial Link; the e-puck2's Link on its USB
profile, with the batch ego's profile chooses for this step, ``-D -N``; the e-puck2's WiFi
channel, :mod:`ego.backends.epuck2`), and beside ego's USB Link the bare client of
``serial_link`` (os.write, os.read) on the same pty, once with the same bytes and once
with asercom v2's blocks (``-0x09 -0x08``), which ego's profile does not choose.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from benchmarks.common import Stats, Table, emulator_process, fmt, progress
from benchmarks.serial_link import bare_client
from ego.serial import Command, Firmware, Link, Request, SerialTransport, encode_batch
from ego.serial.profiles import PROFILES, wire_time_s

__all__ = ["run"]

_SPEEDS = Request(Command.SET_SPEED, (200, -200))
_PROXIMITY = Request(Command.PROXIMITY)
#: asercom v2's blocks over USB: the 19-byte actuators (speeds 200, -200), then all sensors.
_V2_BATCH = bytes([0xF7, 0, 200, 0, 0x38, 0xFF]) + bytes(14) + bytes([0xF8, 0])
#: The e-puck1's commands on the e-puck2: -D (speeds), -N (8 proximity, 16 bytes).
_V1_BATCH = bytes([0xBC, 200, 0, 0x38, 0xFF, 0xB2, 0])
_RADIO_LOOP_S = 0.010


@dataclass(frozen=True)
class Measured:
    """One link's steps."""

    label: str
    client: str
    times: list[float]
    cpu_s: float
    bytes_per_step: float
    modelled_s: float


def _timed(steps: int, label: str, step: Callable[[], None]) -> tuple[list[float], float]:
    step()  # warm-up: lazy imports, the first frame's stream
    times = []
    cpu0 = time.process_time()
    for _ in progress(range(steps), label, total=steps):
        t0 = time.perf_counter()
        step()
        times.append(time.perf_counter() - t0)
    return times, (time.process_time() - cpu0) / steps


def _epuck1(steps: int) -> Measured:
    label = "e-puck1, pty at 230400 baud"
    profile = PROFILES[Firmware.WEBOTS]
    batch = encode_batch([_SPEEDS, _PROXIMITY], profile)
    with emulator_process() as path:
        link = Link(SerialTransport(path, 230400), Firmware.WEBOTS)
        try:
            times, cpu = _timed(steps, label, lambda: link.exchange(batch) and None)
        finally:
            link.close()
    wire = wire_time_s(len(batch.tx) + batch.reply_size)
    return Measured(label, "ego Link", times, cpu, batch.reply_size, wire)


def _epuck2_usb(steps: int) -> list[Measured]:
    out = []
    with emulator_process("--robot", "epuck2") as path:
        label = "e-puck2 USB, ego's choice -D -N"
        link = Link(SerialTransport(path, 230400), Firmware.EPUCK2)  # USB CDC: no line rate
        batch = encode_batch([_SPEEDS, _PROXIMITY], link.profile)
        try:
            times, cpu = _timed(steps, label, lambda: link.exchange(batch) and None)
        finally:
            link.close()
        out.append(Measured(label, "ego Link", times, cpu, batch.reply_size, 0.0))
        for label, tx, reply, modelled in (
            ("e-puck2 USB, e-puck1 commands -D -N", _V1_BATCH, 16, 0.0),
            ("e-puck2 USB, asercom v2 -0x09 -0x08", _V2_BATCH, 103, 0.010),
        ):
            run = bare_client(path, tx, reply, steps, label)
            out.append(Measured(label, "bare client", run.times, run.cpu_s, reply, modelled))
    return out


def _epuck2_wifi(steps: int) -> list[Measured]:
    from ego.backends.epuck2.channel import Epuck2Channel
    from ego.backends.epuck2.requests import WIFI_PROFILE
    from ego.core.registry import open_port

    batch = encode_batch([_SPEEDS, _PROXIMITY], WIFI_PROFILE)
    out = []
    with emulator_process("--robot", "epuck2", "--wifi", "--wifi-port", "0") as url:
        opened = open_port("epuck2://" + url.removeprefix("tcp://"))
        channel = opened.channel
        assert isinstance(channel, Epuck2Channel)
        try:
            for camera, label, modelled in (
                (False, "e-puck2 WiFi, sensors", 2 * _RADIO_LOOP_S),
                (True, "e-puck2 WiFi, sensors + camera", 3 * _RADIO_LOOP_S),
            ):

                def step(camera: bool = camera) -> None:
                    channel.exchange(batch)
                    if camera:
                        channel.next_image()

                channel.camera_open(camera)
                received = channel.heard.bytes_received
                times, cpu = _timed(steps, label, step)
                per_step = (channel.heard.bytes_received - received) / (steps + 1)
                out.append(Measured(label, "ego channel", times, cpu, per_step, modelled))
            channel.camera_open(False)
        finally:
            opened.close()
    return out


def run(quick: bool = False) -> list[Table]:
    steps = 15 if quick else 300
    measured = [_epuck1(steps), *_epuck2_usb(steps), *_epuck2_wifi(steps)]
    table = Table(
        key="epuck2_link",
        title="The e-puck2's links beside the e-puck1's: one avoidance step's round trip",
        columns=[
            "link",
            "client",
            "round trip ms (min-max)",
            "steps/s",
            "modelled ms",
            "client CPU us/step",
            "bytes in/step",
        ],
    )
    for m in measured:
        s = Stats.of(m.times).scaled(1000)
        table.rows.append([
            m.label, m.client, f"{fmt(s.median)} ({fmt(s.low)}-{fmt(s.high)})",
            1000 / s.median, m.modelled_s * 1000, m.cpu_s * 1e6, m.bytes_per_step,
        ])  # fmt: skip
    table.notes.append(
        f"{steps} back-to-back steps a link, each emulator in its own process. 'modelled': "
        "the firmware time the emulator models per step (the e-puck1's line time at 230400 "
        "baud; the e-puck2's 10 ms sleep after -0x09 on USB; two or three 10 ms radio loops "
        "a sensor packet over WiFi), a floor that is not ego's cost; 'client CPU': this "
        "process's CPU per step (over WiFi the reader thread's too)."
    )
    return [table]
