"""The Pi-puck emulator tests' client process and quiet world."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
from pathlib import Path
from typing import Any

from firmware_sim.wheels import WheelModel
from firmware_sim.world import World

__all__ = ["Client", "quiet_world"]

CLIENT = Path(__file__).with_name("pipuck_client.py")
#: A guard against a hung child, not a timing assumption: an answer takes milliseconds.
HANG_S = 120.0


class Client:
    """A child process evaluating one expression a line (pipuck_client.py)."""

    def __init__(self, env: dict[str, str]) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, str(CLIENT)],
            env={**os.environ, **env},
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            bufsize=0,
        )
        self._pending = b""
        assert self._answer() == "ready"

    def _answer(self) -> Any:
        assert self.proc.stdout is not None
        fd = self.proc.stdout.fileno()
        while b"\n" not in self._pending:
            ready, _, _ = select.select([fd], [], [], HANG_S)
            chunk = os.read(fd, 65536) if ready else b""
            if not chunk:
                self.proc.kill()
                raise AssertionError(f"the client died or hung: {self.close()}")
            self._pending += chunk
        line, _, self._pending = self._pending.partition(b"\n")
        return json.loads(line)

    def __call__(self, expression: str) -> Any:
        assert self.proc.stdin is not None and "\n" not in expression
        self.proc.stdin.write(expression.encode() + b"\n")
        return self._answer()

    def close(self) -> str:
        """End the child (communicate closes its stdin); its standard error."""
        if self.proc.returncode is not None:
            return ""
        try:
            _, err = self.proc.communicate(timeout=HANG_S)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        return err.decode(errors="replace")


def quiet_world() -> World:
    """No sensor noise and ideal wheels: every value follows from the geometry."""
    return World(seed=1, noise=False, wheels=WheelModel(slip=0, encoder_noise_steps=0))
