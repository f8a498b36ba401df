"""The options several ``ego`` subcommands share, as argparse parent parsers.

``--firmware``, ``--seed`` and ``--world`` of the emulated commands, and the dashboard's
``--dashboard`` / ``--dashboard-address HOST:PORT`` / ``--secret-file FILE``. The
dashboard's switch takes no value, so that it can stand anywhere on a command line
without eating the controller that follows it (``ego run --dashboard avoid.py``); the
old ``--dashboard=HOST:PORT`` (one word) is still read, as ``--dashboard-address``.
"""

from __future__ import annotations

import argparse
import copy
import math
import sys
from collections.abc import Sequence
from typing import Any

from ego.seam.profile import FIRMWARE_CHOICES, Firmware

__all__ = [
    "DEFAULT_DASHBOARD",
    "MAX_DEADLINE_MS",
    "CommandParser",
    "add_dashboard_options",
    "camera_size",
    "deadline_ms",
    "firmware_parent",
    "positive",
    "replay_speed",
    "robot_parent",
    "seed_parent",
    "world_parent",
]

#: Where a dashboard listens when ``--dashboard`` names no address.
DEFAULT_DASHBOARD = "127.0.0.1:8765"
#: The one-word form ``--dashboard=HOST:PORT`` of earlier releases.
_OLD_DASHBOARD = "--dashboard="


class CommandParser(argparse.ArgumentParser):
    """A subcommand's parser: ``--dashboard=HOST:PORT`` is read as ``--dashboard-address``.

    Only a word that argparse itself takes for the ``--dashboard`` switch is read so: one
    a controller is given (after its file, or after ``--``) reaches the controller as it is.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs["exit_on_error"] = False  # parse_known_args says the error itself
        super().__init__(*args, **kwargs)

    def parse_known_args(  # type: ignore[override]
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> tuple[argparse.Namespace, list[str]]:
        words = list(sys.argv[1:] if args is None else args)
        while True:
            attempt = None if namespace is None else copy.copy(namespace)
            try:
                parsed, extra = super().parse_known_args(words, attempt)
            except argparse.ArgumentError as exc:
                at = _old_dashboard_word(words, exc)
                if at is None:
                    self.error(str(exc))
                words[at] = "--dashboard-address=" + words[at].removeprefix(_OLD_DASHBOARD)
                continue
            if namespace is not None:
                vars(namespace).update(vars(parsed))
                parsed = namespace
            return parsed, extra


def _old_dashboard_word(words: list[str], error: argparse.ArgumentError) -> int | None:
    """Where the ``--dashboard=HOST:PORT`` that argparse refused is, if that is the error.

    argparse reads options left to right and stops at ``--`` or at a controller's
    arguments, so the first such word before any ``--`` is the one it refused.
    """
    if error.argument_name != "--dashboard":
        return None
    end = words.index("--") if "--" in words else len(words)
    return next((i for i in range(end) if words[i].startswith(_OLD_DASHBOARD)), None)


def _address(text: str) -> str:
    """An argparse type: a dashboard address, ``HOST:PORT`` (checked now, used later)."""
    from ego.servers.dashboard.live import parse_address

    try:
        parse_address(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return text


class _DashboardSwitch(argparse.Action):
    """``--dashboard``: serve one, at ``--dashboard-address`` if given, else the default."""

    def __init__(self, option_strings: Sequence[str], dest: str, **kwargs: Any) -> None:
        super().__init__(option_strings, dest, nargs=0, **kwargs)

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: object,
        option_string: str | None = None,
    ) -> None:
        if getattr(namespace, self.dest, None) is None:
            setattr(namespace, self.dest, DEFAULT_DASHBOARD)


def add_dashboard_options(
    parser: argparse.ArgumentParser,
    what: str,
    *,
    switch: bool = True,
    secret: bool = True,
    off_loopback: str = "off loopback it needs --secret-file",
    secret_help: str = "the shared secret a dashboard off loopback asks for",
) -> None:
    """``--dashboard`` (a switch: ``what`` says what it serves), ``--dashboard-address``
    and, unless ``secret`` is False, ``--secret-file``; ``args.dashboard`` is the address
    to serve at, or None. ``off_loopback`` says what an address off loopback needs, and
    ``secret_help`` what the secret file is for."""
    if switch:
        parser.add_argument(
            "--dashboard", action=_DashboardSwitch, default=None,
            help=f"serve {what} (at {DEFAULT_DASHBOARD} unless --dashboard-address says "
            "where; the URL is printed)",
        )  # fmt: skip
    parser.add_argument(
        "--dashboard-address", dest="dashboard", type=_address, metavar="HOST:PORT",
        default=None, help=f"where the dashboard listens (default {DEFAULT_DASHBOARD}; "
        f"{off_loopback})" + ("; implies --dashboard" if switch else ""),
    )  # fmt: skip
    if secret:
        parser.add_argument(
            "--secret-file", default=None, metavar="FILE",
            help=f"{secret_help} (ego secret makes one)",
        )  # fmt: skip


def firmware_parent(*, emulated: bool, default: str | None) -> argparse.ArgumentParser:
    """``--firmware``: the one the emulator answers as (``emulated``), else the robot's."""
    parent = argparse.ArgumentParser(add_help=False)
    # The emulator's e-puck answers as either e-puck1 firmware; its e-puck2 is --robot's.
    emulator_firmwares = tuple(c for c in FIRMWARE_CHOICES[1:] if c != Firmware.EPUCK2.value)
    choices = emulator_firmwares if emulated else FIRMWARE_CHOICES
    help_text = (
        f"which firmware the emulator answers as (default: {default})"
        if emulated
        else "the dsPIC's firmware (default: auto, asked with V and C at open)"
    )
    parent.add_argument(
        "--firmware", choices=choices, default=default,
        metavar="{" + ",".join(choices) + "}", help=help_text,
    )  # fmt: skip
    return parent


