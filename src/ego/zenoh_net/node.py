"""``ego serve --zenoh``: a robot as a Zenoh node (the key space is keys.py's).

The node answers its controller's batches on ``ego/NAME/exchange`` (a queryable, served
by one worker thread of its own so that Zenoh's threads never wait on the serial line),
publishes every step's sample on ``ego/NAME/sensors``, answers ``ego/NAME/info``, and
keeps ``ego/NAME/alive`` while it runs. The rules are ``ego serve``'s:

- one controller holds the robot (:class:`ControlLease`: the first to send a batch,
  known by the id its queries carry); another's batches are refused with RobotBusyError;
- if the holder sends nothing new for ``deadline_s`` (no batch, no keepalive) or says
  bye, the deadman (a thread of its own) stops the wheels and frees the robot;
- a malformed query (no id, a payload that is not a batch of this firmware, too long)
  is refused with the reason, before it can reach the robot.
"""

from __future__ import annotations

import json
import logging
import queue
import threading
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ego.dashboard.served import WatchedChannel
from ego.errors import EgoError, ProtocolError, RobotBusyError
from ego.remote.service import firmware_fields
from ego.remote.wire import error_fields, pack_error
from ego.safety import send_stop
from ego.serial.protocol import parse_batch
from ego.zenoh_net.keys import check_name, robot_key

if TYPE_CHECKING:
    import zenoh

    from ego.channel import Channel

__all__ = ["MAX_BATCH_BYTES", "ControlLease", "RobotNode"]

log = logging.getLogger(__name__)

#: The longest batch a query may carry (a step of every command is under 100 bytes).
MAX_BATCH_BYTES = 1024
#: A controller's id: what its queries carry as their attachment (UTF-8, 1..64 bytes).
MAX_ID_BYTES = 64


@dataclass
class ControlLease:
    """Who holds the robot and when they were last heard (sans-I/O: times are given)."""

    deadline_s: float
    holder: str | None = None
    last_heard: float = 0.0

    def claim(self, who: str, now: float) -> bool:
        """``who`` sends a batch: theirs if free (or already theirs); False if another's."""
        if self.holder not in (None, who):
            return False
        self.holder, self.last_heard = who, now
        return True

    def heard(self, who: str, now: float) -> None:
        if who == self.holder:
            self.last_heard = now

    def release(self, who: str) -> bool:
        """``who`` lets go; whether they held it."""
        if who != self.holder:
            return False
        self.holder = None
        return True

    def expire(self, now: float) -> bool:
        """Free the robot if its holder has been silent past the deadline; whether it was."""
        if self.holder is not None and now - self.last_heard > self.deadline_s:
            self.holder = None
            return True
        return False


