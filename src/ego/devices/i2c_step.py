"""The step's reads over the Overo's I2C bus, beside the serial batch: each due family's
chip read and its values handed over as the line's reply would be (validate, then apply)."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Sequence

from ego.devices.base import Device, Sensor
from ego.errors import DeviceError, UnsupportedDeviceError
from ego.i2c.chips import Chip
from ego.i2c.side import MAX_I2C_ATTEMPTS, OveroI2C
from ego.seam.batch import Request

__all__ = ["run_i2c_step"]

log = logging.getLogger(__name__)


def run_i2c_step(
    parts: Sequence[Device],
    side: OveroI2C,
    now_ms: int,
    clock: Callable[[], float] = time.monotonic,
    deadline_s: float | None = None,
) -> None:
    """Read the chip of every part served over I2C that is due at ``now_ms``, and hand
    each its values as a reply of its serial command (validate, then apply), each
    transfer by ``deadline_s`` (the step's, time.monotonic(); ego.i2c.side).

    A reading not in by the deadline is left for a later step (the family keeps its last
    values and stays due); a chip that stops answering, or a transfer that has hung,
    disables its family (UnsupportedDeviceError, raised once every other part has its
    values); values that stay implausible over MAX_I2C_ATTEMPTS reads raise DeviceError.
    """
    due = [
        (part, chip)
        for part in parts
        if isinstance(part, Sensor) and (chip := part.i2c_chip) is not None and part.is_due(now_ms)
    ]
    absent: list[UnsupportedDeviceError] = []
    for part, chip in due:
        request = Request(part.current_command())
        try:
            reading = _plausible(part, chip, side, request, clock, deadline_s)
        except OSError as exc:
            why = f"the {chip.name} at 0x{chip.address:02X} on {side.name} stopped answering"
            absent.append(part.missing(f"{why}: {exc}"))
            continue
        if reading is None:  # late: read again at the next step, when the bus is free
            log.debug("%s: the %s reading is late; next step", side.name, chip.name)
            continue
        values, now_s = reading
        try:
            part.apply(request, values, now_ms, now_s)
        except UnsupportedDeviceError as exc:
            absent.append(exc)
    if absent:
        raise absent[0]


def _plausible(
    part: Sensor, chip: Chip, side: OveroI2C, request: Request, clock: Callable[[], float],
    deadline_s: float | None,
) -> tuple[tuple[int, ...], float] | None:
    problem = ""
    for _ in range(MAX_I2C_ATTEMPTS):
        values = side.read(chip, deadline_s)
        if values is None:
            return None
        now_s = clock()
        verdict = part.validate(request, values, now_s)
        if verdict.fine:
            return values, now_s
        problem = verdict.problem or ""
        log.warning("%s: implausible %s reading (%s); again", side.name, chip.name, problem)
    raise DeviceError(
        f"no plausible reading of the {chip.name} on {side.name} after "
        f"{MAX_I2C_ATTEMPTS} attempts ({problem})"
    )
