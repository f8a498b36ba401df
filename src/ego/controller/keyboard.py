"""Webots' ``Keyboard`` on a robot: the keyboard of the terminal that runs ``ego run``.

Teleoperation controllers call ``keyboard.enable(ms)`` then ``getKey()`` every step. The
keys come from the controlling terminal, put in cbreak mode (keys arrive one by one, not
echoed) while the keyboard is enabled, and restored when it is disabled, at exit, and
when a signal ends the run (the terminal mode is put back on the way out). Arrows, Home,
End, Page Up/Down arrive as Webots' codes; letters as their upper-case code, with
``SHIFT`` when typed upper-case, and ``CONTROL`` for Ctrl-letter. Another source (the
dashboard's, later) can :meth:`Keyboard.press` keys too.
"""

from __future__ import annotations

import atexit
import contextlib
import os
import queue
import select
import sys
import threading
from typing import Any

from ego.nursery import Nursery

__all__ = ["FaceKeys", "Keyboard", "decode_keys"]


#: Escape sequences of a terminal (xterm, VT100) and Webots' key codes for them.
_SEQUENCES = {
    b"\x1b[A": 315,  # UP
    b"\x1b[B": 317,  # DOWN
    b"\x1b[C": 316,  # RIGHT
    b"\x1b[D": 314,  # LEFT
    b"\x1b[H": 313,  # HOME
    b"\x1b[F": 312,  # END
    b"\x1b[1~": 313,
    b"\x1b[4~": 312,
    b"\x1b[5~": 366,  # PAGEUP
    b"\x1b[6~": 367,  # PAGEDOWN
    b"\x1bOA": 315,
    b"\x1bOB": 317,
    b"\x1bOC": 316,
    b"\x1bOD": 314,
}


class Keyboard:
    """Webots' Keyboard: ``enable(ms)``, then ``getKey()`` gives the next key or -1."""

    END = 312
    HOME = 313
    LEFT = 314
    UP = 315
    RIGHT = 316
    DOWN = 317
    PAGEUP = 366
    PAGEDOWN = 367
    NUMPAD_HOME = 375
    NUMPAD_LEFT = 376
    NUMPAD_UP = 377
    NUMPAD_RIGHT = 378
    NUMPAD_DOWN = 379
    NUMPAD_END = 382
    KEY = 0xFFFF
    SHIFT = 0x10000
    CONTROL = 0x20000
    ALT = 0x40000

    def __init__(self, sampling_period: int | None = None, *, fd: int | None = None) -> None:
        self._keys: queue.SimpleQueue[int] = queue.SimpleQueue()
        self._period = 0
        self._fd = fd  # the terminal's, found when first enabled (stdin may have none)
        self._saved: list[Any] | None = None
        self._stop = threading.Event()
        self._reader: threading.Thread | None = None
        self._threads: Nursery | None = None
        self._wake: tuple[int, int] | None = None  # a pipe: disable() wakes the reader
        if sampling_period is None:  # Webots' Keyboard(): on at the basic time step
            from ego.faces.default_robot import current_context

            sampling_period = int(current_context().options.basic_time_step_ms)
        if sampling_period:
            self.enable(sampling_period)

    def enable(self, samplingPeriod: int) -> None:
        """Read keys from the terminal (if ``ego run`` has one) until disabled."""
        self._period = int(samplingPeriod)
        if self._fd is None:
            try:
                self._fd = sys.stdin.fileno()
            except (OSError, ValueError):  # no terminal (a test's stdin): keys come by press()
                return
        if self._reader is None and os.isatty(self._fd):
            self._raw(self._fd)
            self._stop.clear()
            self._wake = os.pipe()
            # A program that exits with the keyboard on: the reader ends first.
            self._threads = Nursery("the keyboard", join_s=1.0, at_exit=self._end_reader)
            self._reader = self._threads.start_thread(
                self._read, self._fd, self._wake[0], name="ego-keyboard"
            )

    def disable(self) -> None:
        """Stop reading keys; the reader thread is joined (a ThreadLeakError if it hangs)."""
        self._period = 0
        threads, self._threads, self._reader = self._threads, None, None
        try:
            if threads is not None:
                self._end_reader()
                threads.close()
        finally:
            if self._wake is not None:
                for end in self._wake:
                    os.close(end)
                self._wake = None
            self._restore()

    def _end_reader(self) -> None:
        self._stop.set()
        if self._wake is not None:
            with contextlib.suppress(OSError):
                os.write(self._wake[1], b"x")

    def getSamplingPeriod(self) -> int:
        return self._period

    def getKey(self) -> int:
        """The next key pressed, or -1 when none is waiting (Webots' convention)."""
        if not self._period:
            return -1
        try:
            return self._keys.get_nowait()
        except queue.Empty:
            return -1

    def empty(self) -> bool:
        """Whether no key waits (for Robot.waitForUserInputEvent)."""
        return self._keys.empty()

    def press(self, key: int) -> None:
        """A key from another source than the terminal (a dashboard)."""
        self._keys.put(int(key))

    #: Webots' property: setting enables (0, None: off).
    sampling_period = property(
        getSamplingPeriod, lambda self, p: self.enable(p) if p else self.disable()
    )

    # -- the terminal ------------------------------------------------------------------------

    def _raw(self, fd: int) -> None:
        import termios
        import tty

        with contextlib.suppress(termios.error):
            self._saved = termios.tcgetattr(fd)
            tty.setcbreak(fd)
            atexit.register(self._restore)

    def _restore(self) -> None:
        saved, self._saved = self._saved, None
        if saved is not None and self._fd is not None:
            import termios

            with contextlib.suppress(termios.error, OSError):
                termios.tcsetattr(self._fd, termios.TCSADRAIN, saved)

    def _read(self, fd: int, wake: int) -> None:
        pending = b""
        while not self._stop.is_set():
            # Asleep until a key or disable(); 50 ms after a lone ESC, it is the ESC key.
            ready, _, _ = select.select([fd, wake], [], [], 0.05 if pending else None)
            if wake in ready:
                return
            if not ready:
                if pending:  # a lone ESC, no sequence behind it
                    for key in decode_keys(pending):
                        self._keys.put(key)
                    pending = b""
                continue
            try:
                data = os.read(fd, 64)
            except OSError:
                return
            if not data:
                return
            pending += data
            keys, pending = _split(pending)
            for key in keys:
                self._keys.put(key)


