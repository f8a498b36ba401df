"""``Robot("zenoh://NAME")``: a robot served as a Zenoh node, from any machine of the
Zenoh network (the key space is keys.py's).

:class:`ZenohChannel` is the Channel: a batch is one query on ``ego/NAME/exchange``
carrying the batch's bytes and this controller's id; its reply is the reply bytes, or
the ego error the node met (raised here with its class and fields). While the
controller waits out a step it puts a keepalive, so that the node's deadman only fires
for a controller that stopped stepping; closing says bye (the robot stops).
"""

from __future__ import annotations

import json
import logging
import secrets
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from ego.backends.base import BackendOptions, Opened
from ego.backends.remote.channel import info_from
from ego.backends.remote.connection import error_from_reply
from ego.errors import LinkLostError, PortNotFoundError
from ego.serial.link import LinkStats
from ego.zenoh_net.keys import check_name, robot_key
from ego.zenoh_net.sessions import ZenohSettings, open_session

if TYPE_CHECKING:
    import zenoh

    from ego.core.environment import Environment
    from ego.serial.firmware import FirmwareInfo
    from ego.serial.protocol import Batch, Profile

__all__ = ["SCHEME", "ZenohBackend", "ZenohChannel", "ZenohOptions"]

log = logging.getLogger(__name__)

SCHEME = "zenoh"
#: How long one batch may take (the node may retry its serial line meanwhile).
QUERY_TIMEOUT_S = 2.0
#: A keepalive goes out at most this often while the controller waits.
KEEPALIVE_EVERY_S = 0.1


class ZenohChannel:
    """The channel to the robot node NAME (see the module's doc)."""

    def __init__(self, name: str, session: zenoh.Session, *, owns_session: bool = True) -> None:
        self.robot = check_name(name)
        self.session = session
        self._owns_session = owns_session
        self.id = f"{name}:{secrets.token_hex(8)}"
        self._who = self.id.encode()
        self._stats = LinkStats()
        self._last_sent = 0.0
        self._alive_until = 0.0
        self._keeper: threading.Thread | None = None
        self._closed = False
        #: The emulated world's true pose the node sent with the last reply, if any.
        #: The node's attachment to the last reply (its world's true pose, JSON), parsed
        #: only when read: most controllers never ask.
        self._truth_raw: bytes | None = None
        self._truth: list[float] | None = None
        self._keys: dict[str, str] = {}
        fields = self._query("info", b"", timeout_s=QUERY_TIMEOUT_S, what="info")
        self._info = info_from(json.loads(fields))

    @property
    def name(self) -> str:
        return f"{SCHEME}://{self.robot}"

    @property
    def info(self) -> FirmwareInfo:
        return self._info

    @property
    def stats(self) -> LinkStats:
        return self._stats

    @property
    def profile(self) -> Profile:
        return self._info.profile

    def _query(self, leaf: str, payload: bytes, *, timeout_s: float, what: str) -> bytes:
        if self._closed:
            raise LinkLostError(f"{self.name}: closed")
        key = self._keys.get(leaf)
        if key is None:
            key = self._keys[leaf] = robot_key(self.robot, leaf)
        replies = self.session.get(key, payload=payload, attachment=self._who, timeout=timeout_s)
        self._last_sent = time.monotonic()
        for reply in replies:
            if reply.ok is not None:
                attachment = reply.ok.attachment
                if attachment is not None:
                    self._truth_raw = attachment.to_bytes()
                return reply.ok.payload.to_bytes()
            if reply.err is not None:
                raise error_from_reply(reply.err.payload.to_bytes(), self.name)
        raise LinkLostError(f"{self.name}: no robot node answered {what} within {timeout_s} s "
                            "(is ego serve --zenoh running, and reachable?)")  # fmt: skip

    @property
    def truth(self) -> list[float] | None:
        """The emulated world's true pose the node sent with the last reply, if any."""
        raw, self._truth_raw = self._truth_raw, None
        if raw is not None:
            self._truth = json.loads(raw)
        return self._truth

    def exchange(self, batch: Batch) -> bytes:
        reply = self._query("exchange", batch.tx, timeout_s=QUERY_TIMEOUT_S, what="a batch")
        self._stats.batches += 1
        self._stats.bytes_sent += len(batch.tx)
        self._stats.bytes_received += len(reply)
        return reply

    def ascii_command(self, letter: str, lines: int = 1) -> list[str]:
        text = self._query("ascii", f"{letter},{lines}".encode(), timeout_s=QUERY_TIMEOUT_S,
                           what=f"ASCII {letter!r}")  # fmt: skip
        return text.decode("ascii", "replace").splitlines()

    def calibrate_proximity(self) -> list[str]:
        text = self._query("ascii", b"K,1", timeout_s=5.0, what="the calibration")
        return text.decode("ascii", "replace").splitlines()

    def waiting_until(self, deadline_s: float) -> None:
        """Keep the robot while its controller waits out a step, and no longer: a thread
        puts a keepalive every 0.1 s until ``deadline_s``."""
        self._alive_until = deadline_s
        if self._keeper is None:
            self._keeper = threading.Thread(target=self._keep, name="ego-zenoh-keepalive",
                                            daemon=True)  # fmt: skip
            self._keeper.start()

    def _keep(self) -> None:
        key, who = robot_key(self.robot, "keepalive"), self.id.encode()
        while not self._closed:
            now = time.monotonic()
            if now < self._alive_until and now - self._last_sent >= KEEPALIVE_EVERY_S:
                try:
                    self.session.put(key, b"", attachment=who)
                except Exception as exc:  # the session is closing
                    log.debug("keepalive: %s", exc)
                    return
                self._last_sent = now
            time.sleep(KEEPALIVE_EVERY_S / 4)

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        if self._keeper is not None:
            self._keeper.join(1)
        try:
            self.session.put(robot_key(self.robot, "bye"), b"", attachment=self.id.encode())
        finally:
            if self._owns_session:
                self.session.close()