def robot_parent(what: str) -> argparse.ArgumentParser:
    """``--robot epuck|epuck2``: which robot the emulator models (port sim), or which one
    a Pi-puck carries (port pipuck)."""
    parent = argparse.ArgumentParser(add_help=False)
    parent.add_argument(
        "--robot", choices=("epuck", "epuck2"), default=None,
        help=f"{what}: an e-puck or a GCtronic e-puck2 (default: an e-puck on the "
        "emulator, detected on a Pi-puck)",
    )  # fmt: skip
    return parent


def seed_parent(default: int | None, what: str) -> argparse.ArgumentParser:
    """``--seed N``: the emulator's noise (and fault) generator's seed."""
    parent = argparse.ArgumentParser(add_help=False)
    shown = "a fresh one each run" if default is None else str(default)
    parent.add_argument(
        "--seed", type=int, default=default, metavar="N",
        help=f"seed of the emulator's sensor noise{what}: the same seed, the same run "
        f"(default: {shown})",
    )  # fmt: skip
    return parent


def world_parent(what: str) -> argparse.ArgumentParser:
    """``--world NAME|FILE``: a built-in world, a TOML world file or a Webots ``.wbt``."""
    parent = argparse.ArgumentParser(add_help=False)
    parent.add_argument(
        "--world", default=None, metavar="NAME|FILE",
        help=f"{what}: arena (default), line-track, maze, light, a TOML world file or a "
        "Webots world (.wbt)",
    )  # fmt: skip
    return parent


# -- errors, in the command line's words --------------------------------------------------

#: The optional packages a command may need: the module, its package, and ego's extra.
EXTRAS = {
    "matplotlib": ("matplotlib", "plot"),
    "zenoh": ("eclipse-zenoh", "zenoh"),
    "aiohttp": ("aiohttp", "dashboard"),
    "mcap": ("mcap", "record"),
}
#: What a secret file on the command line is called (Python says ``secret=...``).
SECRET_REMEDY = "pass --secret-file FILE (ego secret makes one), or set EGO_SECRET_FILE"


def positive(text: str) -> float:
    """An argparse type: a finite number above 0 (seconds, a time step)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan  # argparse would only say "invalid positive value"
    if not value > 0 or math.isinf(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a positive number")
    return value


def camera_size(text: str) -> tuple[int, int]:
    """An argparse type: a camera size as WIDTHxHEIGHT."""
    width, sep, height = text.lower().partition("x")
    if not (sep and width.isdigit() and height.isdigit()):
        raise argparse.ArgumentTypeError(f"{text!r} is not WIDTHxHEIGHT, as 160x120")
    return int(width), int(height)


def replay_speed(text: str) -> float:
    """An argparse type: one of the speeds a replay plays at."""
    from ego.backends.replay import SPEEDS

    value = positive(text)
    if value not in SPEEDS:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not one of {', '.join(f'{s:g}' for s in SPEEDS)}"
        )
    return value


#: The longest deadline (or period) a command accepts: beyond a minute a deadman no
#: longer protects anyone, and a longer step is a unit mistake.
MAX_DEADLINE_MS = 60_000


def deadline_ms(text: str) -> int:
    """An argparse type for every ``--*-deadline-ms`` (and ``ego ros2 --period-ms``):
    whole milliseconds within 1..MAX_DEADLINE_MS, refused with one message otherwise."""
    stripped = text.strip()
    value = int(stripped) if stripped.isdigit() and len(stripped) < 12 else -1
    if not 1 <= value <= MAX_DEADLINE_MS:
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a whole number of milliseconds within 1..{MAX_DEADLINE_MS}"
        )
    return value


def error_line(exc: BaseException) -> str:
    """What the command line says of ``exc``: options where Python would name arguments."""
    from ego.errors import SecretRequiredError

    if isinstance(exc, SecretRequiredError):
        return SecretRequiredError.told(exc.where, SECRET_REMEDY)
    return str(exc)


def missing_extra(exc: ModuleNotFoundError, command: str) -> str | None:
    """``ego COMMAND needs PACKAGE: pip install 'ego[EXTRA]'`` when ``exc`` is the import
    of an optional package failing; None for any other module (a bug, not a choice)."""
    module = (exc.name or "").partition(".")[0]
    if module not in EXTRAS:
        return None
    package, extra = EXTRAS[module]
    if command == "ros2":  # ego ros2 needs the whole ros2 extra (zenoh, rosbags, xxhash)
        extra = "ros2"
    return f"ego {command} needs {package}: pip install 'ego[{extra}]'"


def has_module(name: str) -> bool:
    """Whether ``name`` can be imported, without importing it."""
    import importlib.util

    return importlib.util.find_spec(name) is not None


def demo_dashboard(args: argparse.Namespace) -> str | None:
    """Where ``ego demo`` serves its dashboard, or None. It is on by default, not asked
    for: without the dashboard extra the demo runs without it and says so in one line
    (asked for with --dashboard, a missing aiohttp is an error naming the extra)."""
    dashboard: str | None = None if args.no_dashboard else (args.dashboard or DEFAULT_DASHBOARD)
    if args.dashboard is None and dashboard is not None and not has_module("aiohttp"):
        print("ego demo: no dashboard (aiohttp is missing: pip install 'ego[dashboard]')",
              file=sys.stderr)  # fmt: skip
        dashboard = None
    return dashboard
