"""Each face opens each port at its own rate, with only the options its backend takes.

``wb_robot_init()`` and ``overo_serial_init()`` used to pass ``baudrate=230400`` to every
port: a ``replay://`` (or ``zenoh://``) port refused it, and a Webots-firmware port or a
Bluetooth one (``/dev/rfcomm*``) opened at 230400 where the Python face rightly used
115200. The rate of E-GO's own call applies on the Overo's own UART with the stock
firmware only (ego.core.ports.call_baud); every other port opens at its own rate.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from ego import overo
from ego import webots as wb
from ego.backends.serial_line import SerialOptions
from ego.controller import Robot as WebotsRobot
from ego.core.environment import Environment
from ego.core.registry import bind_options
from ego.core.robot import Robot
from ego.faces import default_robot
from ego.faces.default_robot import FaceContext, activate
from ego.faces.runtime import RunOptions
from ego.recording.writer import Recorder
from ego.serial.link import Link
from firmware_sim import Emulator

SEED = 11
EMPTY = Environment()


def _webots_python() -> Robot:
    return WebotsRobot().core


def _webots_c() -> Robot:
    assert wb.wb_robot_init() == 1
    return default_robot.get()


def _ego_c() -> Robot:
    overo.overo_serial_init(230400)  # what every E-GO controller asks for
    return default_robot.get()


#: How each face opens the robot of its context (the port the run's options name).
FACES: dict[str, Callable[[], Robot]] = {
    "webots-python": _webots_python,
    "webots-c": _webots_c,
    "e-go": _ego_c,
}


def _open_with(face: str, context: FaceContext) -> Robot:
    with activate(context):
        return FACES[face]()


class AskedFor:
    """A robot maker for a face context: records the port and options a face asks for,
    and hands back a robot on the emulator (there is no /dev/rfcomm0 here)."""

    def __init__(self) -> None:
        self.asked: list[tuple[str, dict[str, object]]] = []

    def __call__(self, port: str, *, environment: Environment, **options: object) -> Robot:
        self.asked.append((port, options))
        return Robot("sim", seed=SEED)

    def baud(self) -> int:
        """The rate the serial backend opens the port last asked for at."""
        port, options = self.asked[-1]
        return SerialOptions.narrow(bind_options(port, options, EMPTY)).line_baud(port)


@pytest.mark.parametrize("face", FACES)
def test_each_face_opens_a_webots_firmware_port_at_115200(face: str) -> None:
    with Emulator("webots", seed=SEED) as emu:
        context = FaceContext(RunOptions(port=emu.path, firmware="webots"), EMPTY)
        robot = _open_with(face, context)
        try:
            assert isinstance(robot.channel, Link)
            assert robot.channel.transport.baudrate == 115200
        finally:
            robot.close()
            context.close()


@pytest.mark.parametrize("face", FACES)
@pytest.mark.parametrize(
    ("port", "firmware", "baud"),
    [("/dev/rfcomm0", None, 115200), ("/dev/rfcomm3", "gctronic", 230400),
     ("/dev/ttyS0", None, 230400), ("/dev/ttyS0", "gctronic", 230400),
     ("/dev/ttyS0", "webots", 115200)],
)  # fmt: skip
def test_each_face_opens_each_serial_port_at_its_own_rate(
    face: str, port: str, firmware: str | None, baud: int
) -> None:
    maker = AskedFor()
    context = FaceContext(RunOptions(port=port, firmware=firmware), EMPTY, make_robot=maker)
    robot = _open_with(face, context)
    try:
        assert maker.asked[-1][0] == port
        assert maker.baud() == baud
    finally:
        robot.close()
        context.close()


def test_the_e_go_call_sets_the_rate_of_the_overos_own_uart_only() -> None:
    maker = AskedFor()
    context = FaceContext(RunOptions(), EMPTY, make_robot=maker)
    with activate(context):
        for port, asked, opened in [("/dev/ttyS0", 115200, 115200),
                                    ("/dev/ttyO2", 460800, 460800),
                                    ("/dev/rfcomm0", 230400, 115200),
                                    ("/dev/ttyUSB0", 115200, 230400)]:  # fmt: skip
            overo.overo_serial_init(asked, port)
            assert maker.baud() == opened, port
        overo.overo_serial_close()


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Twenty steps of a robot on the emulator, recorded with nothing enabled."""
    path = tmp_path_factory.mktemp("face-ports") / "run.mcap"
    recorder = Recorder(path)
    try:
        with Robot("sim", seed=SEED) as robot:
            recorder.attach(robot)
            for _ in range(20):
                assert robot.step(32) == 0
    finally:
        recorder.close()
    return path


@pytest.mark.parametrize("face", FACES)
def test_each_face_opens_a_replay(face: str, recording: Path) -> None:
    context = FaceContext(RunOptions(port=f"replay://{recording}"), EMPTY)
    robot = _open_with(face, context)
    try:
        assert robot.port == f"replay://{recording}"
        assert [robot.step(32) for _ in range(3)] == [0, 0, 0]
    finally:
        robot.close()
        context.close()