@dataclass(frozen=True, kw_only=True)
class ZenohOptions(BackendOptions):
    """A Zenoh node's options; None: the default each names."""

    #: Endpoints to connect to (None: EGO_ZENOH_CONNECT, else the default node endpoint
    #: on loopback).
    zenoh_connect: Sequence[str] | None = None
    #: A Zenoh configuration file (None: EGO_ZENOH_CONFIG, else none).
    zenoh_config: str | None = None
    #: Endpoints this controller's session listens on (None: EGO_ZENOH_LISTEN, else an
    #: ephemeral port on loopback).
    zenoh_listen: Sequence[str] | None = None

    def with_environment(self, environment: Environment) -> ZenohOptions:
        settings = ZenohSettings.from_environment(
            environment, self.zenoh_listen, self.zenoh_connect, self.zenoh_config
        )
        return ZenohOptions(
            firmware=self.firmware,
            zenoh_connect=settings.connect,
            zenoh_config=settings.config_file,
            zenoh_listen=settings.listen,
        )


class ZenohBackend:
    """``zenoh://NAME``: the robot node NAME; options :class:`ZenohOptions`."""

    options: ClassVar[type[BackendOptions]] = ZenohOptions

    def open(self, port: str, options: BackendOptions) -> Opened:
        from ego.zenoh_net.sessions import DEFAULT_ENDPOINT

        given = ZenohOptions.narrow(options)
        firmware = given.firmware
        name = port.removeprefix(f"{SCHEME}://")
        settings = ZenohSettings(given.zenoh_listen, given.zenoh_connect, given.zenoh_config)
        if not settings.connect:
            settings.connect = [DEFAULT_ENDPOINT]
        session = open_session(settings)
        try:
            channel = ZenohChannel(name, session)
        except BaseException:
            session.close()
            raise
        if firmware is not None and channel.info.firmware is not firmware:
            channel.close()
            raise PortNotFoundError(
                f"{port} serves a robot with the {channel.info.firmware} firmware, not {firmware}"
            )
        return Opened(channel, remote=True, ground_truth=_Truth(channel))


class _Truth:
    """What a controller of an emulated robot node knows of its true pose (for the radio's
    signal strength): the pose the node sent with the last reply."""

    def __init__(self, channel: ZenohChannel) -> None:
        self.channel = channel

    def pose(self) -> list[float] | None:
        return self.channel.truth


def node_names(session: zenoh.Session, pattern: str, timeout_s: float = 1.0) -> list[str]:
    """The robot nodes whose names match ``pattern`` (``lab/*``), from their liveliness."""
    check_name(pattern, pattern=True)
    names = []
    for reply in session.liveliness().get(robot_key(pattern, "alive"), timeout=timeout_s):
        if reply.ok is not None:
            key = str(reply.ok.key_expr)
            names.append(key.removeprefix("ego/").removesuffix("/alive"))
    return sorted(set(names))
