"""The one clear line ego says when an optional package of the ``ros2`` extra is missing."""

from __future__ import annotations

import importlib

from ego.errors import EgoError

__all__ = ["PIP_COMMAND", "check_installed", "missing"]

#: How to install everything ego.ros2 uses.
PIP_COMMAND = "pip install 'ego[ros2]'"


def missing(exc: ModuleNotFoundError, package: str, module: str) -> BaseException:
    """The error to raise when importing ``module`` failed with ``exc``: an
    :class:`~ego.errors.EgoError` naming ``package`` and the pip command when ``module``
    itself is absent; ``exc`` unchanged when something else is (a bug, not a choice)."""
    if (exc.name or "").partition(".")[0] != module:
        return exc
    return EgoError(f"ego.ros2 needs {package}: {PIP_COMMAND}")


def check_installed() -> None:
    """Import the ``ros2`` extra's packages now, before anything is opened: the one line
    naming a missing one rather than a failure later (a router that cannot be reached)."""
    for package, module in (("rosbags", "rosbags"), ("xxhash", "xxhash")):
        try:
            importlib.import_module(module)
        except ModuleNotFoundError as exc:
            raise missing(exc, package, module) from exc
