"""docs/guide/pipuck.md's troubleshooting table is this test's data: each row's error is
produced for real, by ``ego run --port pipuck`` against the emulated Pi-puck in the state
the row describes, and the line it printed compared with the row's (``…`` stands for
what varies), as tests/docs/test_troubleshooting_table.py does for the main guide."""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest
from helpers import ego_command, message_matches, wait_until
from pipuck_support import EXAMPLES, env_of

from firmware_sim.pipuck import PipuckEmulator

DOC = Path(__file__).resolve().parents[2] / "docs" / "guide" / "pipuck.md"
HEADER = ["symptom", "what you see", "why", "what to do"]
AVOIDANCE = str(EXAMPLES / "obstacle_avoidance.py")


def rows() -> dict[str, tuple[str, str]]:
    """symptom -> (the error class the first cell names, the "what you see" text)."""
    found: dict[str, tuple[str, str]] = {}
    in_table = False
    for line in DOC.read_text(encoding="utf-8").splitlines():
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]
        if cells == HEADER:
            in_table = True
        elif in_table and cells and not set("".join(cells)) <= set("-: "):
            error = re.search(r"\(`(\w+Error)`\)", cells[0])
            seen = re.fullmatch(r"`([^`]*)`", cells[1])
            assert error and seen, line
            found[cells[0].split(" (")[0]] = (error[1], seen[1])
        elif not line.startswith("|"):
            in_table = False
    return found




def _run(emu: PipuckEmulator, controller: str, tmp: Path) -> str:
    done = subprocess.run([*ego_command(), "run", "--port", "pipuck", controller],
                          env=env_of(emu), capture_output=True, text=True, timeout=120,
                          cwd=tmp)  # fmt: skip
    assert done.returncode != 0, done.stderr
    return done.stderr


def _no_bus(emu: PipuckEmulator, tmp: Path) -> str:
    emu.set_bus_present(12, False)
    return _run(emu, AVOIDANCE, tmp)


def _denied(emu: PipuckEmulator, tmp: Path) -> str:
    emu.deny_access()
    return _run(emu, AVOIDANCE, tmp)


def _nothing_at_0x1f(emu: PipuckEmulator, tmp: Path) -> str:
    emu.set_present(0x1F, False)
    return _run(emu, AVOIDANCE, tmp)


def _checksums(emu: PipuckEmulator, tmp: Path) -> str:
    child = subprocess.Popen(
        [*ego_command(), "run", "--port", "pipuck", AVOIDANCE],
        env=env_of(emu), stderr=subprocess.PIPE, text=True, cwd=tmp,
    )  # fmt: skip
    try:
        assert wait_until(lambda: emu.truth.speeds != (0, 0), 30)
        emu.corrupt_next_reply(10**6)  # every reply from now on
        return child.communicate(timeout=120)[1]
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()


def _unsupported(emu: PipuckEmulator, tmp: Path) -> str:
    controller = tmp / "magnetometer.py"
    controller.write_text("import ego\nrobot = ego.Robot()\nrobot.magnetometer.enable(32)\n")
    return _run(emu, str(controller), tmp)


SCENARIOS: dict[str, Callable[[PipuckEmulator, Path], str]] = {
    "No I2C bus": _no_bus,
    "Permission denied": _denied,
    "Nothing answers at 0x1F": _nothing_at_0x1f,
    "Replies keep failing their checksum": _checksums,
    "A device the path cannot serve": _unsupported,
}


def test_every_row_has_its_scenario() -> None:
    assert set(rows()) == set(SCENARIOS)


@pytest.mark.parametrize("symptom", sorted(SCENARIOS))
def test_each_row_is_what_ego_says(symptom: str, tmp_path: Path) -> None:
    error, documented = rows()[symptom]
    with PipuckEmulator("epuck2", "current", seed=1) as emu:
        stderr = SCENARIOS[symptom](emu, tmp_path)
        raised = error if f"{error}:" in stderr else _raised_by_opening(emu)
    said = [line for line in stderr.splitlines() if line.startswith("ego: error:")]
    assert len(said) == 1, stderr
    assert message_matches(documented, said[0]), (
        f"the guide says\n  {documented}\nego said\n  {said[0]}"
    )
    assert raised == error
    if error not in ("ChecksumError", "UnsupportedDeviceError"):  # not the controller's own
        assert "Traceback" not in stderr, stderr


def _raised_by_opening(emu: PipuckEmulator) -> str:
    """The class of the error ``ego.Robot("pipuck")`` raises, in a child in ``emu``'s state."""
    probe = ("import ego\ntry:\n    ego.Robot('pipuck', camera_device='none').close()\n"
             "except Exception as exc:\n    print(type(exc).__name__)\n")  # fmt: skip
    done = subprocess.run([sys.executable, "-c", probe], env=env_of(emu), capture_output=True,
                          text=True, timeout=120)  # fmt: skip
    return done.stdout.strip()
