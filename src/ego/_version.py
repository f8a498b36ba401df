"""ego's version: a module of its own, so that what reports it (the wire's welcome, a
recording's metadata) never imports the package's public surface (ego/__init__)."""

__version__ = "0.1.0"
