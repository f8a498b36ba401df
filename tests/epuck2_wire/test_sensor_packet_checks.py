"""Issue 32, item 5: the documented checks of the e-puck2's "all sensors" reply hold over
USB and Bluetooth, as over WiFi. docs/protocol.md: "ego refuses, as a stream out of step,
a reply whose reserved byte is not 0, whose selector is above 15, or whose SD (or WiFi
button) byte is not 0 or 1". One decoder (``decode_sensors``) checks every link's packet:
the profile's ``-0x08`` wire format carries it, so ``Batch.decode`` runs it.

The end-to-end test puts a real pty between ego and the emulated robot's own pty; the relay
passes every byte and, when armed, changes one byte of the next ``-0x08`` reply."""

from __future__ import annotations

import os
import pty
import select
import threading
import tty
from collections.abc import Iterator

import pytest
from test_asercom2_sensors import RESERVED, SD, SELECTOR, sample_packet

import ego
from ego.errors import ProtocolError
from ego.seam.batch import Request
from ego.seam.profile import Command, Profile
from ego.serial.profiles import EPUCK2_BLUETOOTH, EPUCK2_USB, EPUCK2_WIFI
from ego.serial.protocol import encode_batch
from firmware_sim.epuck2 import Epuck2Emulator

_BAD = [(RESERVED, 1, "reserved byte 1"), (SELECTOR, 16, "selector 16"), (SD, 2, "SD card byte 2")]


@pytest.mark.parametrize("profile", [EPUCK2_USB, EPUCK2_BLUETOOTH, EPUCK2_WIFI])
@pytest.mark.parametrize(("offset", "value", "what"), _BAD)
def test_every_link_refuses_what_the_firmware_never_sends(
    profile: Profile, offset: int, value: int, what: str
) -> None:
    batch = encode_batch([Request(Command.ALL_SENSORS), Request(Command.PROXIMITY)], profile)
    good = sample_packet()
    assert batch.decode(bytes(good))[1] == tuple(100 + k for k in range(8))
    good[offset] = value
    with pytest.raises(ProtocolError, match=what):
        batch.decode(bytes(good))


class CorruptingRelay:
    """ego's pty on one side, the emulator's pty on the other; ``arm(offset, value)``
    changes byte ``offset`` of the reply that follows the next batch starting ``-0x08``."""

    def __init__(self, robot_path: str) -> None:
        self._master, self._slave = pty.openpty()
        tty.setraw(self._slave)
        self.path = os.ttyname(self._slave)
        self._robot = os.open(robot_path, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self._robot)
        self._stop_r, self._stop_w = os.pipe()
        self._lock = threading.Lock()
        self._armed: tuple[int, int] | None = None
        self._pending: tuple[int, int] | None = None  # offset still to reach, value
        self._thread = threading.Thread(target=self._run, name="epuck2-test-pty-relay")
        self._thread.start()

    def arm(self, offset: int, value: int) -> None:
        with self._lock:
            self._armed = (offset, value)

    def _run(self) -> None:
        while True:
            ready, _, _ = select.select([self._master, self._robot, self._stop_r], [], [])
            if self._stop_r in ready:
                return
            if self._master in ready:
                data = os.read(self._master, 4096)
                with self._lock:
                    if self._armed is not None and data[:1] == bytes([Command.ALL_SENSORS]):
                        self._pending, self._armed = self._armed, None
                os.write(self._robot, data)
            if self._robot in ready:
                got = bytearray(os.read(self._robot, 4096))
                with self._lock:
                    if self._pending is not None:
                        offset, value = self._pending
                        if offset < len(got):
                            got[offset] = value
                            self._pending = None
                        else:
                            self._pending = (offset - len(got), value)
                os.write(self._master, bytes(got))

    def close(self) -> None:
        os.write(self._stop_w, b"x")
        self._thread.join()
        for fd in (self._master, self._slave, self._robot, self._stop_r, self._stop_w):
            os.close(fd)


@pytest.fixture(params=["usb", "bluetooth"])
def relay(request: pytest.FixtureRequest) -> Iterator[CorruptingRelay]:
    with Epuck2Emulator("arena", seed=3, bluetooth=request.param == "bluetooth") as emulator:
        assert emulator.pty_path is not None
        relay = CorruptingRelay(emulator.pty_path)
        try:
            yield relay
        finally:
            relay.close()


@pytest.mark.parametrize(("offset", "value", "what"), _BAD)
def test_a_robot_over_a_serial_line_refuses_the_packet_and_goes_on(
    relay: CorruptingRelay, offset: int, value: int, what: str
) -> None:
    with ego.Robot(relay.path) as robot:
        robot.selector.enable(32)
        robot.step(32)
        assert robot.selector.position in (3, 8)
        relay.arm(offset, value)
        with pytest.raises(ProtocolError, match=what):
            robot.step(32)
        robot.step(32)  # the next packet is good again
        assert robot.selector.position in (3, 8)
