"""The e-puck2's speaker: its firmware's melodies and tones (ASCII ``T``).

MAIN:src/epuck1x/Asercom2.c:1486-1516: ``T,n`` plays melody 1 (Mario), 2 (Underworld),
3 (Star Wars), the sample 4 (a 4 kHz tone) or 5 (10 kHz), any other number stops; it
answers ``t``. The binary way is the "all actuators" command's sound byte, which would
send every other actuator with it and, over USB, sleep 10 ms (Asercom2.c:481): one ASCII
line a sound costs less, and plays each sound exactly once (a one-shot).
"""

from __future__ import annotations

import enum
from collections.abc import Callable

from ego.devices.base import Device
from ego.devices.table import TABLE
from ego.errors import EgoError, OutOfRangeError, UnsupportedDeviceError
from ego.seam.profile import Profile

__all__ = ["Melody", "Speaker"]


class Melody(enum.IntEnum):
    """What ``T,n`` plays (Asercom2.c:1486-1516)."""

    MARIO = 1
    UNDERWORLD = 2
    STAR_WARS = 3
    TONE_4KHZ = 4
    TONE_10KHZ = 5


#: Any other number stops what plays.
_STOP = 0


@TABLE.declare("sound", webots_rank=15)
class Speaker(Device):
    """The speaker: ``play(Melody.MARIO)``, ``stop()``; each call is one ASCII ``T``.

    >>> robot.sound.play(Melody.STAR_WARS)               # doctest: +SKIP
    >>> robot.sound.stop()
    """

    family = "speaker"

    def __init__(self, profile: Profile) -> None:
        super().__init__(profile)
        self._send: Callable[[str, int], list[str]] | None = None
        self.last: Melody | None = None

    @property
    def member_names(self) -> tuple[str, ...]:
        return self.served_names()

    def bind_ascii(self, send: Callable[[str, int], list[str]]) -> None:
        """The robot's way of sending an ASCII line (this family does no I/O itself)."""
        self._send = send

    @staticmethod
    def melody_named(sound: str) -> Melody | None:
        """The sound a file name means (``sounds/mario.wav``, ``Star Wars``, ``tone_4khz``),
        None for another: its base name, case, extension, spaces and ``_`` aside."""
        if not isinstance(sound, str):
            return None
        base = sound.replace("\\", "/").rsplit("/", 1)[-1].rsplit(".", 1)[0]
        key = "".join(c for c in base.lower() if c.isalnum())
        for melody in Melody:
            name = melody.name.lower().replace("_", "")
            if key in (name, name.removeprefix("tone")):
                return melody
        return None

    @staticmethod
    def sound_names() -> str:
        """The sounds by the names :meth:`melody_named` knows, for messages."""
        return ", ".join(m.name.lower() for m in Melody)

    def play(self, melody: Melody | int) -> None:
        """Play ``melody`` once (1..5, :class:`Melody`); it replaces what was playing."""
        if isinstance(melody, bool) or not isinstance(melody, int) or melody not in set(Melody):
            known = ", ".join(f"{m.value} ({m.name})" for m in Melody)
            raise OutOfRangeError(f"sound {melody!r} is not one of {known}")
        self._line(int(melody))
        self.last = Melody(melody)

    def stop(self) -> None:
        """Stop what plays."""
        self._line(_STOP)
        self.last = None

    def _line(self, number: int) -> None:
        if not self.member_names:
            raise UnsupportedDeviceError(
                f"the {self.profile.firmware} firmware ({self.profile.description}) has no "
                "speaker ego can play"
            )
        if self._send is None:
            raise EgoError("this speaker is not attached to a robot")
        self._send(f"T,{number}", 1)
