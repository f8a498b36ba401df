"""Webots' ``Emitter`` and ``Receiver``, over Zenoh (ego.zenoh_net.radio).

Webots' e-puck model carries a radio emitter and receiver (channel 1, unlimited range;
a swarm node on a .wbt world says the channels its world file gives them);
the real e-puck has none, so ego gives its controllers one over the network: Zenoh, on
``ego/radio/CHANNEL``. They exist (``getDevice("emitter")``) when eclipse-zenoh is
installed (``pip install ego[zenoh]``) and ``EGO_RADIO`` is not ``none``; otherwise
they are absent, with Webots' warning.

A robot's emitter and receiver share one :class:`RobotRadio`, owned by the Webots
``Robot`` that serves them (ego.controller.robot), opened at first use and closed with the
robot. It uses the robot's Zenoh session when the robot is a Zenoh node
(``zenoh://NAME``), else a session of its own on ``EGO_ZENOH_CONNECT`` /
``EGO_ZENOH_LISTEN`` (ego.zenoh_net.sessions), as the face's environment says.
As in Webots, a packet sent during a step is received at the next one; the queue keeps
a packet until ``nextPacket``, up to a bound (1024 packets, 1 MiB of data:
ego.zenoh_net.radio's BUFFER_PACKETS and BUFFER_BYTES), beyond which arriving packets
are dropped and counted
(``Receiver.dropped_packets``), as Webots' Receiver drops what its ``bufferSize`` cannot
hold.
Signal strength and direction come from the emulated world's true poses (on the
emulator, or a swarm), where the emitter's range is honoured too; on real robots they
are NaN.
"""

from __future__ import annotations

import importlib.util
import os
from typing import TYPE_CHECKING

from ego.controller.device import Device
from ego.core.environment import Environment, read_environment
from ego.errors import OutOfRangeError

if TYPE_CHECKING:
    from ego.core.robot import Robot as CoreRobot
    from ego.zenoh_net.radio import Radio

__all__ = ["RADIO_DEVICES", "RadioDevice", "RobotRadio", "check_channel", "radio_available"]

#: The names Webots' e-puck gives its radio devices.
RADIO_DEVICES = ("emitter", "receiver")
#: Webots' E-puck PROTO: emitter_channel and receiver_channel default to 1.
DEFAULT_CHANNEL = 1


def radio_available(environment: Environment) -> bool:
    """Whether robots get a radio: eclipse-zenoh is installed and EGO_RADIO is not none."""
    return environment.radio and importlib.util.find_spec("zenoh") is not None


class RobotRadio:
    """One robot's radio, shared by its emitter and receiver: made at first use, closed
    with the robot. Its owner is the Webots Robot that serves both devices."""

    def __init__(self, core: CoreRobot, environment: Environment) -> None:
        self._core = core
        self._environment = environment
        self._radio: Radio | None = None

    def get(self) -> Radio:
        """The radio, opened now if it is not yet."""
        if self._radio is None:
            import zenoh

            from ego.zenoh_net.radio import Radio
            from ego.zenoh_net.sessions import ZenohSettings, open_session

            core = self._core
            # A robot reached over Zenoh (even through a recording's tap) shares its session.
            session = core.channel.session_of(zenoh.Session)
            name = f"{core.port}@{os.uname().nodename}:{os.getpid()}"
            owns = session is None
            if session is None:
                session = open_session(ZenohSettings.from_environment(self._environment))
            radio = Radio(session, name, lambda: _true_pose(core), owns_session=owns)
            self._radio = radio
            core.add_closer(radio.close)
        return self._radio

    @property
    def dropped_total(self) -> int:
        """Packets this robot's radio lost (0 before it opened)."""
        return self._radio.dropped.total if self._radio is not None else 0


def _true_pose(core: CoreRobot) -> list[float] | None:
    truth = core.ground_truth
    pose = truth.pose() if truth is not None else None
    return None if pose is None else [pose.x_m, pose.y_m, pose.theta_rad]


def _start_channel(core: CoreRobot, name: str) -> int:
    """The channel a radio device starts on: its world file's, where the robot is a swarm
    node that says it (``ego swarm`` on a .wbt world), else the e-puck's 1."""
    given = getattr(core.channel, "radio_channels", None)
    if isinstance(given, tuple) and len(given) == 2:
        channel = given[0] if name == "emitter" else given[1]
        if isinstance(channel, int):
            return channel
    return DEFAULT_CHANNEL


def check_channel(channel: object) -> int:
    if isinstance(channel, bool) or not isinstance(channel, int) or channel < -1:
        raise OutOfRangeError(f"radio channel {channel!r} must be -1 (broadcast) or 0 and up")
    return channel


class RadioDevice(Device):
    """What the Emitter and the Receiver share: a channel, 1 by default."""

    CHANNEL_BROADCAST = -1

    def __init__(
        self,
        core: CoreRobot | str,
        name: str = "",
        *,
        strict: bool | None = None,
        radio: RobotRadio | None = None,
    ) -> None:
        if isinstance(core, str):
            self._made_by_name(core)  # the robot's own, already set up
            return
        super().__init__(core, name, strict=strict)
        self._channel = _start_channel(core, name)
        #: The robot's radio, shared with its other radio device (None: one of its own).
        self._radio = radio if radio is not None else RobotRadio(core, read_environment())

    def getChannel(self) -> int:
        return self._channel
