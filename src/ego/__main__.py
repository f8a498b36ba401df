"""``python -m ego``: the ``ego`` command (demo, run, sim, serve, bench)."""

import sys

from ego.app.cli import main

sys.exit(main())
