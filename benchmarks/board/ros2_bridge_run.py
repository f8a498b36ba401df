"""``ego ARGS...`` (count.sh runs ``ego ros2``) and, when $EGO_BENCH_RSS is set, the guest's
resident pages once it has ended: the ROS 2 bridge's memory on the board, which the command
itself does not print."""

import os
import sys

from ego.app.cli import main

status = main(sys.argv[1:])
if os.environ.get("EGO_BENCH_RSS"):  # count.sh's memory pass
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from guest_memory import guest_rss_kb

    print(f"rss_kb {guest_rss_kb()} parent_kb 0", flush=True)
sys.exit(status)
