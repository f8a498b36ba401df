"""The Pi-puck emulator tests' client process and quiet world."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

from firmware_sim.wheels import WheelModel
from firmware_sim.world import World

__all__ = ["Client", "quiet_world"]

CLIENT = Path(__file__).with_name("pipuck_client.py")


class Client:
    """A child process evaluating one expression a line (pipuck_client.py)."""

    def __init__(self, env: dict[str, str]) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, str(CLIENT)],
            env={**os.environ, **env},
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        assert self._answer() == "ready"

    def _answer(self) -> Any:
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        if not line:
            raise AssertionError(f"the client died: {self.close()}")
        return json.loads(line)

    def __call__(self, expression: str) -> Any:
        assert self.proc.stdin is not None and "\n" not in expression
        self.proc.stdin.write(expression + "\n")
        self.proc.stdin.flush()
        return self._answer()

    def close(self) -> str:
        """End the child (communicate closes its stdin); its standard error."""
        if self.proc.returncode is not None:
            return ""
        try:
            _, err = self.proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        return err


def quiet_world() -> World:
    """No sensor noise and ideal wheels: every value follows from the geometry."""
    return World(seed=1, noise=False, wheels=WheelModel(slip=0, encoder_noise_steps=0))
