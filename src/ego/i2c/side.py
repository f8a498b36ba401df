"""The Overo's I2C bus as a robot's families use it: each chip probed once, every
transfer under one lock, and the step's reads beside the serial batch.

A family the connected firmware leaves to the Overo's bus (``Profile.i2c``) asks
:meth:`OveroI2C.find` for its chip when it is enabled: the bus is opened then, the chip
probed (its identity register, or an acknowledged read of its data), and the answer kept.
Where no chip answers, :meth:`OveroI2C.absent` says which board and firmware serve the
devices instead. Each step, :func:`ego.devices.i2c_step.run_i2c_step` reads the chips of
the families that are due and hands the values to them as the line's replies would be
(validate, then apply). This module knows no device family: the families use it.

Every transfer runs on the bus's worker (:mod:`ego.i2c.worker`) and is waited for until
a deadline: the step's (``read``'s ``deadline_s``), or :data:`TRANSFER_TIMEOUT_S` for the
probes of an enable. A step's read past it gives no reading this step (None; a loaded
board is late, not broken); a transfer that holds the bus for ``HUNG_S`` has hung
(LinkTimeoutError). A reply of the wrong length or that does not decode is a
ShortReplyError, ExtraBytesError or ProtocolError, read again up to MAX_I2C_ATTEMPTS
times (issue 32: it escaped as ``struct.error``).
"""

from __future__ import annotations

import logging
import struct
import threading
import time
from collections.abc import Callable

from ego.errors import ExtraBytesError, LinkTimeoutError, ProtocolError, ShortReplyError
from ego.i2c.bus import I2CAccess, I2CBus
from ego.i2c.chips import CHIPS, Chip
from ego.i2c.worker import HUNG_S, BusWorker

__all__ = ["MAX_I2C_ATTEMPTS", "MIN_TRANSFER_S", "NO_I2C", "TRANSFER_TIMEOUT_S", "OveroI2C"]

log = logging.getLogger(__name__)

#: Reads of one chip in a step before a failure is final (a glitch on the bus is retried).
MAX_I2C_ATTEMPTS = 3
#: The pause before reading again: a dsPIC restarting takes the bus for a moment to probe
#: its LSM330 (e_init_port.c:39-51) before it lets the Overo have it again.
RETRY_PAUSE_S = 0.002
#: How long a transfer outside a step (an enable's probe) may take: as long as a working
#: bus can (ego.i2c.worker.HUNG_S), though a 6-byte read takes under a millisecond at
#: the bus's 100 kHz; a probe that misses it finds no chip.
TRANSFER_TIMEOUT_S = HUNG_S
#: What a step's transfer gets at least, even when the step's deadline has passed (a late
#: step still reads once rather than failing for nothing).
MIN_TRANSFER_S = 0.005


