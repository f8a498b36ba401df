"""``python -m benchmarks._dashboard_memory PORT [STEPS]``: a controller's resident memory
(VmRSS, kB) after STEPS steps (default 100) without a dashboard, then after as many more
with a dashboard serving one page; one JSON line."""

from __future__ import annotations

import json
import subprocess
import sys

from benchmarks.common import rss_kb


def main(port: str, steps: int = 100) -> int:
    import ego

    with ego.Robot(port, handle_signals=False) as robot:
        for family in (robot.proximity, robot.light, robot.accelerometer, robot.encoders):
            family.enable(32)
        for _ in range(steps):
            robot.step(32)
        before = rss_kb()
        from ego.servers.dashboard.live import RobotDashboard

        board = RobotDashboard("127.0.0.1:0", out=sys.stderr)
        board.attach(robot)
        assert board.server is not None
        page = subprocess.Popen([sys.executable, "-m", "benchmarks._dashboard_page",
                                 board.server.url], stdout=subprocess.PIPE, text=True)  # fmt: skip
        try:
            assert page.stdout is not None and page.stdout.readline().strip() == "connected"
            for _ in range(steps):
                robot.step(32)
            after = rss_kb()
        finally:
            page.terminate()
            page.wait()
            board.close()
    print(json.dumps({"before_kb": before, "after_kb": after}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], *(int(a) for a in sys.argv[2:3])))
