"""``ego serve --zenoh``: a robot as a Zenoh node (the key space is keys.py's).

The node answers its controller's batches on ``ego/NAME/exchange`` and ASCII commands
on ``ego/NAME/ascii``, publishes every step's sample on ``ego/NAME/sensors``, answers
``ego/NAME/info``, and keeps ``ego/NAME/alive`` while it runs. An emulated robot of a
swarm also answers a Supervisor's requests of its world on ``ego/NAME/scene``
(ego.zenoh_net.scene_codec; anyone's, outside the lease). The rules are
``ego serve``'s:

- one controller holds the robot (the lease of the
  :class:`~ego.servers.sessions.control.ControlSession` ``ego serve`` runs too, held by
  the first to send a batch or an ASCII command, known by the id its queries carry);
  another's queries, ASCII ones included, are refused with RobotBusyError as they
  arrive, before they are queued;
- if the holder sends nothing new for ``deadline_s`` (no batch, no keepalive) while
  none of its queries runs, or says bye, the deadman (a thread of its own) has the
  wheels stopped, drops the holder's queued queries, and frees the robot;
- a malformed query (no id, a payload that is not a batch of this firmware, too long,
  an ASCII command asking for too many lines) is refused with the reason (admission.py).

Zenoh's threads never run Python: queries wait in Zenoh for a thread of ours that
checks and queues them (intake.py); one worker owns the serial line (line.py) and runs
the stop ahead of every queued query, so a flood never delays the deadman. Refusals are
counted (``refused``) and logged once, then periodically.
"""

from __future__ import annotations

import json
import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ego.errors import EgoError, ProtocolError, RobotBusyError
from ego.net.payloads import error_fields, pack_error
from ego.nursery import DeadlineTimer, Nursery
from ego.servers.dashboard.served import WatchedChannel
from ego.servers.service import firmware_fields
from ego.servers.sessions.control import ControlSession, Lapsed
from ego.servers.zenoh_node.admission import (
    MAX_BATCH_BYTES,
    check_ascii,
    check_batch,
    check_lease,
    controller_id,
)
from ego.servers.zenoh_node.intake import Intake
from ego.servers.zenoh_node.line import LineWorker
from ego.zenoh_net.keys import check_name, robot_key
from ego.zenoh_net.tally import Tally

if TYPE_CHECKING:
    import zenoh

    from ego.core.ground_truth import GroundTruth
    from ego.core.scene import Scene
    from ego.seam.batch import Batch
    from ego.seam.channel import Channel

__all__ = ["MAX_BATCH_BYTES", "RobotNode"]

log = logging.getLogger(__name__)
#: What a checked query does on the line: given the query and its controller's id.
Work = Callable[[Any, str], None]


@dataclass
class _Query:
    """A checked query waiting for the line: ``work`` runs it there."""

    who: str
    query: Any
    work: Work

    def run(self) -> None:
        try:
            self.work(self.query, self.who)
        finally:
            self.query.drop()

    def cancel(self, why: str) -> None:
        try:
            self.query.reply_err(pack_error("RobotBusyError", why))
            self.query.drop()
        except Exception as exc:  # the node is closing: its queryable may be gone
            log.debug("cancelling a query: %s", exc)


