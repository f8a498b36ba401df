"""The other ways in: asercom v2 over Bluetooth (selector 3, paced at the F407's 115200
baud UART), ``python -m firmware_sim --robot epuck2``, and the package's independence."""

from __future__ import annotations

import ast
import select
import subprocess
import sys
import time
from pathlib import Path

import serial
from epuck2_wire import WifiClient, ask_serial, batch, command, parse_sensors, read_quiet, say
from helpers import wait_until

import firmware_sim.epuck2
from firmware_sim.epuck2 import Epuck2Emulator
from firmware_sim.world import World


def test_bluetooth_answers_at_the_uart_rate() -> None:
    with Epuck2Emulator(World(seed=4, noise=False), bluetooth=True) as emu:
        assert emu.pty_path is not None
        with serial.Serial(emu.pty_path, timeout=0.2) as port:
            read_quiet(port, 0.05)
            start = time.monotonic()
            reply = ask_serial(port, batch(0x08), 103)
            elapsed = time.monotonic() - start
    assert parse_sensors(reply).selector == 3
    # 2 bytes out and 103 back at 10 bits a byte, 115200 baud (serial_comm.c:44-45).
    assert elapsed >= 105 * 10 / 115200


def test_bluetooth_help_is_the_uart_text() -> None:
    with Epuck2Emulator(World(seed=4), bluetooth=True) as emu:
        assert emu.pty_path is not None
        with serial.Serial(emu.pty_path, timeout=0.2) as port:
            read_quiet(port, 0.05)
            port.write(b"H\r")
            text = read_quiet(port, 0.5).decode()
    assert '"A"               Accelerometer\r\n' in text  # Asercom2.c:1235


def test_wifi_and_bluetooth_together_are_refused() -> None:
    try:
        Epuck2Emulator(wifi=True, bluetooth=True, port=0)
    except ValueError as exc:
        assert "not both" in str(exc)
    else:
        raise AssertionError("an e-puck2 cannot run both")


def _serve(tmp_path: Path, *args: str) -> tuple[subprocess.Popen[str], str]:
    proc = subprocess.Popen(
        [sys.executable, "-m", "firmware_sim", "--robot", "epuck2", *args],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert proc.stdout is not None
    ready, _, _ = select.select([proc.stdout], [], [], 30.0)
    assert ready, "the emulator printed nothing"
    return proc, proc.stdout.readline().strip()


def _stop(proc: subprocess.Popen[str]) -> int:
    proc.terminate()
    code = proc.wait(timeout=10)
    for pipe in (proc.stdout, proc.stderr):
        if pipe is not None:
            pipe.close()
    return code


def test_command_line_serves_wifi_on_the_port_it_prints(tmp_path: Path) -> None:
    proc, url = _serve(tmp_path, "--wifi", "--wifi-port", "0")
    try:
        assert url.startswith("tcp://127.0.0.1:")
        client = WifiClient(("127.0.0.1", int(url.rsplit(":", 1)[1])))
        client.send(command(0))
        assert client.reply() == (0x03, b"")
        client.close()
    finally:
        assert _stop(proc) == 0


def test_command_line_serves_usb_on_the_pty_it_prints(tmp_path: Path) -> None:
    proc, path = _serve(tmp_path, "--world", "maze")
    try:
        with serial.Serial(path, timeout=0.2) as port:
            read_quiet(port, 0.05)
            assert say(port, b"V\r").startswith(b"v,Version 2.0")
    finally:
        assert _stop(proc) == 0
    assert not Path(path).exists()


def test_the_emulator_never_imports_ego() -> None:
    package = Path(firmware_sim.epuck2.__file__).parent
    for source in package.glob("*.py"):
        for node in ast.walk(ast.parse(source.read_text())):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            assert not any(n == "ego" or n.startswith("ego.") for n in names), source


def test_usb_replies_wait_for_a_host_that_reads_late(
    port: serial.Serial,
) -> None:
    # e_uart_char.c:69-74: chSequentialStreamWrite on the USB port waits for the host,
    # so the firmware stalls instead of losing bytes.
    port.write(batch("I") * 40)
    # Replies pile up unread: Linux's line discipline buffer fills (4095 bytes; the rest of
    # the 128 kB waits in the pty's and the firmware's buffers, the firmware stalled).
    assert wait_until(lambda: port.in_waiting >= 4095)
    port.timeout = 5.0
    data = port.read(40 * 3203)
    assert len(data) == 40 * 3203
    assert read_quiet(port, 0.2) == b""