def _split(data: bytes) -> tuple[list[int], bytes]:
    """The keys in ``data``, and what may be the start of an unfinished escape sequence."""
    cut = data.rfind(b"\x1b")
    if (
        cut >= 0
        and not any(data[cut:] == seq for seq in _SEQUENCES)
        and any(seq.startswith(data[cut:]) for seq in _SEQUENCES)
    ):
        return decode_keys(data[:cut]), data[cut:]
    return decode_keys(data), b""


def decode_keys(data: bytes) -> list[int]:
    """Webots key codes for the bytes a terminal sends."""
    keys: list[int] = []
    i = 0
    while i < len(data):
        for sequence, code in _SEQUENCES.items():
            if data.startswith(sequence, i):
                keys.append(code)
                i += len(sequence)
                break
        else:
            byte = data[i]
            i += 1
            if 65 <= byte <= 90:  # typed upper-case: SHIFT + the letter
                keys.append(Keyboard.SHIFT | byte)
            elif 97 <= byte <= 122:
                keys.append(byte - 32)  # Webots gives letters as upper-case codes
            elif 1 <= byte <= 26 and byte not in (9, 10, 13):
                keys.append(Keyboard.CONTROL | (byte + 64))  # Ctrl-A..Ctrl-Z
            elif byte == 10 or byte == 13:
                keys.append(4)  # Return: Qt's Key_Return (0x01000004), as Webots passes it
            else:
                keys.append(byte)
    return keys


class FaceKeys:
    """The keys of a run's Webots Keyboard, for a dashboard: ``context`` is the run's
    FaceContext (captured when its robot opens: the dashboard's thread has another)."""

    def __init__(self, context: Any) -> None:
        self._context = context

    def _keyboard(self) -> Keyboard | None:
        robot = getattr(self._context, "webots_robot", None)
        keyboard = getattr(robot, "keyboard", None)  # the controller may have replaced it
        return keyboard if isinstance(keyboard, Keyboard) else None

    @property
    def webots_face(self) -> bool:
        """Whether a Webots controller (its Python face's Robot) runs: the dashboard then
        shows Webots' units (rad/s) beside the robot's own (steps/s)."""
        return getattr(self._context, "webots_robot", None) is not None

    def listening(self) -> bool:
        """Whether the controller has enabled its Keyboard."""
        keyboard = self._keyboard()
        return keyboard is not None and keyboard.getSamplingPeriod() > 0

    def press(self, key: int) -> None:
        keyboard = self._keyboard()
        if keyboard is not None:
            keyboard.press(key)
