"""What can go wrong on the line, each kind with a rate or a trigger (``drop=0.01``, ``reset@500``).

Kinds, as a battery-powered robot with a checksum-less serial line shows them:

=========== ================================================================================
drop        one byte of a batch's reply is lost
corrupt     one bit of a chunk the host sent flips on its way to the dsPIC (a command or
            its argument is misread; unknown commands are then skipped, so the reply's
            length changes)
garble      one bit of a reply byte flips: a reply of the right length with a wrong value,
            which no length check can see (measured, not hidden)
delay       the reply leaves ``delay_s`` late
extra       1 to 4 stray bytes are inserted into (or, for a silent batch, sent after) a reply
stall       the dsPIC hangs for ``stall_s``: it neither hears nor answers
disconnect  the port disappears for ``replug_s`` and comes back under the same path
reset       the dsPIC restarts: the batch is lost, state clears, the banner is printed
=========== ================================================================================
"""

from __future__ import annotations

import random
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field

__all__ = ["FAULT_KINDS", "FaultPlan", "FaultSpec", "FaultTimings", "Mangled", "parse_fault"]

FAULT_KINDS = ("drop", "corrupt", "garble", "delay", "extra", "stall", "disconnect", "reset")
#: Faults drawn when a batch ends (``corrupt`` is drawn per chunk received instead).
BATCH_FAULTS = ("reset", "disconnect", "stall", "delay", "drop", "extra", "garble")


@dataclass(frozen=True, slots=True)
class FaultSpec:
    """One kind of fault, drawn with probability ``rate`` per batch, or at given batches."""

    kind: str
    rate: float = 0.0
    at_batches: frozenset[int] = frozenset()

    def __post_init__(self) -> None:
        if self.kind not in FAULT_KINDS:
            raise ValueError(f"fault kind {self.kind!r} is not one of {', '.join(FAULT_KINDS)}")
        if not 0.0 <= self.rate <= 1.0:
            raise ValueError(f"fault rate {self.rate} is outside 0..1")


#: The longest a delay, stall or re-plug may last, and the last batch a fault may be
#: planned at: beyond either, a "fault" only ever makes the emulator look dead.
MAX_FAULT_S = 3600.0
MAX_BATCH = 10**9


@dataclass(frozen=True, slots=True)
class FaultTimings:
    delay_s: float = 0.1
    stall_s: float = 1.0
    replug_s: float = 0.3
    #: After a reset, how long the banner's second line lags its first (0: at line
    #: rate). A loaded machine, a USB hub or a Bluetooth stack can split the two.
    banner_gap_s: float = 0.0

    def __post_init__(self) -> None:
        for name in ("delay_s", "stall_s", "replug_s", "banner_gap_s"):
            value = getattr(self, name)
            if not 0.0 <= value <= MAX_FAULT_S:  # also refuses NaN
                raise ValueError(f"{name} {value} is outside 0..{MAX_FAULT_S:g} s")


def parse_fault(text: str) -> FaultSpec:
    """``KIND=RATE`` (a probability per batch) or ``KIND@N[,N...]`` (at those batches)."""
    if "=" in text:
        kind, _, rate = text.partition("=")
        try:
            return FaultSpec(kind.strip(), rate=float(rate))
        except ValueError as exc:
            raise ValueError(f"bad fault {text!r}: {exc}") from exc
    if "@" in text:
        kind, _, batches = text.partition("@")
        numbers = batches.split(",")
        if not all(n.strip().isdigit() and n.strip().isascii() for n in numbers):
            raise ValueError(f"bad fault {text!r}: batch numbers are whole numbers, like reset@500")
        if any(len(n.strip()) > 10 or int(n) > MAX_BATCH for n in numbers):
            raise ValueError(f"bad fault {text!r}: batch numbers go up to {MAX_BATCH}")
        try:
            return FaultSpec(kind.strip(), at_batches=frozenset(int(n) for n in numbers))
        except ValueError as exc:
            raise ValueError(f"bad fault {text!r}: {exc}") from exc
    raise ValueError(f"bad fault {text!r}: write KIND=RATE or KIND@BATCH[,BATCH...]")


