"""docs/guide/troubleshooting.md is this test's data: every row's error is produced for
real and its text compared with the row's (as tests/reliability/test_bad_input_table.py
does for docs/bad_input.md).

Each row names a symptom, the line a user sees (``…`` standing for what varies) and,
in its first cell, the ego error class behind it. A scenario below makes the symptom
happen the way a user meets it: ``ego run`` on a silent pseudo-terminal, on a port held
by another robot, on a pty that answers like a modem, on an emulator that vanishes
mid-run, against an ``ego serve`` that wants a secret. The row's text must be one line
of what ``ego run`` printed, and where the row names a class, opening the same port
with ``ego.Robot`` must raise exactly that class (or ``ego run``'s traceback names it).
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import pty
import re
import select
import shutil
import socket
import subprocess
import sys
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
from helpers import ego_command, message_matches, wait_until

import ego
from ego.nursery import Nursery
from firmware_sim import Emulator

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "guide" / "troubleshooting.md"
HEADER = ["symptom", "what you see", "why", "what to do"]
AVOIDANCE = ROOT / "examples" / "obstacle_avoidance.py"
SECRET = "troubleshooting-secret-0123456789"
WRONG_SECRET = "wrong-but-long-enough"

# -- the table -----------------------------------------------------------------------------


@dataclass(frozen=True)
class Row:
    line: int
    symptom: str  # the first cell up to its " (": the scenario's key
    error: str | None  # the ego error class the first cell names, if any
    seen: str  # the text of the "what you see" code span


_CELL = re.compile(r"(?<!\\)\|")


def parse_rows(text: str) -> list[Row]:
    """Every row of the ``| symptom | what you see | why | what to do |`` table."""
    rows: list[Row] = []
    in_table = False
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.startswith("|"):
            in_table = False
            continue
        cells = [c.strip() for c in _CELL.split(line.strip())[1:-1]]
        if cells == HEADER:
            in_table = True
            continue
        if not in_table or not "".join(cells).strip("-: "):
            continue
        assert len(cells) == len(HEADER), f"troubleshooting.md:{number}: {len(cells)} cells"
        seen = re.fullmatch(r"`([^`]*)`", cells[1])
        assert seen, f"troubleshooting.md:{number}: 'what you see' is not one `code` span"
        error = re.search(r"\(`(\w+Error)`\)", cells[0])
        rows.append(
            Row(number, cells[0].split(" (")[0], error.group(1) if error else None, seen[1])
        )
    return rows


ROWS = parse_rows(DOC.read_text(encoding="utf-8"))




# -- what a user runs ----------------------------------------------------------------------


@dataclass
class Seen:
    """What a scenario produced: ``ego run``'s standard error, and the class of the error
    behind it (None where the row names none)."""

    stderr: str
    error: str | None


def ego_run(
    port: str, *options: str, cwd: Path, controller: Path = AVOIDANCE,
    env: dict[str, str] | None = None, preexec: Callable[[], None] | None = None,
) -> str:  # fmt: skip
    """``ego run --port PORT [options] CONTROLLER``; its standard error."""
    done = subprocess.run(
        [*ego_command(), "run", "--port", port, *options, str(controller)],
        capture_output=True, text=True, timeout=60, cwd=cwd, env=env, preexec_fn=preexec,
    )  # fmt: skip
    assert done.returncode != 0 or "ERROR" in done.stderr, done.stderr
    return done.stderr


PROBE = (
    "import sys, ego\n"
    "try:\n"
    "    ego.Robot(sys.argv[1]).close()\n"
    "except Exception as exc:\n"
    "    print(type(exc).__name__)\n"
)


def raised_by_opening(
    port: str, cwd: Path, env: dict[str, str] | None = None,
    preexec: Callable[[], None] | None = None,
) -> str:  # fmt: skip
    """The class of the error ``ego.Robot(port)`` raises, in a fresh process."""
    done = subprocess.run(
        [sys.executable, "-c", PROBE, port],
        capture_output=True, text=True, timeout=60, cwd=cwd, env=env, preexec_fn=preexec,
    )  # fmt: skip
    return done.stdout.strip()


def without_secret() -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if not k.startswith("EGO_SECRET")}


def without_file_permission_override() -> None:
    """In the child: drop root's power to open files whatever their mode (CAP_DAC_OVERRIDE,
    CAP_DAC_READ_SEARCH) from the bounding set, so that the exec'd program is refused a
    mode-000 port as an ordinary user is. PR_CAPBSET_DROP is prctl option 24."""
    libc = ctypes.CDLL(None, use_errno=True)
    for capability in (1, 2):
        if libc.prctl(24, capability, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP)")


# -- devices that are not e-pucks ----------------------------------------------------------


@contextlib.contextmanager
def pty_answering(answer: bytes | None) -> Iterator[str]:
    """A pseudo-terminal whose far end stays silent (``answer`` None) or answers every line
    with ``answer``, as a modem does; its path."""
    master, slave = pty.openpty()
    path = os.ttyname(slave)
    os.close(slave)
    stop = threading.Event()

    def serve() -> None:
        while not stop.is_set():
            ready, _, _ = select.select([master], [], [], 0.05)
            if not ready:
                continue
            try:
                data = os.read(master, 1024)
            except OSError:  # no one has the slave open: wait for the next opener
                stop.wait(0.05)
                continue
            if answer is not None and b"\n" in data:
                os.write(master, answer * data.count(b"\n"))

    threads = Nursery("the test's pty")
    threads.start_thread(serve, name="test-pty")
    try:
        yield path
    finally:
        stop.set()
        threads.close()
        os.close(master)


# -- the scenarios, one a row --------------------------------------------------------------


def no_answer(tmp: Path, served: Served) -> Seen:
    with pty_answering(None) as port:
        return Seen(ego_run(port, cwd=tmp), raised_by_opening(port, tmp))


def no_such_port(tmp: Path, served: Served) -> Seen:
    port = str(tmp / "ttyNOPE")
    return Seen(ego_run(port, cwd=tmp), raised_by_opening(port, tmp))


def permission_denied(tmp: Path, served: Served) -> Seen:
    preexec = without_file_permission_override if os.geteuid() == 0 else None
    with Emulator("webots", seed=1) as emu:
        os.chmod(emu.path, 0)
        return Seen(
            ego_run(emu.path, cwd=tmp, preexec=preexec),
            raised_by_opening(emu.path, tmp, preexec=preexec),
        )


def port_busy(tmp: Path, served: Served) -> Seen:
    with Emulator("webots", seed=1) as emu, ego.Robot(emu.path):  # the other controller
        return Seen(ego_run(emu.path, cwd=tmp), raised_by_opening(emu.path, tmp))


def not_an_epuck(tmp: Path, served: Served) -> Seen:
    with pty_answering(b"OK\r\n") as port:
        return Seen(ego_run(port, cwd=tmp), raised_by_opening(port, tmp))


def wrong_firmware(tmp: Path, served: Served) -> Seen:
    with Emulator("gctronic", seed=1) as emu:  # the stock firmware in Overo mode
        stderr = ego_run(emu.path, "--firmware", "webots", "--duration", "2", cwd=tmp)
    return Seen(stderr, _traceback_class(stderr))


def unsupported_device(tmp: Path, served: Served) -> Seen:
    controller = tmp / "battery.py"
    controller.write_text("from controller import Robot\nRobot().batterySensorEnable(64)\n")
    with Emulator("webots", seed=1) as emu:
        stderr = ego_run(emu.path, cwd=tmp, controller=controller)
    return Seen(stderr, _traceback_class(stderr))


def link_lost(tmp: Path, served: Served) -> Seen:
    emulator = Emulator("webots", seed=1)
    with emulator:
        proc = subprocess.Popen(
            [*ego_command(), "run", "--port", emulator.path, str(AVOIDANCE)],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=tmp,
        )  # fmt: skip
        try:
            assert wait_until(lambda: emulator.world.speeds != (0, 0), timeout_s=30)
        except BaseException:
            proc.kill()
            raise
    # The emulator is gone, its pty with it: the line vanished under the controller.
    _, stderr = proc.communicate(timeout=60)
    return Seen(stderr, None)


def secret_missing(tmp: Path, served: Served) -> Seen:
    env = without_secret()
    return Seen(ego_run(served.url, cwd=tmp, env=env), raised_by_opening(served.url, tmp, env))


def secret_refused(tmp: Path, served: Served) -> Seen:
    env = {**without_secret(), "EGO_SECRET": WRONG_SECRET}
    return Seen(ego_run(served.url, cwd=tmp, env=env), raised_by_opening(served.url, tmp, env))


def secret_file_readable(tmp: Path, served: Served) -> Seen:
    copy = tmp / "copied-secret"
    shutil.copyfile(served.secret_file, copy)
    copy.chmod(0o644)
    env = {**without_secret(), "EGO_SECRET_FILE": str(copy)}
    return Seen(ego_run(served.url, cwd=tmp, env=env), raised_by_opening(served.url, tmp, env))


def robot_busy(tmp: Path, served: Served) -> Seen:
    env = {**without_secret(), "EGO_SECRET_FILE": str(served.secret_file)}
    first = subprocess.Popen(
        [*ego_command(), "run", "--port", served.url, str(AVOIDANCE)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=tmp, env=env,
    )  # fmt: skip
    try:
        assert wait_until(lambda: served.emulator.world.speeds != (0, 0), timeout_s=30)
        return Seen(ego_run(served.url, cwd=tmp, env=env), raised_by_opening(served.url, tmp, env))
    finally:
        first.terminate()
        first.wait(timeout=30)


def no_server(tmp: Path, served: Served) -> Seen:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        url = f"tcp://127.0.0.1:{probe.getsockname()[1]}"  # free: nothing listens there
    return Seen(ego_run(url, cwd=tmp), raised_by_opening(url, tmp))


def _traceback_class(stderr: str) -> str | None:
    """The error class ``ego run`` names when the controller raised (``FILE: Class: ...``)."""
    found = re.search(r"^ego: error: [^:]+: (\w+): ", stderr, re.M)
    return found.group(1) if found else None


SCENARIOS: dict[str, Callable[[Path, Served], Seen]] = {
    "No answer on the port": no_answer,
    "No such port": no_such_port,
    "Permission denied": permission_denied,
    "Port busy": port_busy,
    "Not an e-puck": not_an_epuck,
    "Wrong firmware given": wrong_firmware,
    "Unsupported device": unsupported_device,
    "Link lost": link_lost,
    "Secret missing": secret_missing,
    "Secret refused": secret_refused,
    "Secret file readable by others": secret_file_readable,
    "Robot busy": robot_busy,
    "No server": no_server,
}


# -- a served robot that wants a secret ----------------------------------------------------


@dataclass
class Served:
    emulator: Emulator
    url: str
    secret_file: Path


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Served]:
    """``ego serve`` on an emulator, on loopback, wanting the shared secret."""
    tmp = tmp_path_factory.mktemp("served")
    secret_file = tmp / "secret"
    secret_file.write_text(SECRET)
    secret_file.chmod(0o600)
    with Emulator("webots", seed=1) as emu:
        server = subprocess.Popen(
            [*ego_command(), "serve", "--port", emu.path, "--listen", "tcp://127.0.0.1:0",
             "--secret-file", str(secret_file)],
            stderr=subprocess.PIPE, text=True, cwd=tmp,
        )  # fmt: skip
        try:
            assert server.stderr is not None
            url = None
            for line in server.stderr:
                match = re.search(r"ego serve: .* on (tcp://\S+)", line)
                if match:
                    url = match.group(1)
                    break
            assert url, f"ego serve exited with {server.wait()} before serving"
            yield Served(emu, url, secret_file)
        finally:
            server.terminate()
            server.communicate(timeout=30)


# -- the tests -----------------------------------------------------------------------------


@pytest.mark.parametrize("row", ROWS, ids=[f"L{r.line}: {r.symptom}" for r in ROWS])
def test_each_row_is_what_ego_says(row: Row, served: Served, tmp_path: Path) -> None:
    assert row.symptom in SCENARIOS, f"no scenario produces {row.symptom!r}"
    seen = SCENARIOS[row.symptom](tmp_path, served)
    lines = seen.stderr.splitlines()
    assert any(message_matches(row.seen, line) for line in lines), (
        f"no line of ego run's output says {row.seen!r}:\n{seen.stderr}"
    )
    assert seen.error == row.error, f"the error is {seen.error}, the row names {row.error}"


def test_every_scenario_has_its_row() -> None:
    assert sorted(SCENARIOS) == sorted(row.symptom for row in ROWS)
    assert len({row.symptom for row in ROWS}) == len(ROWS), "a symptom is listed twice"


@pytest.mark.parametrize(
    ("documented", "actual", "matches"),
    [
        ("nothing answers on … port?", "nothing answers on /dev/pts/3: is this its port?", True),
        ("held by process … (…): one", "held by process 12 (ego run): one", True),
        ("outside 0..2", "outside 0..9", False),
        ("b … a", "a b", False),
    ],
)  # fmt: skip
def test_a_message_holds_the_documented_pieces_in_order(
    documented: str, actual: str, matches: bool
) -> None:
    assert message_matches(documented, actual) is matches
