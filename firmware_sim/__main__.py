"""``python -m firmware_sim``: serve an emulated dsPIC on a pty until killed."""

import sys

from firmware_sim.cli import main

sys.exit(main())
