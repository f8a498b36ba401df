"""Webots' ``Speaker`` on the robot's own sounds."""

from __future__ import annotations

import sys

from ego.controller.device import Device, view
from ego.errors import UnsupportedDeviceError

__all__ = ["Speaker"]


@view("Speaker")
class Speaker(Device):
    """Webots' Speaker on the robot's own sounds: ``playSound`` plays the firmware's sound
    a file is named after (``mario.wav``, ``star_wars``, ``tone_4khz``...: the family's
    :class:`~ego.devices.sound.Melody`); any other sound, and ``speak``, are refused
    under ``--strict`` and told on stderr otherwise, as Webots tells a missing file."""

    @staticmethod
    def playSound(
        left: Speaker, right: Speaker, sound: str, volume: float = 1.0, pitch: float = 1.0,
        balance: float = 0.0, loop: bool = False,
    ) -> None:  # fmt: skip
        speaker = left if isinstance(left, Speaker) else right
        family = speaker._core.sound
        melody = family.melody_named(sound)
        if melody is None:
            speaker._refuse(f"cannot play {sound!r}: the robot plays {family.sound_names()}")
            return
        family.play(melody)

    def stop(self, sound: str | None = None) -> None:
        self._core.sound.stop()

    def isSoundPlaying(self, sound: str | None = None) -> bool:
        """Whether ego asked a sound last (the firmware does not say when one ends)."""
        last = self._core.sound.last
        return last is not None and (sound is None or self._core.sound.melody_named(sound) == last)

    def speak(self, text: str, volume: float = 1.0) -> None:
        self._refuse("the robot has no speech synthesis")

    def isSpeaking(self) -> bool:
        return False

    def _refuse(self, why: str) -> None:
        if self._strict:
            raise UnsupportedDeviceError(f"speaker {self._name!r}: {why}")
        print(f"Error: speaker {self._name!r}: {why}.", file=sys.stderr)
