"""Run a controller written for Webots, unchanged: ``from controller import Robot`` gets ego."""

from __future__ import annotations

import runpy
import sys
from collections.abc import Sequence
from pathlib import Path

import ego.controller
from ego.core.safety import install_signal_handlers
from ego.errors import (
    BadFileError,
    CameraCaptureError,
    ControllerError,
    LinkError,
    RemoteError,
)
from ego.faces.default_robot import run_context
from ego.faces.runtime import RunOptions

__all__ = ["run_controller"]


def run_controller(path: str | Path, options: RunOptions, argv: Sequence[str] = ()) -> None:
    """Execute the controller file at ``path`` as ``__main__`` with ego as its ``controller``.

    As Webots does, the controller's own folder is on ``sys.path`` and ``sys.argv`` holds
    its arguments. Whatever way it ends, every robot it opened is stopped and closed:
    the run holds each one strongly until then, since the controller's globals (and with
    them its robots) are torn down in no particular order when the script ends.

    The run's ``options`` go to the controller through a face context of its own
    (:func:`ego.faces.default_robot.run_context`), active while it runs: its ``Robot()``
    and ``wb_robot_init()`` read them there, and they do not outlive the run.
    """
    script = Path(path)
    if not script.is_file():
        raise FileNotFoundError(f"controller file {str(script)!r} does not exist")
    saved_module = sys.modules.get("controller")
    saved_argv, saved_path = sys.argv[:], sys.path[:]
    aliases = _alias_controller_package()
    sys.argv = [str(script), *argv]
    sys.path.insert(0, str(script.resolve().parent))
    install_signal_handlers()
    try:
        with run_context(options):
            try:
                runpy.run_path(str(script), run_name="__main__")
            except (LinkError, RemoteError, CameraCaptureError, BadFileError):
                raise  # the robot's (or its world's, its recording's): said in one line
            except Exception as exc:
                raise ControllerError(
                    f"{script.name}: {type(exc).__name__}: {exc}", _user_traceback(exc)
                ) from exc
    finally:
        sys.argv, sys.path[:] = saved_argv, saved_path
        for alias in aliases:
            sys.modules.pop(alias, None)
        if saved_module is not None:
            sys.modules["controller"] = saved_module


def _alias_controller_package() -> list[str]:
    """Make ``controller`` and its submodules name ego.controller's, as Webots ships them.

    ``controller.robot`` must be ``ego.controller.robot`` itself: loaded a second time
    under another name, it would make a second ``Robot`` class, and so would every
    module holding a class (``controller.distance_sensor``): the package imports them
    all, so each is aliased here.
    """
    aliases = ["controller"]
    sys.modules["controller"] = ego.controller
    prefix = "ego.controller."
    for name, module in list(sys.modules.items()):
        if name.startswith(prefix):
            alias = "controller." + name[len(prefix) :]
            sys.modules[alias] = module
            aliases.append(alias)
    return aliases


#: ego's own sources: their frames are left out of a controller's traceback.
_EGO_DIR = str(Path(ego.__file__).resolve().parent)


def _user_traceback(exc: BaseException) -> str:
    """The traceback of ``exc`` without ego's frames (nor runpy's): from the controller's
    file down to the line of it that made the failing call."""
    import traceback

    frames = [
        frame
        for frame in traceback.extract_tb(exc.__traceback__)
        if not frame.filename.startswith((_EGO_DIR, "<frozen "))
        and "runpy" not in Path(frame.filename).name
    ]
    lines = ["Traceback (most recent call last):\n", *traceback.format_list(frames)]
    lines += traceback.format_exception_only(type(exc), exc)
    return "".join(lines)
