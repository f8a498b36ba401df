"""docs/bad_input.md is this test's data: every row is run, and must raise what it says.

Each row of the document's tables is a Python expression (the ``call`` column), the
error it must raise (``raises``) and the message a user sees (``message``, with ``…``
standing for text left out). The expression is evaluated against the names of
:func:`namespace`: robots on emulators, the faces, a camera, ports that are not
e-pucks, a served robot, and the ``ego`` command. So the document cannot drift from
the code: change a message and this test names the row to update.

Rows under a heading that says "Awaiting a fix" describe what ego should say but does
not yet; they are strict xfails, so the fix turns them into failures until they move
to their section.
"""

from __future__ import annotations

import builtins
import contextlib
import io
import logging
import os
import re
import subprocess
import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from dashboard_probe import DashboardProbe, HttpAnswer
from helpers import IN_PROCESS_LINK, ego_command, message_matches
from hostile_files import make as make_hostile
from reliability_helpers import echo_device, modem_device, silent_device
from remote_probes import pipelined, udp_request

import ego
import ego.errors
import ego.overo
import ego.webots
from ego.app.cli import main as ego_main
from ego.camera import Camera
from ego.camera.config import parse_configuration
from ego.controller import DifferentialWheels
from ego.faces import default_robot, runtime
from ego.recording.reader import Recording
from ego.serial.link import Link
from ego.serial.transport import SerialTransport
from ego.servers.dashboard.live import RobotFeed
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator
from firmware_sim.camera import SimulatedSource

DOC = Path(__file__).resolve().parents[2] / "docs" / "bad_input.md"
HEADER = ["call", "raises", "message"]
PENDING_HEADING = "awaiting a fix"
#: The shared secret of the served robot.
SECRET = "s3cret-s3cret-s3cret"

# -- the table -----------------------------------------------------------------------------


@dataclass(frozen=True)
class Row:
    """One row of the document: where it is, what to run, and what must come of it."""

    line: int
    section: str
    call: str
    raises: str
    message: str

    @property
    def pending(self) -> bool:
        return PENDING_HEADING in self.section.lower()

    @property
    def id(self) -> str:
        return f"L{self.line}: {self.call}"


_CELL = re.compile(r"(?<!\\)\|")
_CODE = re.compile(r"`([^`]*)`")


def _cells(line: str) -> list[str]:
    parts = _CELL.split(line.strip())
    return [p.strip().replace("\\|", "|") for p in parts[1:-1]]


def _code(cell: str, line: int) -> str:
    match = _CODE.fullmatch(cell)
    if match is None:
        raise ValueError(f"docs/bad_input.md:{line}: expected one `code` span, got {cell!r}")
    return match.group(1)


def parse_rows(text: str) -> list[Row]:
    """Every row of every ``| call | raises | message |`` table, with its ``##`` section."""
    rows: list[Row] = []
    section = ""
    in_table = False
    for number, line in enumerate(text.splitlines(), start=1):
        if line.startswith("#"):
            section = line.lstrip("#").strip()
            in_table = False
            continue
        if not line.startswith("|"):
            in_table = False
            continue
        cells = _cells(line)
        if cells == HEADER:
            in_table = True
            continue
        if not in_table or not "".join(cells).strip("-: "):
            continue  # another table, or the separator row
        if len(cells) != len(HEADER):
            raise ValueError(f"docs/bad_input.md:{number}: {len(cells)} cells, expected 3")
        call, raises, message = cells
        rows.append(Row(number, section, _code(call, number), raises, _code(message, number)))
    return rows


ROWS = parse_rows(DOC.read_text(encoding="utf-8"))




def error_class(name: str) -> type[BaseException]:
    """An ``ego.errors`` class by name, else a builtin exception."""
    cls = getattr(ego.errors, name, None) or getattr(builtins, name, None)
    if not (isinstance(cls, type) and issubclass(cls, BaseException)):
        raise ValueError(f"{name!r} is neither an ego error nor a builtin exception")
    return cls


