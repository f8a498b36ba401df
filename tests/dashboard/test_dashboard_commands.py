"""The commands that serve a dashboard: ego demo (on by default, its URL printed), ego run
--dashboard, ego replay; each page is reached while the command runs."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import aiohttp
from dashboard_support import LineReader
from helpers import ego_command, run_async

from ego.servers.dashboard.access import socket_url

LOGGER = Path(__file__).parents[1] / "faces" / "controllers" / "sensor_logger.py"


async def _visit(url: str) -> tuple[int, dict[str, Any], list[dict[str, Any]], int]:
    """The page's status, and over the socket: the hello, three samples, and how many
    camera frames (JPEG) came meanwhile."""
    async with aiohttp.ClientSession(cookie_jar=aiohttp.CookieJar(unsafe=True)) as session:
        async with session.get(url) as page:
            status = page.status
        async with session.ws_connect(socket_url(url)) as ws:
            hello = await ws.receive_json()
            samples: list[dict[str, Any]] = []
            frames = 0
            while len(samples) < 3:
                received = await ws.receive()
                if received.type == aiohttp.WSMsgType.BINARY:
                    frames += received.data[:2] == b"\xff\xd8"  # a JPEG's start
                    continue
                message = json.loads(received.data)
                if message["type"] == "sample":
                    samples.append(message)
    return status, hello, samples, frames


def _visit_during(command: list[str], cwd: Path, stream: str) -> tuple[Any, str]:
    proc = subprocess.Popen([*ego_command(), *command], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=cwd)  # fmt: skip
    assert proc.stdout is not None and proc.stderr is not None
    out, err = LineReader(proc.stdout), LineReader(proc.stderr)
    try:
        url = (out if stream == "stdout" else err).find(r"dashboard at (http://\S+)")
        seen = run_async(_visit(url))
    finally:
        proc.wait(timeout=60)
        errors, printed = err.rest(), out.rest()
    assert proc.returncode == 0, errors
    return seen, printed


def test_ego_demo_serves_its_dashboard_by_default_and_prints_the_url(tmp_path: Path) -> None:
    (status, hello, samples, frames), out = _visit_during(
        ["demo", "--duration", "4", "--dashboard-address", "127.0.0.1:0"], tmp_path, "stdout"
    )
    assert status == 200
    assert hello["mode"] == "live" and hello["world"] is not None
    assert samples[-1]["proximity"] is not None and samples[-1]["light"] is not None
    assert frames >= 1  # the demo's controller samples its camera: the page shows it
    assert "summary:" in out


def test_ego_run_dashboard_and_record_together(tmp_path: Path) -> None:
    (status, hello, samples, _), _ = _visit_during(
        ["run", "--port", "sim", "--duration", "3", "--dashboard-address", "127.0.0.1:0",
         "--record", "run.mcap", str(LOGGER), "log.json"], tmp_path, "stderr",
    )  # fmt: skip
    assert status == 200 and hello["robot"]["port"] == "sim"
    assert samples[-1]["encoders"] is not None
    assert (tmp_path / "run.mcap").stat().st_size > 1000


def test_ego_replay_plays_a_recording_into_the_dashboard(tmp_path: Path) -> None:
    recorded = subprocess.run(
        [*ego_command(), "run", "--port", "sim", "--duration", "1", "--record", "run.mcap",
         str(LOGGER), "log.json"], capture_output=True, text=True, cwd=tmp_path, timeout=60,
    )  # fmt: skip
    assert recorded.returncode == 0, recorded.stderr
    (status, hello, samples, _), _ = _visit_during(
        ["replay", "run.mcap", "--duration", "4", "--dashboard-address", "127.0.0.1:0"], tmp_path,
        "stderr",
    )  # fmt: skip
    assert status == 200 and hello["mode"] == "replay"
    times = [s["t"] for s in samples]
    assert times == sorted(times) and 0 < times[0] <= 1.1
