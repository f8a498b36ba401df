"""Who may act on the robot from the dashboard, and what the one who may has asked.

Sans-I/O: the server feeds it clients' messages (dicts) and it answers with what to
send back; the robot's controller thread applies the accepted commands through
:meth:`ControlDesk.guard`, a step guard, so that devices are only ever touched from the
thread that steps them. The rules are ``ego serve``'s:

- one client holds control (the first to ask while nobody holds it); the others view,
  and any command of theirs that would act on the robot is refused;
- a drive command lasts :data:`DRIVE_HOLD_S` unless repeated: a page that goes away (or a
  browser tab put to sleep) leaves the robot stopped, not driving;
- stop latches: the wheels stay at 0 whatever the controller asks, until resumed. The
  server also sends the stop batch at once, between two steps' batches.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from ego.devices.base import Sampled
from ego.devices.table import TABLE, DeviceTable
from ego.serial.profiles import MAX_SPEED_STEPS

if TYPE_CHECKING:
    from ego.camera import Camera
    from ego.core.robot import Robot

__all__ = ["DRIVE_HOLD_S", "ControlDesk", "KeySink", "Reply", "webots_key"]

log = logging.getLogger(__name__)

#: How long one drive command moves the robot: the page repeats it while a key is held.
DRIVE_HOLD_S = 0.4
#: The sensor families the page may switch on and off (camera included): the table's.
SWITCHABLE = TABLE.switchable
#: Webots' key codes for the browser's named keys (KeyboardEvent.key).
_NAMED_KEYS = {
    "ArrowLeft": 314, "ArrowUp": 315, "ArrowRight": 316, "ArrowDown": 317,
    "Home": 313, "End": 312, "PageUp": 366, "PageDown": 367, "Enter": 4, "Tab": 9,
    "Escape": 27, " ": 32, "Backspace": 8, "Delete": 127,
}  # fmt: skip
_SHIFT, _CONTROL, _ALT = 0x10000, 0x20000, 0x40000


class KeySink(Protocol):
    """Where the dashboard's keys go when a Webots controller reads its Keyboard."""

    def listening(self) -> bool: ...

    def press(self, key: int) -> None: ...


def webots_key(message: dict[str, Any]) -> int | None:
    """The Webots key code of a page's key event (None for a key Webots has no code for):
    letters in upper case, as Webots' getKey gives them, with the modifier bits."""
    name = message.get("key")
    if not isinstance(name, str):
        return None
    if name in _NAMED_KEYS:
        code = _NAMED_KEYS[name]
    elif len(name) == 1 and 32 < ord(name) < 127:
        code = ord(name.upper())
    else:
        return None
    for flag, bit in (("shift", _SHIFT), ("ctrl", _CONTROL), ("alt", _ALT)):
        if message.get(flag) is True:
            code |= bit
    return code


@dataclass(frozen=True)
class Reply:
    """What the desk answers a client: a message for it, and whether to send the stop
    batch now (the server does that I/O, off its event loop)."""

    message: dict[str, Any] | None = None
    stop_now: bool = False