# -- the names a row's expression sees -----------------------------------------------------


class Namespace(dict[str, Any]):
    """Names for the rows' expressions; one that a row lacks says which exist."""

    def __missing__(self, key: str) -> Any:
        if hasattr(builtins, key):
            raise KeyError(key)  # let eval find the builtin
        raise NameError(f"{key!r} is not a name of the bad-input table: {', '.join(self)}")


@dataclass
class CliResult:
    """How an ``ego`` command line ended: its exit status and what it printed on stderr."""

    status: int
    stderr: str


def ego_cli(tmp: Path) -> Callable[..., CliResult]:
    """``ego(*args)``: the ``ego`` command. ``ego run``, ``ego replay`` and ``ego demo``
    run in a child process (they run a controller, and close the process's default robot
    when it ends); the rest in this process."""

    def run(*args: str) -> CliResult:
        if args and args[0] in ("run", "replay", "demo"):
            done = subprocess.run(
                [*ego_command(), *args],
                cwd=tmp,
                capture_output=True,
                text=True,
                timeout=60,
                check=False,
            )
            return CliResult(done.returncode, done.stderr)
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            try:
                status = ego_main(list(args))
            except SystemExit as exc:  # argparse refuses by exiting
                status = exc.code if isinstance(exc.code, int) else 1
        return CliResult(status, err.getvalue())

    return run


CONTROLLERS = {
    # A Webots controller: Robot() opens the port that ``ego run --port`` names.
    "webots_controller.py": "from controller import Robot\nRobot()\n",
    # An E-GO controller: overo_serial_init(baudrate, None) opens it too.
    "overo_controller.py": "from ego.overo import overo_serial_init\n"
    "overo_serial_init(230400, None)\n",
}


