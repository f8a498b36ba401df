"""The checks of ego's public calls, each in one place: integers (device families, the
camera, image encoding) and image rotations.

Refused, never clamped: a value out of range raises :class:`~ego.errors.OutOfRangeError`,
a value of the wrong type ``TypeError``.
"""

from __future__ import annotations

import math
import numbers

from ego.errors import OutOfRangeError

__all__ = ["MAX_PERIOD_MS", "ROTATIONS", "check_int", "check_rotation"]

#: Longest sampling period accepted (a day); anything longer is surely a unit mistake.
MAX_PERIOD_MS = 86_400_000

#: The rotations a frame can be given, degrees counter-clockwise (as ``np.rot90``).
ROTATIONS = (0, 90, 180, 270)


def check_int(
    what: str,
    value: object,
    low: int | None = None,
    high: int | None = None,
    unit: str = "",
    *,
    rounding: bool = False,
    integral: bool = False,
) -> int:
    """``value`` as an int within low..high (either bound None: none), else an error.

    Any real number is accepted (numpy's too); a fractional one is refused
    (OutOfRangeError), or rounded to the nearest integer with ``rounding``. With
    ``integral`` only an integer type is (a float, even 3.0, is a TypeError). A bool is
    never a number here. Out of range is always refused, never clamped.
    """
    bounded = low is not None or high is not None
    span = f"{'' if low is None else low}..{'' if high is None else high}{unit}"
    if integral and (isinstance(value, bool) or not isinstance(value, numbers.Integral)):
        raise TypeError(f"{what} must be an integer{f' {span}' if bounded else ''}, not {value!r}")
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{what} must be a number, not {type(value).__name__}")
    if not math.isfinite(float(value)):
        where = f"is outside {span}" if bounded else "is not a finite number"
        raise OutOfRangeError(f"{what} {value}{unit} {where}: refused")
    if isinstance(value, numbers.Integral):
        number = int(value)
    elif rounding or float(value).is_integer():
        number = round(float(value))
    else:
        within = f" in {span}" if bounded else ""
        raise OutOfRangeError(f"{what} {value}{unit} is not a whole number{within}: refused")
    if (low is not None and number < low) or (high is not None and number > high):
        raise OutOfRangeError(f"{what} {value}{unit} is outside {span}: refused, not clamped")
    return number


def check_rotation(rotation: object) -> int:
    """``rotation`` if it is one of :data:`ROTATIONS` (a bool is not), else OutOfRangeError."""
    if isinstance(rotation, bool) or rotation not in ROTATIONS:
        choices = ", ".join(map(str, ROTATIONS))
        raise OutOfRangeError(f"rotation {rotation!r} is not one of {choices} degrees")
    return int(rotation)  # one of ROTATIONS
