"""``ego serve`` as a process: serves the emulator over TCP and UDP, stops on SIGTERM."""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import signal
import subprocess
import sys
from pathlib import Path

from ego.app.serve import add_arguments
from ego.backends.remote.channel import RemoteChannel
from ego.seam.batch import Request
from ego.seam.profile import Command
from ego.serial.protocol import encode_batch

#: ``ego serve`` through this module alone, whatever the ``ego`` command wires.
SERVE = (
    "import argparse, sys\n"
    "from ego.app import serve as cli\n"
    "parser = argparse.ArgumentParser()\n"
    "cli.add_arguments(parser)\n"
    "sys.exit(cli.run(parser.parse_args(sys.argv[1:])))\n"
)


def _serve(tmp_path: Path, *args: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-c", SERVE, *args],
        cwd=tmp_path,  # never inside src/ego, where ego/serial shadows pyserial
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "EGO_CAMERA": "none"},
    )


def _urls(process: subprocess.Popen[str]) -> list[str]:
    assert process.stderr is not None
    for line in process.stderr:
        match = re.search(r"ego serve: .* on (.+)$", line)
        if match:
            return match.group(1).split(", ")
    raise AssertionError(f"ego serve exited with {process.wait()} before serving")


def test_defaults_are_loopback_tcp_and_half_a_second() -> None:
    parser = argparse.ArgumentParser()
    add_arguments(parser)
    args = parser.parse_args([])
    assert (args.port, args.listen, args.secret_file, args.deadline_ms) == (None, None, None, 500)


def test_serve_sim_over_tcp_and_udp_then_stop_on_sigterm(tmp_path: Path) -> None:
    process = _serve(
        tmp_path, "--port", "sim", "--listen", "tcp://127.0.0.1:0", "--listen", "udp://127.0.0.1:0"
    )
    try:
        urls = _urls(process)
        assert [u.split(":")[0] for u in urls] == ["tcp", "udp"]
        for url in urls:
            link = RemoteChannel.from_url(url)
            batch = encode_batch([Request(Command.PROXIMITY)], link.profile)
            assert len(batch.decode(link.exchange(batch))[0]) == 8
            link.close()
        process.send_signal(signal.SIGTERM)
        assert process.wait(timeout=10) == 0
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_serving_off_loopback_without_a_secret_is_refused_before_the_robot_opens(
    tmp_path: Path,
) -> None:
    process = _serve(tmp_path, "--port", "/nonexistent/tty", "--listen", "tcp://0.0.0.0:0")
    _, err = process.communicate(timeout=20)
    assert process.returncode == 2
    assert "shared secret" in err and "0.0.0.0" in err


def test_empty_secret_file_is_refused(tmp_path: Path) -> None:
    secret = tmp_path / "secret"
    secret.write_text("\n")
    secret.chmod(0o600)
    process = _serve(tmp_path, "--port", "sim", "--secret-file", str(secret))
    _, err = process.communicate(timeout=20)
    assert process.returncode == 2
    assert "empty" in err


def test_running_out_of_file_descriptors_is_quiet_and_the_client_still_gets_in(
    tmp_path: Path,
) -> None:
    """A socket flood bigger than the server's file-descriptor limit: it keeps a quarter
    of them for strangers, logs the shortage in a line or two, and the client steps."""
    import resource
    import socket

    def low_limit() -> None:
        resource.setrlimit(resource.RLIMIT_NOFILE, (64, 64))

    process = subprocess.Popen(
        [sys.executable, "-c", SERVE, "--port", "sim", "--listen", "tcp://127.0.0.1:0"],
        cwd=tmp_path,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "EGO_CAMERA": "none"},
        preexec_fn=low_limit,
    )
    idle: list[socket.socket] = []
    try:
        url = _urls(process)[0]
        host, port = url.removeprefix("tcp://").rsplit(":", 1)
        for _ in range(300):  # far more than its 64 descriptors
            with contextlib.suppress(OSError):
                idle.append(socket.create_connection((host, int(port)), timeout=1))
        channel = RemoteChannel.from_url(url, connect_timeout_s=5.0)
        try:
            batch = encode_batch([Request(Command.GET_SPEED)], channel.profile)
            for _ in range(10):
                assert batch.decode(channel.exchange(batch)) == [(0, 0)]
        finally:
            channel.close()
    finally:
        for sock in idle:
            sock.close()
        process.send_signal(signal.SIGTERM)
        _, err = process.communicate(timeout=15)
    noise = [line for line in err.splitlines() if "Traceback" in line or "Error" in line]
    assert noise == [], err[-2000:]
    assert len(err.splitlines()) < 40, err[-2000:]


def test_a_controller_that_sends_nothing_ends_when_its_server_is_killed(tmp_path: Path) -> None:
    # A supervised controller whose supervisor was killed stepped on blind for ever: its
    # steps send nothing (no sensor enabled, speeds already set), and its heartbeat's
    # failing pings were only logged. Now they end it after the reconnection window.
    import ego

    process = _serve(tmp_path, "--port", "sim", "--listen", f"unix://{tmp_path / 'robot.sock'}")
    try:
        (url,) = _urls(process)
        with ego.Robot(url, handle_signals=False) as robot:
            robot.motors.set_speed(200, 200)
            assert robot.step(32) == 0
            process.kill()  # nothing of the server runs again, its socket breaks
            process.wait()
            window_s = robot.channel.settings.reconnect_timeout_s
            steps = 0
            while robot.step(32) == 0:  # each step only waits: nothing to send
                steps += 1
                assert steps * 0.032 < 20 * window_s, "the controller never learnt it"
            assert robot.step(32) == -1  # ended, as on a lost link
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