@pytest.fixture(scope="module")
def namespace() -> Iterator[Namespace]:
    """Everything the table's expressions name, built once for the module.

    Nothing a row does may change what later rows see: rows are refused before any
    state changes, and the few that open something close it.
    """
    saved_options = default_robot.current_options()
    saved_env = {k: os.environ.pop(k) for k in ("EGO_SECRET", "EGO_SECRET_FILE") if k in os.environ}
    with contextlib.ExitStack() as stack, tempfile.TemporaryDirectory(prefix="ego-bad-") as tmp:
        stack.callback(os.environ.update, saved_env)
        stack.callback(default_robot.set_options, saved_options)
        tmp_path = Path(tmp)
        for name, text in CONTROLLERS.items():
            (tmp_path / name).write_text(text)

        emu = stack.enter_context(Emulator("webots", seed=3))
        overo_emu = stack.enter_context(Emulator("gctronic", seed=3))
        robot = stack.enter_context(ego.Robot(emu.path, link_settings=IN_PROCESS_LINK))
        overo_robot = stack.enter_context(ego.Robot(overo_emu.path, link_settings=IN_PROCESS_LINK))

        # The faces: a Webots controller's Robot and the C faces' default robot, each on
        # its own built-in emulator ("sim"), so that the camera is the emulator's.
        default_robot.set_options(runtime.RunOptions(port="sim", seed=3))
        controller = DifferentialWheels()
        stack.callback(controller.cleanup)
        controller.getDevice("camera").enable(32)
        controller.step(32)
        # ego run --strict's: one Robot a process, so in a face context of its own.
        with default_robot.activate(
            default_robot.FaceContext(runtime.RunOptions(port="sim", seed=3, strict=True))
        ):
            strict_controller = DifferentialWheels()
        stack.callback(strict_controller.cleanup)
        ego.webots.wb_robot_init()
        stack.callback(default_robot.close)
        # Through the E-GO face, which keeps the full 640x480 its rows speak of (the
        # Webots faces would ask Webots' 52x39).
        ego.overo.overo_camera_enable("camera", 32)
        ego.webots.wb_robot_step(32)

        camera = stack.enter_context(Camera(source=SimulatedSource(emu.world), width=64, height=48))
        camera.enable(32)
        camera.update(0)

        # A served robot that wants a secret, and one that does not, driven by remote_robot.
        served_emu = stack.enter_context(Emulator("webots", seed=3))
        served_link = Link(SerialTransport(served_emu.path), settings=IN_PROCESS_LINK)
        stack.callback(served_link.close)
        server = Server(
            served_link, listen=["tcp://127.0.0.1:0", "udp://127.0.0.1:0"], secret=SECRET
        )
        served = stack.enter_context(ServerThread(server))
        open_emu = stack.enter_context(Emulator("webots", seed=3))
        open_link = Link(SerialTransport(open_emu.path), settings=IN_PROCESS_LINK)
        stack.callback(open_link.close)
        open_server = stack.enter_context(
            ServerThread(
                Server(
                    open_link,
                    listen="tcp://127.0.0.1:0",
                    frame_source=SimulatedSource(open_emu.world),
                )
            )
        )
        remote_robot = stack.enter_context(ego.Robot(open_server.url))
        epuck2_robot = stack.enter_context(ego.Robot("sim", robot="epuck2", seed=3))

        dashboard = stack.enter_context(DashboardProbe(RobotFeed(robot)))

        devices = {
            "silent_port": stack.enter_context(silent_device()).path,
            "echo_port": stack.enter_context(echo_device()).path,
            "modem_port": stack.enter_context(modem_device()).path,
        }

        def config_file(text: str | bytes) -> str:
            """A camera configuration file holding ``text`` (or raw bytes); its path."""
            path = tmp_path / "camera.conf"
            path.write_bytes(text if isinstance(text, bytes) else text.encode("utf-8"))
            return str(path)

        hostile_dir = tmp_path / "hostile"
        hostile_dir.mkdir()

        yield Namespace(
            ego=ego,
            Robot=ego.Robot,
            robot=robot,
            overo_robot=overo_robot,
            overo_emulator_port=overo_emu.path,
            controller=controller,
            strict_controller=strict_controller,
            webots=ego.webots,
            overo=ego.overo,
            Camera=Camera,
            SimulatedSource=SimulatedSource,
            world=emu.world,
            camera=camera,
            parse_configuration=parse_configuration,
            config_file=config_file,
            tmp=tmp,
            server_tcp=served.urls[0],
            server_udp=served.urls[1],
            remote_robot=remote_robot,
            epuck2_robot=epuck2_robot,
            pipelined=pipelined,
            udp_request=udp_request,
            ego_cli=ego_cli(tmp_path),
            dashboard_get=dashboard.get,
            dashboard_sockets=dashboard.sockets,
            dashboard_send=dashboard.send,
            Recording=Recording,
            hostile=lambda name: make_hostile(hostile_dir, name),
            **devices,
        )


# -- the rows ------------------------------------------------------------------------------


def _close(result: object) -> None:
    """A row that unexpectedly opened something (a robot) must not leave it open."""
    close = getattr(result, "close", None)
    if callable(close) and not isinstance(result, type):
        close()