@dataclass
class FaultPlan:
    """Draws the faults of each batch from the specs, with its own seeded generator."""

    specs: Iterable[FaultSpec] = ()
    seed: int | None = None
    timings: FaultTimings = field(default_factory=FaultTimings)

    def __post_init__(self) -> None:
        self.specs = tuple(self.specs)
        self.rng = random.Random(self.seed)
        self.injected: Counter[str] = Counter()
        #: Forced faults: (kind, the batch number to strike, or None for the next one).
        self._forced: list[tuple[str, int | None]] = []

    def force(self, kind: str, batch: int | None = None) -> None:
        """Inject ``kind`` into batch number ``batch`` (1-based, as
        :attr:`BatchRecord.index` counts), or into the next batch to arrive if None
        (tests use it as a trigger)."""
        FaultSpec(kind)  # validates the name
        self._forced.append((kind, batch))

    def _take_forced(self, batch: int, corrupt: bool) -> set[str]:
        """The forced kinds that strike ``batch`` (corrupt's, or the others); taken out,
        with those meant for a batch already gone."""
        hit = {k for k, b in self._forced if (k == "corrupt") == corrupt and b in (None, batch)}
        self._forced = [
            (k, b) for k, b in self._forced
            if (k == "corrupt") != corrupt or (b is not None and b > batch)
        ]  # fmt: skip
        return hit

    def _due(self, spec: FaultSpec, batch: int) -> bool:
        return batch in spec.at_batches or (spec.rate > 0 and self.rng.random() < spec.rate)

    def for_batch(self, batch: int, has_reply: bool) -> list[str]:
        """The kinds that strike batch number ``batch`` (1-based), in application order.

        A silent batch (actuators only) has no reply to drop, garble or delay.
        """
        kinds = {s.kind for s in self.specs if s.kind != "corrupt" and self._due(s, batch)}
        kinds.update(self._take_forced(batch, corrupt=False))
        if not has_reply:
            kinds -= {"drop", "garble", "delay"}
        chosen = [k for k in BATCH_FAULTS if k in kinds]
        self.injected.update(chosen)
        return chosen

    def corrupt_chunk(self, chunk: bytes, batch: int) -> tuple[bytes, bool]:
        """Maybe flip one bit of one byte of a chunk on its way in."""
        if not chunk:
            return chunk, False
        forced = self._take_forced(batch, corrupt=True)
        if not forced and not any(s.kind == "corrupt" and self._due(s, batch) for s in self.specs):
            return chunk, False
        self.injected["corrupt"] += 1
        data = bytearray(chunk)
        data[self.rng.randrange(len(data))] ^= 1 << self.rng.randrange(8)
        return bytes(data), True

    def mangle_reply(self, kinds: list[str], reply: bytes) -> Mangled:
        """Apply drop / extra / garble to a reply's bytes."""
        data = bytearray(reply)
        if "drop" in kinds and data:
            del data[self.rng.randrange(len(data))]
        together_from = None
        if "extra" in kinds:
            pos = self.rng.randrange(len(data) + 1)
            data[pos:pos] = bytes(self.rng.randrange(256) for _ in range(self.rng.randint(1, 4)))
            together_from = max(0, pos - 1)
        if "garble" in kinds and data:
            data[self.rng.randrange(len(data))] ^= 1 << self.rng.randrange(8)
        return Mangled(bytes(data), len(data) if together_from is None else together_from)


@dataclass(frozen=True, slots=True)
class Mangled:
    """A reply's bytes after drop / extra / garble, and which of them travel together.

    Stray bytes come on the wire amid a reply the dsPIC sends without a pause: the byte
    before them, they and the reply's tail follow each other at the line rate. An
    emulator that paces its writes in chunks must not let a host's scheduling put a gap
    there, or the host's trailing guard (a few bytes' time) misses the tail and takes
    the stray bytes for the reply's (seen on a busy 2-core machine). So the bytes from
    ``together_from`` on go out in one write; ``len(data)`` when none need it.
    """

    data: bytes
    together_from: int
