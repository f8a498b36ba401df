"""``python -m firmware_sim pipuck`` serves an emulated Pi-puck and prints the
environment a process needs to reach it."""

from __future__ import annotations

import os
import shlex
import signal
import subprocess
import sys
from pathlib import Path

from pipuck_harness import Client


def test_the_command_line_serves_until_terminated(tmp_path: Path) -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "firmware_sim", "pipuck", "--robot", "epuck", "--buses",
         "legacy", "--seed", "3"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert proc.stdout is not None
        env: dict[str, str] = {}
        while True:
            line = proc.stdout.readline()
            assert line, proc.stderr.read() if proc.stderr else "no output"
            if line.startswith("#"):
                assert "/dev/i2c-4" in line and "/dev/i2c-3" in line
                break
            name, _, value = line.removeprefix("export ").strip().partition("=")
            env[name] = shlex.split(value)[0]
        assert set(env) == {"LD_PRELOAD", "FIRMWARE_SIM_I2C_SOCKET", "FIRMWARE_SIM_SYSFS_ROOT"}
        client = Client(env)
        try:
            client("bus(4).write_word_data(0x1F, 2, 1200)")
            assert client("bus(4).read_word_data(0x1F, 2)") == 1000  # York's clamp
        finally:
            client.close()
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == 0
        assert not os.path.exists(env["FIRMWARE_SIM_I2C_SOCKET"])
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.communicate()


def test_a_bad_option_is_one_line() -> None:
    out = subprocess.run([sys.executable, "-m", "firmware_sim", "pipuck", "--imu-address", "0x50"],
                         capture_output=True, text=True, timeout=60)  # fmt: skip
    assert out.returncode == 2
    assert out.stderr.strip() == "error: the MPU-9250 answers at 0x68 or 0x69, not 0x50"
