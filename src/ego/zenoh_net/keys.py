"""ego's Zenoh key space (docs/zenoh.md).

A robot NAME (one or more chunks: ``epuck3``, ``lab/epuck3``) owns ``ego/NAME/...``:

====================  ===========  ========================================================
key                   kind         what
====================  ===========  ========================================================
``ego/NAME/alive``    liveliness   present while the robot's node runs (discovery)
``ego/NAME/info``     queryable    firmware, profile, devices, battery (JSON)
``ego/NAME/exchange`` queryable    one batch: payload the batch's bytes, attachment the
                                   controller's id; reply the reply bytes, or an error
``ego/NAME/ascii``    queryable    an ASCII command (``V``, ``C``, ``S``, ``K``)
``ego/NAME/keepalive`` put         a controller's keepalive while it waits out a step
``ego/NAME/bye``      put          a controller lets go (the robot stops)
``ego/NAME/sensors``  publication  every step's sample (ego.core.telemetry's keys, JSON)
``ego/NAME/scene``    queryable    an emulated robot's world, for a Supervisor
                                   (scene_codec.py: JSON request, JSON reply)
====================  ===========  ========================================================

Webots' radio: an Emitter on channel C puts on ``ego/radio/C`` (``ego/radio/all`` for
CHANNEL_BROADCAST); a Receiver on C subscribes to ``ego/radio/C`` and ``ego/radio/all``,
on CHANNEL_BROADCAST to ``ego/radio/*``.
"""

from __future__ import annotations

import re

__all__ = ["BROADCAST", "PREFIX", "check_name", "radio_key", "radio_keys", "robot_key"]

PREFIX = "ego"
#: Webots' Emitter.CHANNEL_BROADCAST / Receiver.CHANNEL_BROADCAST.
BROADCAST = -1
_CHUNK = re.compile(r"[A-Za-z0-9_.\-]+")
_LEAVES = frozenset(
    {"alive", "info", "exchange", "ascii", "keepalive", "bye", "sensors", "scene"}
)


def check_name(name: str, *, pattern: bool = False) -> str:
    """A robot name (chunks of letters, digits, ``_.-`` joined by ``/``); with
    ``pattern``, a chunk may be ``*`` (``lab/*``). ValueError naming what is wrong."""
    chunks = name.split("/") if isinstance(name, str) else [""]
    for chunk in chunks:
        if not (_CHUNK.fullmatch(chunk) or (pattern and chunk in ("*", "**"))):
            raise ValueError(
                f"Zenoh robot name {name!r}: each part must be letters, digits, '_', '.' or '-'"
                + (" or '*'" if pattern else "")
            )
    if chunks[0] == PREFIX or chunks[0] == "radio":
        raise ValueError(f"Zenoh robot name {name!r} may not start with {chunks[0]!r}")
    return name


def robot_key(name: str, leaf: str) -> str:
    if leaf not in _LEAVES:
        raise ValueError(f"no key {leaf!r} under a robot")
    return f"{PREFIX}/{name}/{leaf}"


def radio_key(channel: int) -> str:
    """Where an Emitter on ``channel`` puts."""
    return f"{PREFIX}/radio/{'all' if channel == BROADCAST else int(channel)}"


def radio_keys(channel: int) -> list[str]:
    """What a Receiver on ``channel`` subscribes to."""
    if channel == BROADCAST:
        return [f"{PREFIX}/radio/*"]
    return [radio_key(channel), radio_key(BROADCAST)]
