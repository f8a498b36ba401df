"""Several robots stepped together: one step of each, whatever backend each one is on.

Each robot's step (its network round trip, then the wait to the end of its step) runs in
a thread of its own, so ten robots step in about the time of one, not ten.
"""

from __future__ import annotations

import concurrent.futures
from collections.abc import Iterable
from types import TracebackType
from typing import Generic, Protocol, TypeVar

__all__ = ["RobotGroup", "Steppable", "step_all"]


class Steppable(Protocol):
    """Anything with Webots' ``step(ms) -> int`` (-1 once lost): an ``ego.Robot``."""

    def step(self, ms: int) -> int: ...


R = TypeVar("R", bound=Steppable)


class RobotGroup(Generic[R]):
    """Steps a list of robots together: each call steps every robot once, in parallel.

    The group does not own the robots: close them yourself (``with`` each one).

    >>> with ego.Robot("udp://epuck1:4242") as a, ego.Robot("udp://epuck2:4242") as b:
    ...     with RobotGroup([a, b]) as group:                  # doctest: +SKIP
    ...         while group.step(64) != -1:
    ...             a.motors.set_speed(200, 200)
    """

    def __init__(self, robots: Iterable[R]) -> None:
        self.robots: tuple[R, ...] = tuple(robots)
        if not self.robots:
            raise ValueError("a RobotGroup needs at least one robot")
        #: Each robot's result of the last step (0, or -1 for a robot that is lost).
        self.results: tuple[int, ...] = ()
        self._pool: concurrent.futures.ThreadPoolExecutor | None = (
            concurrent.futures.ThreadPoolExecutor(len(self.robots), "ego-group")
        )

    def step(self, ms: int) -> int:
        """One step of ``ms`` milliseconds for every robot; -1 if any robot is lost, else 0.

        An exception in one robot's step is raised once every robot's step has ended.
        """
        if self._pool is None:
            raise RuntimeError("this RobotGroup is closed")
        futures = [self._pool.submit(robot.step, ms) for robot in self.robots]
        results: list[int] = []
        error: BaseException | None = None
        for future in futures:
            try:
                results.append(future.result())
            except BaseException as exc:  # wait for the others before raising
                error = error or exc
                results.append(-1)
        self.results = tuple(results)
        if error is not None:
            raise error
        return -1 if -1 in results else 0

    @property
    def lost(self) -> tuple[R, ...]:
        """The robots whose last step returned -1."""
        return tuple(
            r for r, result in zip(self.robots, self.results, strict=False) if result == -1
        )

    def close(self) -> None:
        """Stop the group's threads (not the robots); idempotent."""
        pool, self._pool = self._pool, None
        if pool is not None:
            pool.shutdown(wait=True)

    def __enter__(self) -> RobotGroup[R]:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


def step_all(robots: Iterable[Steppable], ms: int) -> int:
    """One step of every robot, in parallel; -1 if any is lost (a loop wants a RobotGroup)."""
    with RobotGroup(robots) as group:
        return group.step(ms)
