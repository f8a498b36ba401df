"""The app: the ``ego`` command line, the demo, swarms, replays and plots."""
