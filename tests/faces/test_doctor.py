"""``ego doctor`` (issue 34, item 5): one line a check, ok or what to do, and a status that
says whether a controller can run; the firmware probe against the emulator on a pty."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers import ego_command, spawn

from ego.app.doctor import check_memory, check_python, holders, version_tuple

#: ``ego`` with the import of one module refused, as where its package is not installed.
WITHOUT = (
    "import sys; sys.modules[sys.argv.pop(1)] = None; "
    "from ego.app.cli import main; sys.exit(main(sys.argv[1:]))"
)


@pytest.fixture
def emulated_port(tmp_path: Path) -> Iterator[str]:
    """``ego sim`` in another process: the pty it serves (its first line)."""
    with spawn([*ego_command(), "sim", "--firmware", "gctronic"], tmp_path) as proc:
        assert proc.stdout is not None
        yield proc.stdout.readline().strip()


def _doctor(*words: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*ego_command(), "doctor", *words], cwd=cwd,
                          capture_output=True, text=True, timeout=120)  # fmt: skip


def _line(output: str, what: str) -> str:
    (found,) = [line for line in output.splitlines() if line.split(":")[0].split()[-1] == what]
    return found


def test_the_emulated_robot_answers_and_a_controller_can_run(
    emulated_port: str, tmp_path: Path
) -> None:
    done = _doctor("--port", emulated_port, cwd=tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    firmware = _line(done.stdout, "firmware")
    assert firmware.startswith("ok    firmware: gctronic") and "selector 10" in firmware
    assert _line(done.stdout, "port").startswith("ok ")
    assert done.stdout.splitlines()[-1] == "ego doctor: a controller can run"


def test_a_missing_port_fails_with_what_to_do(tmp_path: Path) -> None:
    done = _doctor("--port", str(tmp_path / "ttyS0"), cwd=tmp_path)
    assert done.returncode == 1
    port = _line(done.stdout, "port")
    assert port.startswith("fail  serial port:") and "EGO_PORT or --port" in port
    assert "firmware" not in done.stdout  # no probe of a port that is not there
    assert done.stdout.splitlines()[-1] == "ego doctor: 1 to fix first"


def test_a_missing_dependency_is_a_failure_naming_the_debian_package(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-c", WITHOUT, "smbus2", "doctor", "--no-probe"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)  # fmt: skip
    assert _line(done.stdout, "smbus2") == (
        "fail  smbus2: not installed: apt-get install python3-smbus2"
    )
    assert done.returncode == 1


def test_a_missing_extra_is_a_note_and_fails_nothing(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-c", WITHOUT, "aiohttp", "doctor", "--no-probe"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)  # fmt: skip
    line = _line(done.stdout, "aiohttp")
    assert line.startswith("note  aiohttp: not installed") and "ego[dashboard]" in line
    assert "fail  aiohttp" not in done.stdout


def test_holders_names_the_process_that_has_the_port_open(tmp_path: Path) -> None:
    port = tmp_path / "ttyS0"
    port.write_bytes(b"")
    script = f"f = open({str(port)!r}); print('open', flush=True); input()"
    with spawn([sys.executable, "-c", script], tmp_path) as proc:
        assert proc.stdout is not None and proc.stdout.readline() == "open\n"
        assert any(h.startswith(f"{proc.pid} ") for h in holders(port))
        proc.kill()
        proc.wait(timeout=10)
    assert holders(port) == []


def test_versions_and_python_and_memory_lines() -> None:
    assert version_tuple("4.6.0+dfsg") == (4, 6, 0)
    assert version_tuple("1.24.2") > version_tuple("1.9")
    assert check_python((3, 9, 18)).status == "fail"
    assert check_python((3, 10, 0)).status == "ok"


def test_low_memory_is_a_note(tmp_path: Path) -> None:
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:  248000 kB\nMemAvailable:   40960 kB\n")
    line = check_memory(meminfo)
    assert (line.status, line.said.split()[0]) == ("note", "40")
    meminfo.write_text("MemAvailable:   204800 kB\n")
    assert check_memory(meminfo).status == "ok"
