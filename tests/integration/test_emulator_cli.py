"""``python -m firmware_sim`` as a separate process: the pty path on stdout, then a dsPIC."""

from __future__ import annotations

import os
import select
import signal
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
import serial

from firmware_sim.cli import main

FULL_STEP = bytes.fromhex("9f bb b3 b2 b1 af 8b 00")  # a E M N O Q u + 0


@contextmanager
def sim_process(tmp_path: Path, *args: str) -> Iterator[tuple[subprocess.Popen[str], str]]:
    proc = subprocess.Popen(
        [sys.executable, "-m", "firmware_sim", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=tmp_path,  # never src/ego, where ego/serial would shadow pyserial
    )
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], 30.0)
        assert ready, "the emulator printed no pty path"
        yield proc, proc.stdout.readline().strip()
    finally:
        if proc.poll() is None:
            proc.terminate()
            proc.wait(timeout=10)
        for pipe in (proc.stdout, proc.stderr):
            if pipe is not None:
                pipe.close()


@contextmanager
def open_port(path: str) -> Iterator[serial.Serial]:
    with serial.Serial(path, 230400, timeout=0.1) as port:
        while port.read(4096):  # the power-on banner, if it is still there
            pass
        yield port


def ask(port: serial.Serial, tx: bytes, size: int) -> bytes:
    """Send ``tx``, read ``size`` bytes, then make sure nothing else follows."""
    port.write(tx)
    port.timeout = 5.0
    reply = port.read(size)
    port.timeout = 0.1
    return reply + port.read(4096)


def test_thesis_process_answers_the_full_step_with_58_bytes(tmp_path: Path) -> None:
    with sim_process(tmp_path, "--firmware", "webots") as (_, path):
        assert os.path.exists(path)
        with open_port(path) as port:
            assert len(ask(port, FULL_STEP, 58)) == 58


def test_overo_process_answers_n_with_20_bytes_and_m_with_none(tmp_path: Path) -> None:
    """protocol.md: on gctronic "N and O return 10 values (20 bytes)", "M returns
    nothing"."""
    with (
        sim_process(tmp_path, "--firmware", "gctronic") as (_, path),
        open_port(path) as port,
    ):
        assert len(ask(port, bytes.fromhex("b2 00"), 20)) == 20
        assert ask(port, bytes.fromhex("b3 00"), 0) == b""
        assert len(ask(port, bytes.fromhex("bb 00"), 4)) == 4  # still in step


def test_sigterm_stops_the_process_and_removes_the_pty(tmp_path: Path) -> None:
    with sim_process(tmp_path) as (proc, path):
        assert os.path.lexists(path)
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=10) == 0
        assert not os.path.lexists(path)
        assert not os.path.exists(os.path.dirname(path))


def test_bad_fault_exits_2_with_a_message(tmp_path: Path) -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "firmware_sim", "--fault", "drop=2"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=30,
    )
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert "bad fault 'drop=2'" in proc.stderr


@pytest.mark.parametrize("fault", ["drop", "drop=x", "jam=0.1", "reset@", "stall=-1"])
def test_each_bad_fault_is_refused_before_a_pty_is_made(
    fault: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["--fault", fault]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.startswith("error: bad fault")


def test_unknown_firmware_is_refused_by_the_parser(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as caught:
        main(["--firmware", "e-puck2"])
    assert caught.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def test_bad_baud_rate_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--baud", "0"]) == 2
    assert "baud rate 0" in capsys.readouterr().err
