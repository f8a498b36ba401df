"""ego: run Webots e-puck controllers on the real robot, or drive it from a PC."""

__version__ = "0.1.0"
