"""A register-file I2C target: the first byte a write sends is the register pointer, the
bytes after it are written from there on, and a read sends from the pointer on. The
pointer steps after each byte (the usual convention of the sensor chips here; a chip
that steps only on request overrides :meth:`step`)."""

from __future__ import annotations

__all__ = ["RegisterTarget"]


class RegisterTarget:
    """256 byte registers; subclasses give values (:meth:`get`) and side effects
    (:meth:`put`). ``snapshot`` is called once per read message, so that a burst read
    sees one sample (the chips' block data update)."""

    def __init__(self, initial: dict[int, int] | None = None) -> None:
        self.regs = bytearray(256)
        for reg, value in (initial or {}).items():
            self.regs[reg] = value
        self.pointer = 0

    def step(self, register: int) -> int:
        return (register + 1) & 0xFF

    def get(self, register: int) -> int:
        return self.regs[register]

    def put(self, register: int, value: int) -> None:
        self.regs[register] = value

    def snapshot(self) -> None:
        """Latch the sensor values a read will send (default: none)."""

    def write(self, data: bytes) -> None:
        if not data:
            return
        self.pointer = data[0]
        for value in data[1:]:
            self.put(self.pointer, value)
            self.pointer = self.step(self.pointer)

    def read(self, count: int) -> bytes:
        self.snapshot()
        out = bytearray()
        for _ in range(count):
            out.append(self.get(self.pointer) & 0xFF)
            self.pointer = self.step(self.pointer)
        return bytes(out)

    def stop(self) -> None:
        pass
