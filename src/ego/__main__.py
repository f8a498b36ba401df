"""``python -m ego``: the ``ego`` command (demo, run, sim, serve, bench)."""

import sys

from ego.cli import main

sys.exit(main())
