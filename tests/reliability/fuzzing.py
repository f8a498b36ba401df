"""What the fuzz tests share: Hypothesis settings, the profiles, and byte mutations.

Runs are derandomized, so CI replays the same examples; an example slower than the
deadline (a hang, or a quadratic blow-up) fails.
"""

from __future__ import annotations

from datetime import timedelta

from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

from ego.seam.profile import Command, Firmware
from ego.serial.profiles import PROFILES

__all__ = [
    "COMMAND_BYTES",
    "FUZZ",
    "FUZZ_SLOW",
    "MUTATIONS",
    "OVERO",
    "PROFILE_LIST",
    "THESIS",
    "U32",
    "mutated",
]

#: Every fuzz test: the same examples on every run, a bounded count, and a deadline per
#: example that a hang (or a quadratic blow-up) cannot meet.
FUZZ = settings(
    derandomize=True,
    max_examples=150,
    deadline=timedelta(seconds=1),
    suppress_health_check=[HealthCheck.too_slow],
)
#: For properties whose examples wait on timeouts (the scripted transport sleeps them).
FUZZ_SLOW = settings(FUZZ, max_examples=40)

THESIS = PROFILES[Firmware.WEBOTS]
OVERO = PROFILES[Firmware.GCTRONIC]
PROFILE_LIST = [THESIS, OVERO]


def mutated(data: bytes, ops: list[tuple[int, int, int]]) -> bytes:
    """``data`` after each ``(kind, position, byte)``: flip, insert, delete or truncate."""
    out = bytearray(data)
    for kind, position, value in ops:
        at = position % (len(out) + 1)
        if kind == 0 and out:
            out[at % len(out)] ^= 1 << (value % 8)
        elif kind == 1:
            out.insert(at, value)
        elif kind == 2 and out:
            del out[at % len(out)]
        elif kind == 3:
            del out[at:]
    return bytes(out)


MUTATIONS = st.lists(
    st.tuples(st.integers(0, 3), st.integers(0, 1 << 16), st.integers(0, 255)),
    min_size=1,
    max_size=6,
)

#: Every command byte of the wire protocol.
COMMAND_BYTES = [int(c) for c in Command]
U32 = st.integers(0, 2**32 - 1)