class OveroI2C:
    """The Overo's I2C bus of one robot: opened at first need, closed with the robot.

    ``access`` is None where the port does not reach the robot's bus (a network port, a
    replay); ``where`` names the port for that message.
    """

    def __init__(self, access: I2CAccess | None, where: str = "this port") -> None:
        self._access = access
        self._where = where
        self._bus: I2CBus | None = None
        self._closed = False
        #: The chips that answered (kept), and why the others did not (probed again at
        #: the next enable: a restarting dsPIC may have held the bus).
        self._found: dict[str, Chip] = {}
        self._why: dict[str, str] = {}
        #: Held for every transfer: the probes and set-ups of enable() and the step's reads.
        self.lock = threading.Lock()
        self._worker = BusWorker(self.name)

    @property
    def name(self) -> str:
        return self._access.name if self._access is not None else "no I2C bus"

    def find(self, chip_name: str) -> Chip | None:
        """The chip ``chip_name`` if it answers on this bus (probed once), else None."""
        with self.lock:
            if chip_name not in self._found:
                probed = self._probe(CHIPS[chip_name])
                if isinstance(probed, str):
                    self._why[chip_name] = probed
                    return None
                self._found[chip_name] = probed
            return self._found[chip_name]

    def absent(self, chip_name: str) -> str:
        """Which way leads to the chip's devices, as :meth:`find` left it: one line."""
        chip = CHIPS[chip_name]
        if self._access is None:
            return (
                f"the Overo reads {chip.devices} from the {chip.name} on its own I2C bus, "
                f"which {self._where} does not reach: run the controller on the robot "
                f"(ego run --port /dev/ttyS0); {chip.elsewhere}"
            )
        why = self._why.get(chip_name, "not probed")
        return (
            f"the Overo reads {chip.devices} from the {chip.name} on {self.name} ({why}); "
            f"{chip.elsewhere}"
        )

    def read(self, chip: Chip, deadline_s: float | None = None) -> tuple[int, ...] | None:
        """One reading of ``chip``, decoded, by ``deadline_s`` (time.monotonic(); None:
        :data:`TRANSFER_TIMEOUT_S` from now), or None if it is not in by then (or a late
        one still holds the bus). LinkTimeoutError once a transfer has hung; OSError or a
        ProtocolError (a short, long or undecodable reply) after MAX_I2C_ATTEMPTS."""
        bus = self._bus
        if bus is None or self._closed:
            raise OSError(f"{self.name} is not open")
        if deadline_s is None:
            deadline_s = time.monotonic() + TRANSFER_TIMEOUT_S
        with self.lock:
            for attempt in range(MAX_I2C_ATTEMPTS):
                try:
                    data = self._transfer(
                        lambda: bus.read_block(chip.address, chip.data_register, chip.data_count),
                        deadline_s, chip, chip.data_count,
                    )  # fmt: skip
                    return None if data is None else _decoded(chip, data, self.name)
                except LinkTimeoutError:
                    raise  # the bus has hung: reading again cannot help
                except (OSError, ProtocolError) as exc:
                    if attempt == MAX_I2C_ATTEMPTS - 1:
                        raise
                    log.warning("%s: reading the %s failed (%s); again", self.name, chip.name, exc)
                    time.sleep(RETRY_PAUSE_S)
        raise AssertionError("unreachable")

    def _transfer(
        self, work: Callable[[], bytes], deadline_s: float, chip: Chip, count: int
    ) -> bytes | None:
        """``work``'s bytes, which must be ``count`` (ShortReplyError, ExtraBytesError),
        by ``deadline_s`` (MIN_TRANSFER_S at least), else None."""
        deadline_s = max(deadline_s, time.monotonic() + MIN_TRANSFER_S)
        what = f"reading the {chip.name} at 0x{chip.address:02X}"
        data = self._worker.run(work, deadline_s, what)
        if data is None:
            return None
        if len(data) < count:
            raise ShortReplyError(f"{self.name}: {what}: {len(data)} bytes, not {count}")
        if len(data) > count:
            raise ExtraBytesError(f"{self.name}: {what}: {len(data)} bytes, not {count}")
        return bytes(data)

    def close(self) -> None:
        """Release the bus; idempotent."""
        self._closed = True
        self._worker.close()
        if self._bus is not None:
            self._bus.close()
            self._bus = None

    # -- probing (under the lock) ----------------------------------------------------------

    def _probe(self, chip: Chip) -> Chip | str:
        try:
            bus = self._open()
        except OSError as exc:
            return f"not found: {exc}"
        at = f"0x{chip.address:02X}"
        deadline_s = time.monotonic() + TRANSFER_TIMEOUT_S
        try:
            if chip.identity is not None:
                register, expected = chip.identity
                identity = self._transfer(
                    lambda: bus.read_block(chip.address, register, 1), deadline_s, chip, 1
                )
                if identity is None:
                    return f"no answer at {at} within {TRANSFER_TIMEOUT_S:.0f} s"
                got = identity[0]
                if got != expected:
                    return (
                        f"{at} answers 0x{got:02X} at register 0x{register:02X}, not the "
                        f"{chip.name}'s 0x{expected:02X}"
                    )
            elif self._transfer(
                lambda: bus.read_block(chip.address, chip.data_register, chip.data_count),
                deadline_s, chip, chip.data_count,
            ) is None:  # fmt: skip
                return f"no answer at {at} within {TRANSFER_TIMEOUT_S:.0f} s"
            for register, value in chip.setup:
                done = self._worker.run(
                    lambda r=register, v=value: _written(bus, chip.address, r, v),  # type: ignore[misc]
                    deadline_s, f"setting up the {chip.name} at {at}",
                )  # fmt: skip
                if done is None:
                    return f"no answer at {at} within {TRANSFER_TIMEOUT_S:.0f} s"
        except LinkTimeoutError as exc:
            return f"no answer at {at} in time: {exc}"
        except (OSError, ProtocolError) as exc:
            return f"nothing answers at {at}: {exc}"
        log.info("%s: the %s answers at %s", bus.name, chip.name, at)
        return chip

    def _open(self) -> I2CBus:
        if self._closed:
            raise OSError(f"{self.name} is closed")
        if self._access is None:
            raise OSError(f"{self._where} does not reach the robot's I2C bus")
        if self._bus is None:
            self._bus = self._access.open()
        return self._bus


def _written(bus: I2CBus, address: int, register: int, value: int) -> bool:
    bus.write_byte_data(address, register, value)
    return True


def _decoded(chip: Chip, data: bytes, bus: str) -> tuple[int, ...]:
    try:
        return chip.decode(data)
    except (struct.error, ValueError) as exc:
        raise ProtocolError(f"{bus}: the {chip.name}'s reply does not decode: {exc}") from exc


#: The bus of a robot whose port reaches none (families made on their own).
NO_I2C = OveroI2C(None)
