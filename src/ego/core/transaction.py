"""One step's transaction over the device parts: plan, exchange, validate, apply.

The protocol has no checksum, so the robot's only integrity checks are the reply's
length (the channel's) and the plausibility of its values (each part's ``validate``).
A step therefore runs as a transaction (docs/architecture.md, "The layers"):

* every part plans its requests; they go out in one batch, setters first
  (``ego.devices.base.PHASE``, a stable order: ``P`` before ``Q``);
* the reply is split per request and each part judges its own values, without
  changing anything;
* a single problem refuses the whole reply: each part hears its verdict (a suspect
  reading remembered, a correction queued) and the step asks again;
* otherwise every part applies its values, the only change after a good reply;
* a restarted dsPIC (RobotResetError from the channel) resets every part, which
  re-plans what the dsPIC lost.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence

from ego.devices.base import PHASE, Device
from ego.errors import ProtocolError, RobotResetError, UnsupportedDeviceError
from ego.seam.batch import Request
from ego.seam.channel import Channel
from ego.serial.protocol import encode_batch

__all__ = ["MAX_ATTEMPTS_PER_STEP", "run_step"]

log = logging.getLogger(__name__)

#: A step whose robot restarts, or answers implausibly, more often than this gives up.
MAX_ATTEMPTS_PER_STEP = 3


def run_step(
    parts: Sequence[Device],
    channel: Channel,
    now_ms: int,
    restarted: Callable[[], None],
    clock: Callable[[], float] = time.monotonic,
) -> None:
    """One batch of everything due at ``now_ms``, asked again after a restart (then
    ``restarted()`` re-applies the robot's state) or an implausible reply.

    Raises ProtocolError after MAX_ATTEMPTS_PER_STEP attempts, UnsupportedDeviceError
    once the step is delivered when a reply proved a device absent, and the channel's
    LinkLostError.
    """
    why = ""
    for _ in range(MAX_ATTEMPTS_PER_STEP):
        plan = [(part, request) for part in parts for request in part.plan(now_ms)]
        if not plan:
            return
        plan.sort(key=lambda item: PHASE[item[1].command])
        batch = encode_batch([request for _, request in plan], channel.profile)
        try:
            reply = channel.exchange(batch)
        except RobotResetError as exc:
            log.warning("%s; re-applying the robot's state", exc)
            why = str(exc)
            restarted()
            continue
        now_s = clock()
        answered = list(zip(plan, batch.decode(reply), strict=True))
        verdicts = [
            (part, part.validate(request, values, now_s)) for (part, request), values in answered
        ]
        problems = [(part, verdict) for part, verdict in verdicts if not verdict.fine]
        if problems:
            # The reply had the right length, so the stream is in step: just ask again.
            for part, verdict in problems:
                part.refused(verdict, now_s)
            channel.stats.faults["implausible"] += 1
            why = f"implausible reply: {problems[0][1].problem}"
            log.warning("%s; asking again", why)
            continue
        _apply(answered, now_ms, now_s)
        return
    raise ProtocolError(f"no usable reply after {MAX_ATTEMPTS_PER_STEP} attempts ({why})")


def _apply(
    answered: list[tuple[tuple[Device, Request], tuple[float, ...]]], now_ms: int, now_s: float
) -> None:
    """Every part takes its values. A reply that proves a device absent (docs/protocol.md:
    zeros from a rev 1.3 accelerometer, 0xFFFF without the ground module) disables it, and
    is told once the rest of the step is delivered."""
    absent: list[UnsupportedDeviceError] = []
    for (part, request), values in answered:
        try:
            part.apply(request, values, now_ms, now_s)
        except UnsupportedDeviceError as exc:
            absent.append(exc)
    if absent:
        raise absent[0]