def check_row(row: Row, names: Namespace, caplog: pytest.LogCaptureFixture) -> None:
    if row.raises.startswith("exit"):
        status = int(_code(row.raises.removeprefix("exit").strip(), row.line))
        result = eval(row.call, {}, names)
        assert isinstance(result, CliResult), f"{row.call} is not an ego_cli(...) call"
        assert result.status == status, f"exit {result.status}, stderr: {result.stderr}"
        assert message_matches(row.message, result.stderr), (
            f"stderr does not say {row.message!r}:\n{result.stderr}"
        )
        return
    if row.raises.startswith("HTTP"):
        status = int(_code(row.raises.removeprefix("HTTP").strip(), row.line))
        result = eval(row.call, {}, names)
        assert isinstance(result, HttpAnswer), f"{row.call} is not a dashboard_...(...) call"
        assert result.status == status, f"HTTP {result.status}: {result.text}"
        assert message_matches(row.message, result.text), f"it says {result.text!r}"
        return
    if row.raises.startswith("returns"):
        expected = eval(_code(row.raises.removeprefix("returns").strip(), row.line))
        with caplog.at_level(logging.WARNING):
            result = eval(row.call, {}, names)
        assert result == expected, f"returned {result!r}, not {expected!r}"
        logged = "\n".join(r.getMessage() for r in caplog.records)
        assert message_matches(row.message, logged), (
            f"the log does not say {row.message!r}:\n{logged}"
        )
        return
    cls = error_class(_code(row.raises, row.line))
    try:
        result = eval(row.call, {}, names)
    except Exception as exc:  # the error under test, whatever it is
        assert type(exc) is cls, f"raised {type(exc).__name__}: {exc}"
        assert message_matches(row.message, str(exc)), f"the message is {str(exc)!r}"
    else:
        _close(result)
        raise AssertionError(f"no error: returned {result!r}")


@pytest.mark.parametrize(
    "row",
    [
        pytest.param(
            row,
            id=row.id,
            marks=[pytest.mark.xfail(raises=AssertionError, strict=True)] if row.pending else [],
        )
        for row in ROWS
    ],
)
def test_row_raises_its_documented_error(
    row: Row, namespace: Namespace, caplog: pytest.LogCaptureFixture
) -> None:
    check_row(row, namespace, caplog)


# -- the document itself -------------------------------------------------------------------


def test_every_entry_point_has_its_section() -> None:
    sections = {row.section for row in ROWS}
    for expected in (
        "The core",
        "The Webots Python face",
        "The Webots C face",
        "The E-GO face",
        "The camera",
        "Camera configuration files",
        "Ports",
        "Remote robots",
        "The ego command",
        "The emulator's command",
        "The dashboard",
    ):
        assert any(s.startswith(expected) for s in sections), f"no section {expected!r}"
    assert len(ROWS) >= 100


def test_every_row_names_a_real_error_and_is_unique() -> None:
    # A pending row may repeat a call whose behaviour today is documented in its section.
    calls = [row.call for row in ROWS if not row.pending]
    assert len(calls) == len(set(calls)), "a call is documented twice"
    for row in ROWS:
        if not row.raises.startswith(("exit", "returns", "HTTP")):
            error_class(_code(row.raises, row.line))


@pytest.mark.parametrize(
    ("documented", "actual", "matches"),
    [
        ("speed 1200 steps/s is outside", "left speed 1200 steps/s is outside -1000..1000", True),
        ("valid names: ps0, … camera", "valid names: ps0, ps1, ps2, camera", True),
        ("valid names: camera … ps0", "valid names: ps0, ps1, ps2, camera", False),
        ("outside 0..2", "outside 0..9", False),
    ],
)
def test_a_message_holds_the_documented_pieces_in_order(
    documented: str, actual: str, matches: bool
) -> None:
    assert message_matches(documented, actual) is matches


def test_the_parser_reads_sections_escaped_pipes_and_skips_other_tables() -> None:
    text = (
        "## One\n\n| call | raises | message |\n| --- | --- | --- |\n"
        "| `f(1)` | `OutOfRangeError` | `a \\| b` |\n\n"
        "| name | meaning |\n| --- | --- |\n| `robot` | a robot |\n\n"
        "## Awaiting a fix\n\n| call | raises | message |\n| --- | --- | --- |\n"
        "| `g()` | exit `2` | `usage` |\n"
    )
    first, second = parse_rows(text)
    assert (first.section, first.call, first.message, first.pending) == (
        "One",
        "f(1)",
        "a | b",
        False,
    )
    assert (second.raises, second.pending) == ("exit `2`", True)
