"""However a controller ends, the robot ends with its wheels stopped and every LED off.

A controller process is started on the emulator, drives the wheels with every LED on,
and is then ended: SIGINT (Ctrl-C), SIGTERM (a service stopping), an uncaught exception,
or, over the network, SIGKILL, which leaves the client no chance to clean up. The
emulator runs in this process, so the test reads the ground truth from its world.

tests/faces/test_face_safe_stop.py covers the Webots Python face on the serial link; here
are the faces it leaves out (the Webots C names, the E-GO functions, a plain
``ego.Robot`` script) and the remote link, over TCP and UDP, through ``ego serve``.

Over the network, the server stops the robot itself when its client goes: at once when a
TCP connection drops, after its deadline when a UDP client falls silent. So that these
tests see the client's own cleanup rather than the server's, their server waits
``PATIENT_DEADLINE_S`` before the deadman acts, far beyond the bounded poll; only the
SIGKILL tests, where the server must do the stopping, use the shipped deadline.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from fakes import FAST_LINK
from helpers import ego_command, spawn, wait_until
from reliability_helpers import read_line

from ego.serial.link import Link
from ego.serial.transport import SerialTransport
from ego.servers.socket.server import DEFAULT_DEADLINE_S, Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator, World

CONTROLLER = Path(__file__).parent / "controllers" / "interrupted_controller.py"
#: A deadman the polls below never wait for: what stops the robot is the client.
PATIENT_DEADLINE_S = 60.0
#: How the controller process ends: its signal and the exit status it must give. ``ego``
#: exits 130 on Ctrl-C; a plain Python script dies of the SIGINT it re-raises.
ENDINGS = {
    "SIGINT": (signal.SIGINT, 130),
    "SIGTERM": (signal.SIGTERM, 128 + signal.SIGTERM),
    "exception": (None, 1),
    "SIGKILL": (signal.SIGKILL, -signal.SIGKILL),
    "SIGINT, plain": (signal.SIGINT, -signal.SIGINT),
}


def is_running(world: World) -> bool:
    return world.speeds != (0, 0) and all(world.leds)


def is_stopped(world: World) -> bool:
    return world.speeds == (0, 0) and not any(world.leds)


@pytest.fixture
def emulator() -> Iterator[Emulator]:
    """The thesis firmware's dsPIC behind a pty, outliving every process that drives it."""
    with Emulator("webots", seed=5) as emu:
        yield emu


def drive_then_end(
    args: list[str], world: World, ending: str, cwd: Path
) -> subprocess.CompletedProcess[str]:
    """Run the controller until it drives with its LEDs on, end it, and wait for its exit."""
    sig, status = ENDINGS[ending]
    with spawn(args, cwd) as proc:
        line = read_line(proc.stdout, timeout_s=20)
        if line.strip() != "running":
            proc.kill()
            _, err = proc.communicate(timeout=10)
            pytest.fail(f"the controller did not start: {line!r}\n{err}")
        assert wait_until(lambda: is_running(world)), (world.speeds, world.leds)
        if sig is None:
            out, err = proc.communicate("go\n", timeout=20)  # the controller then raises
        else:
            proc.send_signal(sig)
            out, err = proc.communicate(timeout=20)
        assert proc.returncode == status, err
        if ending == "exception":
            assert "RuntimeError: a bug in the controller" in err
    return subprocess.CompletedProcess(args, status, out, err)


def assert_stopped(world: World) -> None:
    assert wait_until(lambda: is_stopped(world), timeout_s=10), (
        f"the robot was left running: speeds {world.speeds}, LEDs {world.leds}"
    )


# -- the serial link ---------------------------------------------------------------------------


@pytest.mark.parametrize("ending", ["SIGINT", "SIGTERM", "exception"])
@pytest.mark.parametrize("face", ["c", "overo"], ids=["webots-c-face", "e-go-face"])
def test_a_c_style_controller_ended_on_the_serial_link_stops_the_robot(
    emulator: Emulator, tmp_path: Path, face: str, ending: str
) -> None:
    mode = "raise" if ending == "exception" else "forever"
    run = [*ego_command(), "run", "--port", emulator.path, str(CONTROLLER), face, mode]
    drive_then_end(run, emulator.world, ending, tmp_path)
    assert_stopped(emulator.world)


@pytest.mark.parametrize("ending", ["SIGINT", "exception"])
def test_a_plain_robot_script_ended_on_the_serial_link_stops_the_robot(
    emulator: Emulator, tmp_path: Path, ending: str
) -> None:
    mode = "raise" if ending == "exception" else "forever"
    run = [sys.executable, str(CONTROLLER), "plain", mode, emulator.path]
    drive_then_end(run, emulator.world, ending if mode == "raise" else "SIGINT, plain", tmp_path)
    assert_stopped(emulator.world)


