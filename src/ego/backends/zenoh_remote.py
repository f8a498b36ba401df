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
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, TypeVar

from ego.backends.remote.channel import info_from
from ego.backends.remote.connection import error_from_reply
from ego.backends.zenoh_scene import RemoteScene
from ego.core.backend import BackendOptions, Opened
from ego.core.ground_truth import TruePose
from ego.errors import FirmwareMismatchError, LinkLostError, LinkTimeoutError
from ego.nursery import Nursery
from ego.seam.channel import ChannelBase
from ego.zenoh_net.keys import check_name, robot_key
from ego.zenoh_net.sessions import ZenohSettings, open_session

if TYPE_CHECKING:
    import zenoh

    from ego.core.environment import Environment
    from ego.seam.batch import Batch

__all__ = ["SCHEME", "ZenohBackend", "ZenohChannel", "ZenohOptions"]

log = logging.getLogger(__name__)

T = TypeVar("T")

SCHEME = "zenoh"
#: How long one batch may take (the node may retry its serial line meanwhile).
QUERY_TIMEOUT_S = 2.0
#: The error Zenoh itself replies to a query whose replies did not all come in time (a
#: node's own errors are JSON, ego.net.payloads.pack_error).
ZENOH_TIMEOUT = b"Timeout"
#: A keepalive goes out at most this often while the controller waits.
KEEPALIVE_EVERY_S = 0.1


class _Keeper:
    """The owner of a channel's keepalive thread: it starts the thread, which calls
    ``put`` every ``KEEPALIVE_EVERY_S / 4`` until :meth:`stop` (which joins it). An error
    of ``put`` ends the thread, logged, and is kept in :attr:`failure` for the channel
    to raise at its next exchange."""

    def __init__(self, put: Callable[[], None]) -> None:
        self._put = put
        self._stop = threading.Event()
        self.failure: Exception | None = None
        self._threads = Nursery("a Zenoh channel's keepalive", at_exit=self._stop.set)
        self._threads.start_thread(self._run, name="ego-zenoh-keepalive")

    def _run(self) -> None:
        while not self._stop.wait(KEEPALIVE_EVERY_S / 4):
            try:
                self._put()
            except Exception as exc:  # zenoh raises its own ZError: any is the end
                log.warning("keepalive failed, the node's deadman will stop the robot: %s", exc)
                self.failure = exc
                return

    def stop(self) -> None:
        self._stop.set()
        self._threads.close()


