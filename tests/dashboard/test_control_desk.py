"""The dashboard's control rules, sans I/O: who may act, drives that lapse, a stop that
latches, keys for a controller's Keyboard, and commands applied in the step's thread."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import pytest

from ego.servers.dashboard.control import DRIVE_HOLD_S, ControlDesk, webots_key


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


@dataclass
class StandInMotors:
    speed: tuple[int, int] = (0, 0)

    def set_speed(self, left: int, right: int) -> None:
        self.speed = (left, right)


@dataclass
class StandInLeds:
    on: dict[int, int] = field(default_factory=dict)
    rgb: tuple[int, ...] = ()  # the LEDs that take a colour (an e-puck2's)

    def set(self, index: int, value: int) -> None:
        self.on[index] = value


@dataclass
class StandInRobot:
    """What the guard touches of a Robot: the motors and the LEDs."""

    motors: StandInMotors = field(default_factory=StandInMotors)
    leds: StandInLeds = field(default_factory=StandInLeds)


@dataclass
class Keys:
    on: bool = False
    pressed: list[int] = field(default_factory=list)

    def listening(self) -> bool:
        return self.on

    def press(self, key: int) -> None:
        self.pressed.append(key)


def _error(reply: Any) -> str:
    return "" if reply.message is None else str(reply.message.get("error", ""))


def test_the_first_page_to_ask_holds_control_and_the_others_view() -> None:
    desk = ControlDesk()
    assert _error(desk.handle("a", {"type": "take"})) == ""
    assert "another page holds control" in _error(desk.handle("b", {"type": "take"}))
    assert desk.state("a")["role"] == "control"
    assert desk.state("b") == {"type": "state", "role": "view", "held": True, "halted": False,
                               "keyboard": False}  # fmt: skip


@pytest.mark.parametrize(
    "message",
    [
        {"type": "drive", "left": 500, "right": 500},
        {"type": "stop"},
        {"type": "resume"},
        {"type": "led", "index": 0, "on": True},
        {"type": "sensor", "family": "proximity", "on": False},
        {"type": "key", "key": "ArrowUp"},
        {"type": "release"},
    ],
)
def test_a_viewer_cannot_act(message: dict[str, Any]) -> None:
    desk = ControlDesk()
    desk.handle("a", {"type": "take"})
    robot = StandInRobot()
    assert "only views" in _error(desk.handle("b", message))
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.motors.speed == (0, 0) and robot.leds.on == {} and not desk.halted
    assert desk.holder == "a"


def test_a_drive_lasts_only_while_it_is_repeated() -> None:
    clock = Clock()
    desk = ControlDesk(clock=clock)
    robot = StandInRobot()
    desk.handle("a", {"type": "take"})
    desk.handle("a", {"type": "drive", "left": 400, "right": -400})
    robot.motors.set_speed(100, 100)  # what the controller asked this step
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.motors.speed == (400, -400)
    clock.now += DRIVE_HOLD_S + 0.01  # the page stopped repeating it (gone, asleep)
    robot.motors.set_speed(100, 100)
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.motors.speed == (0, 0)  # stopped once ...
    robot.motors.set_speed(100, 100)
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.motors.speed == (100, 100)  # ... then the controller drives again


def test_a_page_that_goes_away_ends_its_drive_and_frees_control() -> None:
    desk = ControlDesk()
    robot = StandInRobot()
    desk.handle("a", {"type": "take"})
    desk.handle("a", {"type": "drive", "left": 600, "right": 600})
    desk.leave("a")
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.motors.speed == (0, 0)
    assert desk.holder is None
    assert _error(desk.handle("b", {"type": "take"})) == ""


def test_stop_latches_whatever_the_controller_asks_until_resumed() -> None:
    desk = ControlDesk()
    robot = StandInRobot()
    desk.handle("a", {"type": "take"})
    assert desk.handle("a", {"type": "stop"}).stop_now  # the server sends the stop at once
    for _ in range(3):
        robot.motors.set_speed(700, 700)
        desk.guard(robot)  # type: ignore[arg-type]
        assert robot.motors.speed == (0, 0)
    desk.handle("a", {"type": "drive", "left": 300, "right": 300})
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.motors.speed == (0, 0)  # not even the page drives while stopped
    desk.leave("a")
    assert desk.halted  # the stop outlives the page that pressed it
    desk.handle("b", {"type": "take"})
    desk.handle("b", {"type": "resume"})
    robot.motors.set_speed(700, 700)
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.motors.speed == (700, 700)


@pytest.mark.parametrize(
    ("message", "error"),
    [
        ({"type": "drive", "left": 1001, "right": 0}, "-1000..1000"),
        ({"type": "drive", "left": 1.5, "right": 0}, "integer"),
        ({"type": "drive", "left": True, "right": 0}, "integer"),
        ({"type": "led", "index": "0", "on": True}, "integer index"),
        ({"type": "sensor", "family": "gps", "on": True}, "a family among"),
        ({"type": "key", "key": "F13"}, "no Webots key code"),
        ({"type": "fly"}, "unknown command type 'fly'"),
        ({"kind": "drive"}, "JSON object with a 'type'"),
        (["drive"], "JSON object with a 'type'"),
    ],
)
def test_bad_commands_are_refused_saying_why(message: Any, error: str) -> None:
    desk = ControlDesk()
    desk.handle("a", {"type": "take"})
    assert error in _error(desk.handle("a", message))


def test_keys_go_to_a_controller_that_reads_its_keyboard_and_then_do_not_drive() -> None:
    keys = Keys()
    desk = ControlDesk(keys)
    desk.handle("a", {"type": "take"})
    desk.handle("a", {"type": "key", "key": "ArrowUp"})
    assert keys.pressed == []  # nobody listens: the page's arrows drive instead
    keys.on = True
    desk.handle("a", {"type": "key", "key": "ArrowUp"})
    desk.handle("a", {"type": "key", "key": "w", "shift": True})
    assert keys.pressed == [315, ord("W") | 0x10000]
    assert "reads the keyboard" in _error(desk.handle("a", {"type": "drive", "left": 1,
                                                            "right": 1}))  # fmt: skip
    assert desk.state("a")["keyboard"] is True


def test_webots_key_codes() -> None:
    assert [webots_key({"key": k}) for k in ("ArrowLeft", "ArrowUp", "ArrowRight", "ArrowDown")] \
        == [314, 315, 316, 317]  # fmt: skip
    assert webots_key({"key": "a"}) == ord("A")  # Webots gives letters in upper case
    assert webots_key({"key": "1", "ctrl": True, "alt": True}) == ord("1") | 0x20000 | 0x40000
    assert webots_key({"key": "Shift"}) is None


def test_led_and_sensor_commands_run_in_the_steps_thread() -> None:
    desk = ControlDesk()
    robot = StandInRobot()
    desk.handle("a", {"type": "take"})
    desk.handle("a", {"type": "led", "index": 3, "on": True})
    assert robot.leds.on == {}  # nothing touched from the server's thread
    desk.guard(robot)  # type: ignore[arg-type]
    assert robot.leds.on == {3: 1}
