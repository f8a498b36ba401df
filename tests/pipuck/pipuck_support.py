"""Running ego against the emulated Pi-puck: ``ego run`` and small scripts in a child
process whose environment loads the emulator's shim (and names its sysfs root)."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

from helpers import ego_command

from firmware_sim.pipuck import PipuckEmulator

__all__ = ["CONTROLLERS", "EXAMPLES", "Runner", "env_of"]

ROOT = Path(__file__).resolve().parents[2]
CONTROLLERS = Path(__file__).with_name("controllers")
EXAMPLES = ROOT / "examples"


def env_of(emu: PipuckEmulator) -> dict[str, str]:
    """This process's environment with the emulator's (the shim, its socket) and
    ``EGO_SYSFS`` at its sysfs root's ``sys``."""
    return {**os.environ, **emu.environ(), "EGO_SYSFS": str(emu.sysfs_root / "sys")}


class Runner:
    """Child processes in ``emu``'s environment, in ``folder``."""

    def __init__(self, emu: PipuckEmulator, folder: Path) -> None:
        self.emu = emu
        self.folder = folder
        self.env = env_of(emu)
        self.children: list[subprocess.Popen[str]] = []

    def ego(self, *args: str, timeout_s: float = 120) -> subprocess.CompletedProcess[str]:
        """``ego ARGS``, to its end."""
        return subprocess.run([*ego_command(), *args], env=self.env, cwd=self.folder,
                              capture_output=True, text=True, timeout=timeout_s)  # fmt: skip

    def start_ego(self, *args: str) -> subprocess.Popen[str]:
        """``ego ARGS``, started in a session of its own (:meth:`close` ends the whole
        session, the supervised controller with its supervisor)."""
        child = subprocess.Popen(
            [*ego_command(), *args], env=self.env, cwd=self.folder,
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
        )  # fmt: skip
        self.children.append(child)
        return child

    def script(self, code: str, timeout_s: float = 120) -> Any:
        """Run ``code`` (Python, ego imported as ``ego``) in a child; the JSON of its last
        line of output. An exception is printed as ``{"error": class, "message": text}``."""
        wrapped = "import json, sys, ego\ntry:\n" + textwrap.indent(textwrap.dedent(code), "    ")
        wrapped += (
            "\nexcept Exception as exc:\n"
            "    print(json.dumps({'error': type(exc).__name__, 'message': str(exc)}))\n"
        )
        done = subprocess.run([sys.executable, "-c", wrapped], env=self.env, cwd=self.folder,
                              capture_output=True, text=True, timeout=timeout_s)  # fmt: skip
        lines = done.stdout.strip().splitlines()
        assert lines, f"the script printed nothing; stderr:\n{done.stderr}"
        return json.loads(lines[-1])

    def close(self) -> None:
        """Kill what is left of each child's session (a controller its killed supervisor
        left behind still holds the pipes: communicate would wait for it for ever)."""
        for child in self.children:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(child.pid, signal.SIGKILL)
            child.communicate(timeout=60)