class ControlDesk:
    """Control of one robot from dashboard clients (identified by any hashable id)."""

    def __init__(
        self,
        key_sink: KeySink | None = None,
        clock: Callable[[], float] = time.monotonic,
        *,
        can_act: bool = True,
        table: DeviceTable = TABLE,
    ) -> None:
        """``can_act`` False: the page may only stop and resume (``ego serve``'s: the
        controller runs on a PC, and its robot's devices are its own). ``table``: whose
        sampled families the page may switch (the device table)."""
        self.key_sink = key_sink
        #: The families the page may switch on and off (camera included).
        self.switchable = table.switchable
        self.can_act = can_act
        self._clock = clock
        self._lock = threading.Lock()
        self.holder: object | None = None
        self.halted = False
        self._drive: tuple[int, int] | None = None
        self._drive_until = 0.0
        self._driving = False
        self._pending: list[Callable[[Robot], None]] = []
        #: The sampling period the page's "enable" gives a sensor: the run's step.
        self.period_ms = 64

    # -- clients (the server's thread) ---------------------------------------------------

    def state(self, client: object) -> dict[str, Any]:
        """What the page shows of control: its role, whether someone else holds it."""
        listening = self.key_sink is not None and self.key_sink.listening()
        return {
            "type": "state",
            "role": "control" if client == self.holder else "view",
            "held": self.holder is not None,
            "halted": self.halted,
            "keyboard": listening,
        }

    def leave(self, client: object) -> None:
        """A client went away: if it held control, its drive ends and control is free."""
        with self._lock:
            if client == self.holder:
                self.holder = None
                self._drive = None

    def handle(self, client: object, message: object) -> Reply:
        """One message of a client; refused ones get an error naming why."""
        if not isinstance(message, dict) or not isinstance(message.get("type"), str):
            return _error("a command is a JSON object with a 'type'")
        kind = message["type"]
        with self._lock:
            if kind == "take":
                if self.holder not in (None, client):
                    return _error("another page holds control")
                self.holder = client
                return Reply()
            if kind not in ("release", "drive", "key", "led", "sensor", "stop", "resume"):
                return _error(f"unknown command type {kind!r}")
            if client != self.holder:
                return _error(f"{kind!r} refused: this page only views (take control first)")
            if not self.can_act and kind in ("drive", "key", "led", "sensor"):
                return _error(f"{kind!r} refused: the controller runs on the PC that drives "
                              "ego serve; this page can stop and resume the robot")  # fmt: skip
            if kind == "release":
                self.holder, self._drive = None, None
                return Reply()
            if kind == "stop":
                self.halted, self._drive = True, None
                return Reply(stop_now=True)
            if kind == "resume":
                self.halted = False
                return Reply()
            if kind == "drive":
                return self._drive_command(message)
            if kind == "key":
                return self._key(message)
            if kind == "led":
                return self._led(message)
            return self._sensor(message)

    def _drive_command(self, message: dict[str, Any]) -> Reply:
        left, right = message.get("left"), message.get("right")
        if not all(
            isinstance(v, int) and not isinstance(v, bool) and abs(v) <= MAX_SPEED_STEPS
            for v in (left, right)
        ):
            return _error(f"drive needs integer left and right in -{MAX_SPEED_STEPS}.."
                          f"{MAX_SPEED_STEPS} steps/s, not {left!r}, {right!r}")  # fmt: skip
        if self.key_sink is not None and self.key_sink.listening():
            return _error("the controller reads the keyboard: the keys drive it, not the page")
        assert isinstance(left, int) and isinstance(right, int)
        self._drive = (left, right)
        self._drive_until = self._clock() + DRIVE_HOLD_S
        return Reply()

    def _key(self, message: dict[str, Any]) -> Reply:
        code = webots_key(message)
        if code is None:
            return _error(f"key {message.get('key')!r} has no Webots key code")
        if self.key_sink is not None and self.key_sink.listening():
            self.key_sink.press(code)
        return Reply()

    def _led(self, message: dict[str, Any]) -> Reply:
        index, on = message.get("index"), message.get("on")
        if not (isinstance(index, int) and not isinstance(index, bool) and isinstance(on, bool)):
            return _error("led needs an integer index and a boolean on")
        # An RGB LED (the e-puck2's) switched on from the page shows white.
        def switch(robot: Robot) -> None:
            robot.leds.set(index, (0xFFFFFF if index in robot.leds.rgb else 1) if on else 0)

        self._pending.append(switch)
        return Reply()

    def _sensor(self, message: dict[str, Any]) -> Reply:
        family, on = message.get("family"), message.get("on")
        if family not in self.switchable or not isinstance(on, bool):
            return _error(f"sensor needs a family among {', '.join(self.switchable)} "
                          "and a boolean on")  # fmt: skip

        def switch(robot: Robot) -> None:
            device: Camera | Sampled
            if family == "camera":
                device = robot.camera
            else:
                found = robot.family(str(family))
                if not isinstance(found, Sampled):
                    raise TypeError(f"the {family} cannot be switched on and off")
                device = found
            if on:
                device.enable(self.period_ms)
            else:
                device.disable()

        self._pending.append(switch)
        return Reply()

    # -- the robot (its controller's thread) ---------------------------------------------

    def guard(self, robot: Robot) -> None:
        """Before each step's batch: run what was asked, then hold the wheels stopped (if
        halted) or at the page's drive (while it lasts)."""
        with self._lock:
            pending, self._pending = self._pending, []
            drive = self._drive if self._clock() < self._drive_until else None
            halted = self.halted
        for action in pending:
            try:
                action(robot)
            except Exception as exc:  # a page's wish must never end the controller
                log.warning("dashboard command failed: %s", exc)
        if halted:
            robot.motors.set_speed(0, 0)
        elif drive is not None:
            robot.motors.set_speed(*drive)
            self._driving = True
        elif self._driving:  # the drive ran out: stop, then leave the wheels to the controller
            robot.motors.set_speed(0, 0)
            self._driving = False


def _error(text: str) -> Reply:
    return Reply({"type": "error", "error": text})
