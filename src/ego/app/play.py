"""``ego replay run.mcap``: serve the dashboard on a recording until Ctrl-C (or a time)."""

from __future__ import annotations

import sys
import time

from ego.app.replay import ReplayFeed
from ego.recording.reader import Recording
from ego.servers.dashboard.live import parse_address
from ego.servers.dashboard.server import DashboardServer

__all__ = ["play"]


def play(
    path: str,
    address: str,
    secret_file: str | None = None,
    speed: float = 1.0,
    duration_s: float | None = None,
) -> int:
    """Play ``path`` into a dashboard at ``address``; returns the exit status."""
    from ego.net.auth import load_secret

    recording = Recording.open(path)
    feed = ReplayFeed(recording, speed)
    host, port = parse_address(address)
    secret = load_secret(secret_file) if secret_file else None
    with DashboardServer(feed, host, port, secret) as server:
        feed.server = server
        end = None if duration_s is None else time.monotonic() + duration_s
        try:
            feed.start()
            print(f"ego replay: {len(recording.samples)} steps, {recording.duration_s:.1f} s "
                  f"of {recording.robot.get('firmware', '?')} robot; dashboard at {server.url}",
                  file=sys.stderr, flush=True)  # fmt: skip
            while end is None or time.monotonic() < end:
                time.sleep(0.1)
        except KeyboardInterrupt:
            pass
        finally:
            feed.close()
    return 0
