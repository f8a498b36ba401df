"""The serial line's one owner in a robot node: jobs run in order, the stop before them."""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

from ego.servers.zenoh_node.line import LineWorker


@dataclass
class Recorded:
    who: str
    log: list[str]
    gate: threading.Event | None = None
    cancelled: list[str] = field(default_factory=list)
    started: threading.Event = field(default_factory=threading.Event)

    def run(self) -> None:
        self.log.append(f"run {self.who}")
        self.started.set()
        if self.gate is not None:
            self.gate.wait(5)

    def cancel(self, why: str) -> None:
        self.cancelled.append(why)


def test_the_stop_runs_before_every_queued_job_and_the_silent_holders_are_dropped() -> None:
    log: list[str] = []
    stopped = threading.Event()
    worker = LineWorker(lambda: (log.append("stop"), stopped.set()), name="test-line").start()
    try:
        gate = threading.Event()
        in_hand = Recorded("a", log, gate)
        assert worker.submit(in_hand)
        assert in_hand.started.wait(5)  # in hand, held by the gate
        queued = [Recorded(who, log) for who in ("a", "b", "a", "b")]
        assert all(worker.submit(job) for job in queued)
        dropped = worker.request_stop(drop=lambda job: job.who == "a")
        assert [job.who for job in dropped] == ["a", "a"]
        gate.set()
        assert stopped.wait(5)
    finally:
        worker.close("closing")
    assert log[:2] == ["run a", "stop"]  # the stop waited only for the job in hand
    assert log[2:] == ["run b", "run b"]


def test_a_full_queue_refuses_and_closing_cancels_what_waits() -> None:
    log: list[str] = []
    worker = LineWorker(lambda: None, name="test-line", capacity=2)  # not started: none run
    jobs = [Recorded("a", log) for _ in range(3)]
    assert [worker.submit(job) for job in jobs] == [True, True, False]
    worker.close("the node is closing")
    assert [job.cancelled for job in jobs] == [["the node is closing"]] * 2 + [[]]
    assert not worker.submit(Recorded("a", log)) and log == []