class RobotNode:
    """Serves ``channel`` as the Zenoh node NAME on ``session`` (see the module's doc)."""

    def __init__(
        self,
        channel: Channel,
        session: zenoh.Session,
        name: str,
        *,
        deadline_s: float = 0.5,
        world: GroundTruth | None = None,
        clock: Callable[[], float] = time.monotonic,
        scene: Scene | None = None,
        radio: tuple[int | None, int | None] | None = None,
    ) -> None:
        self.name = check_name(name)
        self.session = session
        self.watched = WatchedChannel(channel, on_sample=self._publish, world=world)
        #: The lease, the deadman, one query in flight: held by the controller's id.
        self.lease: ControlSession[str] = ControlSession(deadline_s)
        #: The deadman's firings, newest last (the last 64): whose, and after how long a
        #: silence on the node's own clock (what the stop's promise is measured on).
        self.lapses: deque[Lapsed[str]] = deque(maxlen=64)
        self._clock = clock
        self.world = world
        #: The simulated world a Supervisor of this robot sees (``ego/NAME/scene``), if any.
        self.scene = scene
        #: The channels its Emitter and Receiver start on, where its world file sets them.
        self.radio = radio
        self._lock = threading.Lock()  # the lease: the intakes, the puts, the worker, the deadman
        self._closing = threading.Event()
        self._entities: list[Any] = []
        #: The node's threads: the line's worker, the intakes', the deadman's timer.
        self.threads = Nursery(f"robot node {self.name}", join_s=2.0)
        self._line = LineWorker(self.stop, name=f"ego-zenoh-line-{self.name}",
                                nursery=self.threads)  # fmt: skip
        #: The deadman: sleeps until the holder's deadline (set once started).
        self.deadman: DeadlineTimer | None = None
        self._publisher: Any = None
        self._busy = f"robot {self.name} is driven by another controller"
        self._busy_reply = pack_error("RobotBusyError", self._busy)
        #: What the node refused, by reason ("busy", "malformed", "flood"; tests, logs).
        self.refused = Tally(log, f"robot {self.name}: refused a query")
        self.stops = 0

    # -- life ----------------------------------------------------------------------------

    def start(self) -> RobotNode:
        key = lambda leaf: robot_key(self.name, leaf)  # noqa: E731
        session = self.session
        self._publisher = session.declare_publisher(key("sensors"))
        # Queries wait in Zenoh (intake.py) for a thread of ours that checks and queues
        # them; the line's worker runs them (the serial line takes milliseconds). All can
        # be told to end: a Python thread left inside Zenoh at exit would abort the process.
        self._line.start()
        self.deadman = self.threads.start_timer(
            self._deadline_passed, name=f"ego-zenoh-deadman-{self.name}", clock=self._clock
        )
        self._entities.append(self._publisher)
        declare: list[Callable[[], Any]] = [
            lambda: Intake(session, key("exchange"), self._on_exchange, self.threads),
            lambda: Intake(session, key("info"), self._info, self.threads),
            lambda: Intake(session, key("ascii"), self._on_ascii, self.threads),
            lambda: session.declare_subscriber(key("keepalive"), self._keepalive),
            lambda: session.declare_subscriber(key("bye"), self._bye),
            lambda: session.liveliness().declare_token(key("alive")),
        ]
        scene = self.scene
        if scene is not None:  # anyone's: a Supervisor reads and moves the world, not the robot
            declare.append(
                lambda: Intake(session, key("scene"), lambda q: _answer(scene, q), self.threads)
            )
        try:
            for entity in declare:
                self._entities.append(entity())
        except BaseException:
            self.close()  # the threads started above end with it
            raise
        log.info("robot %s served on Zenoh (%s firmware)", self.name, self.watched.info.firmware)
        return self

    def close(self) -> None:
        """Stop serving, then stop the robot's wheels and LEDs; a thread of the node still
        running then is a :class:`~ego.errors.ThreadLeakError` (after the stop)."""
        self._closing.set()
        for entity in reversed(self._entities):
            try:
                entity.undeclare()
            except Exception as exc:  # the session may be closing too
                log.debug("undeclaring %s: %s", entity, exc)
        self._line.close(f"robot {self.name} is no longer served")
        try:
            self.threads.close()
        finally:
            self.stop()

    def stop(self) -> None:
        """The confirmed stop batch (wheels 0, LEDs off), on the line's worker (or at close)."""
        try:
            self.watched.stop()
            self.stops += 1
        except (EgoError, OSError) as exc:
            log.error("robot %s: could not stop: %s", self.name, exc)

    # -- queries: checked as they arrive (the intakes' threads), run by the line's worker --

    def _admit(self, query: Any, prepare: Callable[[], Work]) -> None:
        """Check ``query`` (its id, the lease, ``prepare``'s checks) and queue its work."""
        holder = self.lease.holder  # read without the lock: the fast refusal of a flood
        if holder is not None and _attachment(query) != holder.encode():
            self.refused.add("busy", self._busy)
            query.reply_err(self._busy_reply)
            return None
        try:
            who = controller_id(_attachment(query))
            with self._lock:
                check_lease(self.lease, who, self._clock(), self.name)
            work = prepare()
        except RobotBusyError as exc:
            return self._refuse(query, "busy", exc)
        except ProtocolError as exc:
            return self._refuse(query, "malformed", exc)
        if not self._line.submit(_Query(who, query, work)):  # a flood: refused, not queued
            self._refuse(query, "flood", RobotBusyError(f"robot {self.name} is overloaded"))
        return None

    def _on_exchange(self, query: Any) -> None:
        def prepare() -> Work:
            payload = query.payload.to_bytes() if query.payload is not None else b""
            batch = check_batch(payload, self.watched.profile)
            return lambda q, who: self._exchange(q, who, batch)

        self._admit(query, prepare)

    def _on_ascii(self, query: Any) -> None:
        def prepare() -> Work:
            raw = query.payload.to_bytes()[:64] if query.payload is not None else b""
            letter, lines = check_ascii(raw.decode("ascii", "replace"))
            return lambda q, who: self._ascii(q, who, letter, lines)

        self._admit(query, prepare)

    def _dispatch(self, query: Any, who: str, run: Callable[[], None]) -> None:
        """``who`` takes the robot as its query runs (refused if another holds it); the
        deadman waits while it runs, and counts anew from its end."""
        with self._lock:
            now = self._clock()
            taken = self.lease.take(who, now) and self.lease.dispatch(who, now) is None
        if not taken:
            self._refuse(query, "busy", RobotBusyError(self._busy))
            return
        try:
            run()
        except EgoError as exc:
            query.reply_err(pack_error(type(exc).__name__, str(exc), error_fields(exc)))
        finally:
            with self._lock:
                self.lease.completed(who, self._clock())
                due = self.lease.due_at()
            if due is not None and self.deadman is not None:
                self.deadman.arm(due)  # the deadline counts anew from the call's end

    def _exchange(self, query: Any, who: str, batch: Batch) -> None:
        def run() -> None:
            reply = self.watched.exchange(batch)
            truth = self.watched.last_truth
            pose = json.dumps(truth).encode() if truth is not None else None
            query.reply(query.key_expr, reply, attachment=pose)

        self._dispatch(query, who, run)

    def _ascii(self, query: Any, who: str, letter: str, lines: int) -> None:
        def run() -> None:
            if letter == "K":
                got = self.watched.calibrate_proximity()
            else:
                got = self.watched.ascii_command(letter, lines)
            query.reply(query.key_expr, "\n".join(got).encode("ascii", "replace"))

        self._dispatch(query, who, run)

    def _refuse(self, query: Any, reason: str, error: EgoError) -> None:
        self.refused.add(reason, str(error))
        query.reply_err(pack_error(type(error).__name__, str(error), error_fields(error)))

    def _info(self, query: Any) -> None:
        info = {**firmware_fields(self.watched.info), "name": self.name,
                "emulated": self.world is not None, "devices": self.watched.device_families(),
                "battery": self.watched.battery, "scene": self.scene is not None,
                **({"radio": list(self.radio)} if self.radio is not None else {})}  # fmt: skip
        query.reply(query.key_expr, json.dumps(info).encode())

    # -- the controller's puts, and the deadman --------------------------------------------

    def _keepalive(self, sample: Any) -> None:
        try:
            who = controller_id(_attachment(sample))
        except ProtocolError:
            return  # a put is not answered: nothing to tell, nothing to keep
        with self._lock:
            self.lease.heard(who, self._clock())

    def _bye(self, sample: Any) -> None:
        try:
            who = controller_id(_attachment(sample))
        except ProtocolError:
            return
        with self._lock:
            released = self.lease.release(who)
        if released:
            self._stop_for(who, f"robot {self.name}: its controller said bye")

    def _deadline_passed(self, now: float) -> float | None:
        """The deadman's timer fired: the robot stopped at once if its holder went silent;
        the next deadline (None while nobody holds it or a call runs: a call's end arms it)."""
        with self._lock:
            lapsed = self.lease.tick(now)
            due = self.lease.due_at()
        if lapsed is not None:
            self.lapses.append(lapsed)
            log.warning("robot %s: its controller went silent; stopping it", self.name)
            why = f"its controller was {lapsed.why}"
            self._stop_for(lapsed.holder, f"robot {self.name} was stopped before this "
                           f"query ran: {why}")  # fmt: skip
        return due

    def _stop_for(self, who: str, why: str) -> None:
        """The stop, ahead of every queued query; ``who``'s queued ones are cancelled."""
        for job in self._line.request_stop(drop=lambda job: job.who == who):
            job.cancel(why)

    def _publish(self, sample: dict[str, Any]) -> None:
        if self._publisher is not None and not self._closing.is_set():
            self._publisher.put(json.dumps(sample).encode())


def _attachment(message: Any) -> bytes | None:
    attachment = message.attachment
    return attachment.to_bytes() if attachment is not None else None


def _answer(scene: Scene, query: Any) -> None:
    """A Supervisor's request of the scene (ego.zenoh_net.scene_codec), answered."""
    from ego.zenoh_net.scene_codec import answer

    payload = query.payload.to_bytes() if query.payload is not None else b""
    query.reply(query.key_expr, answer(scene, payload))