class ZenohChannel(ChannelBase):
    """The channel to the robot node NAME (see the module's doc)."""

    def __init__(self, name: str, session: zenoh.Session, *, owns_session: bool = True) -> None:
        super().__init__()
        self.robot = check_name(name)
        self.session = session
        self._owns_session = owns_session
        self.id = f"{name}:{secrets.token_hex(8)}"
        self._who = self.id.encode()
        self._last_sent = 0.0
        self._alive_until = 0.0
        self._keeper: _Keeper | None = None
        #: The node's attachment to the last reply (its world's true pose, JSON), parsed
        #: only when read: most controllers never ask.
        self._truth_raw: bytes | None = None
        self._truth: list[float] | None = None
        self._keys: dict[str, str] = {}
        fields = json.loads(self._query("info", b"", timeout_s=QUERY_TIMEOUT_S, what="info"))
        self._info = info_from(fields)
        #: Whether the node serves its world's scene (an emulated swarm robot's).
        self.serves_scene = fields.get("scene") is True
        #: The channels the node's world file starts its Emitter and Receiver on (None:
        #: not set, each starts on the e-puck's 1).
        self.radio_channels = _radio_channels(fields.get("radio"))

    @property
    def name(self) -> str:
        return f"{SCHEME}://{self.robot}"

    def session_of(self, kind: type[T]) -> T | None:
        return self.session if isinstance(self.session, kind) else None

    @property
    def keepalive_failure(self) -> Exception | None:
        """Why the keepalive thread stopped putting (the session closed under it...); the
        next exchange raises LinkLostError naming it. None while it runs."""
        return self._keeper.failure if self._keeper is not None else None

    def _query(self, leaf: str, payload: bytes, *, timeout_s: float, what: str) -> bytes:
        failure = self.keepalive_failure
        if failure is not None:
            raise LinkLostError(f"{self.name}: the keepalive failed, so the node may have "
                                f"stopped the robot: {failure}") from failure  # fmt: skip
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
                error = reply.err.payload.to_bytes()
                if error == ZENOH_TIMEOUT:  # Zenoh's own reply: no node answered in time
                    raise LinkTimeoutError(f"{self.name}: the robot node did not answer "
                                           f"{what} within {timeout_s} s")  # fmt: skip
                raise error_from_reply(error, self.name)
        raise LinkLostError(f"{self.name}: no robot node answered {what} within {timeout_s} s "
                            "(is ego serve --zenoh running, and reachable?)")  # fmt: skip

    @property
    def truth(self) -> list[float] | None:
        """The emulated world's true pose the node sent with the last reply, if any."""
        raw, self._truth_raw = self._truth_raw, None
        if raw is not None:
            self._truth = json.loads(raw)
        return self._truth

    def _exchange(self, batch: Batch) -> bytes:
        return self._query("exchange", batch.tx, timeout_s=QUERY_TIMEOUT_S, what="a batch")

    def _ascii_command(self, letter: str, lines: int) -> list[str]:
        text = self._query("ascii", f"{letter},{lines}".encode(), timeout_s=QUERY_TIMEOUT_S,
                           what=f"ASCII {letter!r}")  # fmt: skip
        return text.decode("ascii", "replace").splitlines()

    def _calibrate_proximity(self) -> list[str]:
        text = self._query("ascii", b"K,1", timeout_s=5.0, what="the calibration")
        return text.decode("ascii", "replace").splitlines()

    def waiting_until(self, deadline_s: float) -> None:
        """Keep the robot while its controller waits out a step, and no longer: a thread
        puts a keepalive every 0.1 s until ``deadline_s``."""
        self._alive_until = deadline_s
        if self._keeper is None and not self.closed:
            key = robot_key(self.robot, "keepalive")
            self._keeper = _Keeper(lambda: self._keep_alive(key))

    def _keep_alive(self, key: str) -> None:
        now = time.monotonic()
        if now < self._alive_until and now - self._last_sent >= KEEPALIVE_EVERY_S:
            self.session.put(key, b"", attachment=self._who)
            self._last_sent = now

    def _close(self) -> None:
        keeper, self._keeper = self._keeper, None
        if keeper is not None:
            keeper.stop()
        try:
            self.session.put(robot_key(self.robot, "bye"), b"", attachment=self._who)
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
            raise FirmwareMismatchError(
                f"{port} serves a robot with the {channel.info.firmware} firmware, not {firmware}"
            )
        scene = RemoteScene(session, channel.robot) if channel.serves_scene else None
        return Opened(channel, remote=True, ground_truth=_Truth(channel), scene=scene)


class _Truth:
    """What a controller of an emulated robot node knows of its true pose (for the radio's
    signal strength): the pose the node sent with the last reply; not the whole world
    (ego.core.ground_truth.GroundTruth)."""

    def __init__(self, channel: ZenohChannel) -> None:
        self.channel = channel

    def pose(self) -> TruePose | None:
        sent = self.channel.truth
        return None if sent is None else TruePose(*(float(v) for v in sent[:3]))

    @property
    def true_world(self) -> None:
        return None


def _radio_channels(value: object) -> tuple[int | None, int | None] | None:
    """The emitter's and receiver's channels a node's info gives, if well formed."""
    if not (isinstance(value, list) and len(value) == 2):
        return None
    if not all(v is None or (isinstance(v, int) and not isinstance(v, bool) and v >= -1)
               for v in value):  # fmt: skip
        return None
    return value[0], value[1]


def node_names(session: zenoh.Session, pattern: str, timeout_s: float = 1.0) -> list[str]:
    """The robot nodes whose names match ``pattern`` (``lab/*``), from their liveliness."""
    check_name(pattern, pattern=True)
    names = []
    for reply in session.liveliness().get(robot_key(pattern, "alive"), timeout=timeout_s):
        if reply.ok is not None:
            key = str(reply.ok.key_expr)
            names.append(key.removeprefix("ego/").removesuffix("/alive"))
    return sorted(set(names))