# -- the remote link ---------------------------------------------------------------------------

ServeFactory = Callable[..., Server]


@pytest.fixture
def serve(emulator: Emulator) -> Iterator[ServeFactory]:
    """``serve(deadline_s)``: ``ego serve`` of the emulator, in a thread, on TCP and UDP."""
    with contextlib.ExitStack() as stack:

        def factory(deadline_s: float) -> Server:
            link = Link(SerialTransport(emulator.path), settings=FAST_LINK)
            stack.callback(link.close)
            server = Server(
                link,
                listen=["tcp://127.0.0.1:0", "udp://127.0.0.1:0"],
                deadline_s=deadline_s,
            )
            stack.enter_context(ServerThread(server))
            return server

        yield factory


def url_of(server: Server, kind: str) -> str:
    return next(url for url in server.urls if url.startswith(kind))


@pytest.mark.parametrize("ending", ["SIGINT", "SIGTERM", "exception"])
@pytest.mark.parametrize("kind", ["tcp", "udp"])
def test_a_remote_controller_ended_stops_the_robot_itself(
    emulator: Emulator, serve: ServeFactory, tmp_path: Path, kind: str, ending: str
) -> None:
    server = serve(PATIENT_DEADLINE_S)
    mode = "raise" if ending == "exception" else "forever"
    run = [*ego_command(), "run", "--port", url_of(server, kind), str(CONTROLLER), "webots", mode]
    drive_then_end(run, emulator.world, ending, tmp_path)
    assert_stopped(emulator.world)
    assert server.stats.deadman_stops == 0


@pytest.mark.parametrize("face", ["c", "overo"], ids=["webots-c-face", "e-go-face"])
def test_a_c_style_remote_controller_ended_with_sigterm_stops_the_robot(
    emulator: Emulator, serve: ServeFactory, tmp_path: Path, face: str
) -> None:
    server = serve(PATIENT_DEADLINE_S)
    run = [*ego_command(), "run", "--port", url_of(server, "udp"), str(CONTROLLER), face, "forever"]
    drive_then_end(run, emulator.world, "SIGTERM", tmp_path)
    assert_stopped(emulator.world)
    assert server.stats.deadman_stops == 0


def test_a_killed_tcp_controller_is_stopped_when_its_connection_drops(
    emulator: Emulator, serve: ServeFactory, tmp_path: Path
) -> None:
    server = serve(PATIENT_DEADLINE_S)
    run = [*ego_command(), "run", "--port", url_of(server, "tcp"), str(CONTROLLER), "webots"]
    drive_then_end([*run, "forever"], emulator.world, "SIGKILL", tmp_path)
    assert_stopped(emulator.world)  # long before the deadman could act
    assert server.stats.deadman_stops == 0


def test_a_killed_udp_controller_is_stopped_by_the_deadman(
    emulator: Emulator, serve: ServeFactory, tmp_path: Path
) -> None:
    server = serve(DEFAULT_DEADLINE_S)
    run = [*ego_command(), "run", "--port", url_of(server, "udp"), str(CONTROLLER), "webots"]
    drive_then_end([*run, "forever"], emulator.world, "SIGKILL", tmp_path)
    assert_stopped(emulator.world)
    assert wait_until(lambda: server.stats.deadman_stops == 1)


def test_ego_serve_stops_the_robot_of_a_killed_udp_controller(
    emulator: Emulator, tmp_path: Path
) -> None:
    """The shipped command: ``ego serve`` as a process, its deadman, then its own SIGTERM."""
    serve_cmd = [
        *ego_command(),
        "serve",
        "--port",
        emulator.path,
        "--listen",
        "udp://127.0.0.1:0",
        "--deadline-ms",
        "300",
    ]
    server = subprocess.Popen(
        serve_cmd,
        cwd=tmp_path,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "EGO_CAMERA": "none"},
    )
    try:
        url = ""
        while not url:
            line = read_line(server.stderr, timeout_s=20)
            if not line:
                pytest.fail(f"ego serve did not start (exit {server.poll()})")
            match = re.search(r"^ego serve: .* on (udp://\S+)$", line.strip())
            url = match.group(1) if match else ""
        run = [*ego_command(), "run", "--port", url, str(CONTROLLER), "webots", "forever"]
        drive_then_end(run, emulator.world, "SIGKILL", tmp_path)
        assert_stopped(emulator.world)
        logged = [read_line(server.stderr, timeout_s=20)]
        while logged[-1] and "silent for" not in logged[-1]:
            logged.append(read_line(server.stderr, timeout_s=20))
        assert "silent for" in logged[-1], logged  # the deadman, not a goodbye, stopped it
        server.send_signal(signal.SIGTERM)
        _, err = server.communicate(timeout=20)
        assert server.returncode == 0, err
    finally:
        if server.poll() is None:
            server.kill()
            server.communicate(timeout=10)
