"""A port's options: each backend declares them, and one function binds and checks them.

As python-can's ``load_config``: an option the port's backend does not declare is refused
with one line naming the scheme, the option and the options it takes; a value of the
wrong type is refused; None is the backend's default for every option, and an option
given is never lost on the way (a misspelt one included, None or not).
"""

from __future__ import annotations

import re

import pytest
from helpers import emulator_of

import ego
from ego.backends.remote import RemoteOptions
from ego.backends.serial_line import SerialOptions
from ego.backends.zenoh_remote import ZenohOptions
from ego.core.environment import Environment, read_environment
from ego.core.registry import bind_options, open_port, option_names, takes_option
from ego.errors import BackendOptionError, EgoError
from ego.seam.profile import Firmware
from firmware_sim.ego_backend import SimOptions

EMPTY = Environment()


@pytest.mark.parametrize(
    ("port", "option"),
    [("sim", "sed"), ("loop://", "seed"), ("replay://run.mcap", "baudrate"),
     ("tcp://127.0.0.1:1", "seed"), ("zenoh://lab/e1", "baudrate")],
)  # fmt: skip
def test_an_option_the_backend_does_not_declare_is_refused_naming_what_it_takes(
    port: str, option: str
) -> None:
    with pytest.raises(BackendOptionError) as caught:
        bind_options(port, {option: 1}, EMPTY)
    scheme = port.partition("://")[0] if "://" in port else port
    scheme = "serial" if scheme == "loop" else scheme
    taken = ", ".join(option_names(port))
    assert str(caught.value) == f"{scheme} ports take no option {option!r} (they take: {taken})"
    assert isinstance(caught.value, ValueError) and isinstance(caught.value, EgoError)


def test_a_misspelt_option_set_to_none_is_refused_too() -> None:
    # Robot used to drop every option whose value was None before the backend saw it:
    # a misspelt one then passed unnoticed.
    with pytest.raises(BackendOptionError, match="sim ports take no option 'sed'"):
        ego.Robot("sim", sed=None)


def test_a_value_of_the_wrong_type_is_refused_before_the_port_opens() -> None:
    with pytest.raises(BackendOptionError, match=r"sim option seed='three' must be int \| None"):
        ego.Robot("sim", seed="three")
    text = re.escape("zenoh_connect='tcp/127.0.0.1:1' must be ")
    with pytest.raises(BackendOptionError, match=text):
        bind_options("zenoh://e1", {"zenoh_connect": "tcp/127.0.0.1:1"}, EMPTY)  # not a list
    with pytest.raises(BackendOptionError, match="timeout_s=True must be float"):
        bind_options("tcp://127.0.0.1:1", {"timeout_s": True}, EMPTY)


def test_an_options_own_check_still_says_what_is_wrong() -> None:
    with pytest.raises(TypeError, match="baud rate must be an int, not str"):
        bind_options("/dev/ttyS0", {"baudrate": "fast"}, EMPTY)


def test_none_is_the_backends_default_for_every_option() -> None:
    for port, declared in [("sim", SimOptions), ("/dev/ttyS0", SerialOptions),
                           ("tcp://h:1", RemoteOptions), ("zenoh://e1", ZenohOptions)]:  # fmt: skip
        names = option_names(port)
        bound = bind_options(port, dict.fromkeys(names), EMPTY)
        assert bound == bind_options(port, {}, EMPTY)
        assert isinstance(bound, declared)


def test_an_option_given_is_never_lost() -> None:
    given: dict[str, object] = {
        "firmware": Firmware.GCTRONIC, "baudrate": 115200, "seed": 0, "virtual_time": False,
        "world": "arena", "rev13": False, "selector": 0, "ground_module": False,
        "latency_s": 0.0, "hardware_version": 0,
    }  # fmt: skip
    bound = bind_options("sim", given, EMPTY)
    assert {name: getattr(bound, name) for name in given} == given
    with ego.Robot("sim", seed=0, ground_module=False, selector=0, firmware="gctronic") as robot:
        dspic = emulator_of(robot).dspic  # falsy values reach the emulator
        assert (dspic.selector, dspic.ground_module) == (0, False)
        assert robot.channel.info.firmware is Firmware.GCTRONIC


def test_takes_option_is_answered_from_the_declaration() -> None:
    assert takes_option("tcp://127.0.0.1:1", "secret")
    assert takes_option("udp://127.0.0.1:1", "connect_timeout_s")  # was **connection
    assert not takes_option("sim", "secret")
    assert not takes_option("/dev/ttyS0", "secret")
    assert option_names("replay://run.mcap") == ("firmware",)


def test_the_environment_fills_in_what_was_not_given() -> None:
    env = read_environment({
        "EGO_CAMERA": "none", "EGO_SECRET": "s3cret-s3cret-s3cret",
        "EGO_ZENOH_CONNECT": "tcp/127.0.0.1:7999, tcp/127.0.0.1:7998",
        "EGO_ZENOH_CONFIG": "zenoh.json5",
    })  # fmt: skip
    serial = bind_options("/dev/ttyS0", {}, env)
    assert isinstance(serial, SerialOptions) and serial.camera_device == "none"
    named = bind_options("/dev/ttyS0", {"camera_device": "/dev/video2"}, env)
    assert isinstance(named, SerialOptions) and named.camera_device == "/dev/video2"
    remote = bind_options("tcp://h:1", {}, env)
    assert isinstance(remote, RemoteOptions) and remote.secret == b"s3cret-s3cret-s3cret"
    zenoh = bind_options("zenoh://e1", {}, env)
    assert isinstance(zenoh, ZenohOptions)
    assert list(zenoh.zenoh_connect or ()) == ["tcp/127.0.0.1:7999", "tcp/127.0.0.1:7998"]
    assert zenoh.zenoh_config == "zenoh.json5"


def test_open_port_binds_before_it_opens() -> None:
    with pytest.raises(BackendOptionError, match="serial ports take no option 'seed'"):
        open_port("/dev/ego-no-such-port", seed=3)  # refused before the port is tried