class RobotNode:
    """Serves ``channel`` as the Zenoh node NAME on ``session`` (see the module's doc)."""

    def __init__(
        self,
        channel: Channel,
        session: zenoh.Session,
        name: str,
        *,
        deadline_s: float = 0.5,
        world: Any = None,
    ) -> None:
        self.name = check_name(name)
        self.session = session
        self.watched = WatchedChannel(channel, on_sample=self._publish, world=world)
        self.lease = ControlLease(deadline_s)
        self.world = world
        self._lock = threading.Lock()  # the lease, between the worker and the deadman
        self._closing = threading.Event()
        self._entities: list[Any] = []
        self._threads: list[threading.Thread] = []
        self._publisher: Any = None
        #: What the node refused, by reason (tests and logs).
        self.refused: dict[str, int] = {}
        self.stops = 0

    # -- life ----------------------------------------------------------------------------

    def start(self) -> RobotNode:
        key = lambda leaf: robot_key(self.name, leaf)  # noqa: E731
        session = self.session
        self._publisher = session.declare_publisher(key("sensors"))
        # Zenoh's thread only queues a batch's query; a thread of ours runs it (the serial
        # line takes milliseconds) and can be told to end: a Python thread left inside
        # Zenoh at interpreter exit would abort the process.
        self._queries: queue.Queue[Any] = queue.Queue(maxsize=64)
        self._entities += [
            self._publisher,
            session.declare_queryable(key("exchange"), self._queue_query),
            session.declare_queryable(key("info"), self._info),
            session.declare_queryable(key("ascii"), self._ascii),
            session.declare_subscriber(key("keepalive"), self._keepalive),
            session.declare_subscriber(key("bye"), self._bye),
            session.liveliness().declare_token(key("alive")),
        ]
        workers = ((self._serve, "batches"), (self._watch, "deadman"))
        for target, label in workers:
            thread = threading.Thread(target=target, name=f"ego-zenoh-{label}", daemon=True)
            thread.start()
            self._threads.append(thread)
        log.info("robot %s served on Zenoh (%s firmware)", self.name, self.watched.info.firmware)
        return self

    def close(self) -> None:
        """Stop serving, then stop the robot's wheels and LEDs."""
        self._closing.set()
        for entity in reversed(self._entities):
            try:
                entity.undeclare()
            except Exception as exc:  # the session may be closing too
                log.debug("undeclaring %s: %s", entity, exc)
        for thread in self._threads:
            thread.join(2)
        self.stop()

    def stop(self) -> None:
        """The confirmed stop batch (wheels 0, LEDs off)."""
        try:
            with self.watched.lock:
                send_stop(self.watched.inner)
            self.stops += 1
        except (EgoError, OSError) as exc:
            log.error("robot %s: could not stop: %s", self.name, exc)

    # -- queries -------------------------------------------------------------------------

    def _queue_query(self, query: Any) -> None:
        try:
            self._queries.put_nowait(query)
        except queue.Full:  # a flood: refused rather than queued without end
            self._refuse(query, "flood", RobotBusyError(f"robot {self.name} is overloaded"))

    def _serve(self) -> None:
        while not self._closing.is_set():
            try:
                query = self._queries.get(timeout=0.05)
            except queue.Empty:
                continue
            try:
                self._exchange(query)
            finally:
                query.drop()

    def _exchange(self, query: Any) -> None:
        who = _id(query)
        payload = query.payload.to_bytes() if query.payload is not None else b""
        if who is None:
            why = "a batch must carry its controller's id (1..64 UTF-8 bytes) as attachment"
            return self._refuse(query, "no id", ProtocolError(why))
        if not 0 < len(payload) <= MAX_BATCH_BYTES:
            return self._refuse(query, "size", ProtocolError(
                f"a batch of {len(payload)} bytes (1..{MAX_BATCH_BYTES} accepted)"))  # fmt: skip
        try:
            batch = parse_batch(payload, self.watched.profile)
        except (ValueError, EgoError) as exc:
            return self._refuse(query, "malformed", ProtocolError(f"not a batch: {exc}"))
        with self._lock:
            claimed = self.lease.claim(who, time.monotonic())
        if not claimed:
            return self._refuse(query, "busy", RobotBusyError(
                f"robot {self.name} is driven by another controller"))  # fmt: skip
        try:
            reply = self.watched.exchange(batch)
        except EgoError as exc:
            query.reply_err(pack_error(type(exc).__name__, str(exc), error_fields(exc)))
            return None
        truth = self.watched.last_truth
        pose = json.dumps(truth).encode() if truth is not None else None
        query.reply(query.key_expr, reply, attachment=pose)
        return None

    def _refuse(self, query: Any, reason: str, error: EgoError) -> None:
        self.refused[reason] = self.refused.get(reason, 0) + 1
        log.warning("robot %s: refused a batch (%s): %s", self.name, reason, error)
        query.reply_err(pack_error(type(error).__name__, str(error), error_fields(error)))

    def _info(self, query: Any) -> None:
        info = {**firmware_fields(self.watched.info), "name": self.name,
                "emulated": self.world is not None, "devices": self.watched.device_families(),
                "battery": self.watched.battery}  # fmt: skip
        query.reply(query.key_expr, json.dumps(info).encode())

    def _ascii(self, query: Any) -> None:
        who = _id(query)
        text = query.payload.to_bytes().decode("ascii", "replace") if query.payload else ""
        letter, _, lines = text.partition(",")
        if letter not in ("V", "C", "S", "K") or (lines and not lines.isdigit()):
            query.reply_err(pack_error("ProtocolError", f"ASCII command {text!r} refused: "
                                       "V, C, S or K, then ',LINES'"))  # fmt: skip
            return
        if letter in ("S", "K"):
            with self._lock:
                claimed = who is not None and self.lease.claim(who, time.monotonic())
            if not claimed:
                query.reply_err(pack_error("RobotBusyError", f"robot {self.name} is driven "
                                           "by another controller"))  # fmt: skip
                return
        try:
            with self.watched.lock:
                if letter == "K":
                    got = self.watched.inner.calibrate_proximity()
                else:
                    got = self.watched.inner.ascii_command(letter, int(lines or 1))
        except EgoError as exc:
            query.reply_err(pack_error(type(exc).__name__, str(exc), error_fields(exc)))
            return
        query.reply(query.key_expr, "\n".join(got).encode("ascii", "replace"))

    # -- the controller's puts, and the deadman --------------------------------------------

    def _keepalive(self, sample: Any) -> None:
        who = _id(sample)
        if who is not None:
            with self._lock:
                self.lease.heard(who, time.monotonic())

    def _bye(self, sample: Any) -> None:
        who = _id(sample)
        with self._lock:
            released = who is not None and self.lease.release(who)
        if released:
            self.stop()

    def _watch(self) -> None:
        while not self._closing.wait(0.01):
            with self._lock:
                expired = self.lease.expire(time.monotonic())
            if expired:
                log.warning("robot %s: its controller went silent; stopping it", self.name)
                self.stop()

    def _publish(self, sample: dict[str, Any]) -> None:
        if self._publisher is not None and not self._closing.is_set():
            self._publisher.put(json.dumps(sample).encode())


def _id(message: Any) -> str | None:
    """The controller id a query or put carries (its attachment), or None if malformed."""
    attachment = message.attachment
    raw = attachment.to_bytes() if attachment is not None else b""
    try:
        who = raw.decode("utf-8")
    except UnicodeDecodeError:
        return None
    return who if 0 < len(raw) <= MAX_ID_BYTES else None
