"""``ego ARGS...`` (count.sh runs ``ego ros2``), then the number of steps the robot made
("steps N": the bridge steps on its own clock for a duration, and a slow or loaded board
makes fewer steps than the duration over the period), and, when $EGO_BENCH_RSS is set,
the guest's resident pages once it has ended: the bridge's memory on the board, which the
command itself does not print."""

import os
import sys

from ego.app.cli import main
from ego.core.robot import Robot

steps = 0
_step = Robot.step


def _counted(self, *args, **kwargs):  # type: ignore[no-untyped-def]
    global steps
    steps += 1
    return _step(self, *args, **kwargs)


Robot.step = _counted  # type: ignore[method-assign]
status = main(sys.argv[1:])
print(f"steps {steps}", flush=True)
if os.environ.get("EGO_BENCH_RSS"):  # count.sh's memory pass
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from guest_memory import guest_rss_kb

    print(f"rss_kb {guest_rss_kb()} parent_kb 0", flush=True)
sys.exit(status)
