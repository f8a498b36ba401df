"""The context the C-style faces (``ego.webots``, ``ego.overo``) act in: options and robot.

A :class:`FaceContext` holds a run's options and the one robot that ``wb_robot_init()``
or ``overo_serial_init()`` opens. ``ego run`` makes one for the controller it runs and
activates it (:func:`activate`); the C-style functions, which take no such argument by
their nature, find it with :func:`current_context`: the context activated in this
``contextvars`` context, else one made (with default options) at first use, as a plain
script gets. Nothing here is a module global holding a robot: two contexts never share
one, and a thread (which starts in a fresh ``contextvars`` context) gets its own.

The module-level functions (``open_robot``, ``get``, ``step``, ``is_open``, ``close``)
act on the current context.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar

from ego.core.robot import Robot
from ego.errors import EgoError
from ego.faces.runtime import RunOptions
from ego.serial.protocol import DEFAULT_BAUD

__all__ = [
    "FaceContext",
    "activate",
    "close",
    "current_context",
    "get",
    "is_open",
    "open_robot",
    "step",
]


class FaceContext:
    """A run's options, and the robot the C-style faces drive in it (none until opened)."""

    def __init__(self, options: RunOptions | None = None) -> None:
        self.options = options if options is not None else RunOptions()
        self._robot: Robot | None = None
        #: What ``wbr_has_failed()`` answers: ``wbr_init`` failed, or a step returned -1.
        self.failed = False
        #: The Webots Python face's Robot of this run: Webots allows one a process, and
        #: R2023b's constructors by name (``Motor("left wheel motor")``) find it here.
        self.webots_robot: object | None = None

    def open_robot(self, port: str | None = None, baudrate: int | None = None) -> Robot:
        """Open the robot (closing a previous one); ``port`` None: the options' or EGO_PORT."""
        self.close()
        options = self.options
        robot = Robot(
            port or options.port, baudrate=baudrate or DEFAULT_BAUD, **options.robot_options()
        )
        self._robot = robot
        for callback in options.on_robot:
            callback(robot)
        return robot

    def get(self) -> Robot:
        if self._robot is None:
            raise EgoError("no robot is open: call wb_robot_init() or overo_serial_init() first")
        return self._robot

    def step(self, ms: int) -> int:
        """One time step of the robot; -1 once the options' duration is used up (then closed).

        Both C-style faces step through here, so that a time limit ends an E-GO controller's
        ``overo_scheduler_robot_step`` loop as it ends a Webots one's ``wb_robot_step`` loop.
        """
        robot = self.get()
        if self.options.time_is_up(robot.time_s):
            self.close()
            return -1
        return robot.step(ms)

    def is_open(self) -> bool:
        return self._robot is not None

    def close(self) -> None:
        robot, self._robot = self._robot, None
        if robot is not None:
            robot.close()

    def __repr__(self) -> str:
        return f"<FaceContext robot={self._robot!r} options={self.options!r}>"


#: The face context of the running controller, per ``contextvars`` context.
_CURRENT: ContextVar[FaceContext] = ContextVar("ego_face_context")


def current_context() -> FaceContext:
    """The face context activated here, else a new one (default options), kept from now on."""
    try:
        return _CURRENT.get()
    except LookupError:
        context = FaceContext()
        _CURRENT.set(context)
        return context


@contextmanager
def activate(context: FaceContext) -> Iterator[FaceContext]:
    """Make ``context`` the current one inside the ``with`` block (the previous one after)."""
    token = _CURRENT.set(context)
    try:
        yield context
    finally:
        _CURRENT.reset(token)


def open_robot(port: str | None = None, baudrate: int | None = None) -> Robot:
    """Open the current context's robot (see :meth:`FaceContext.open_robot`)."""
    return current_context().open_robot(port, baudrate)


def get() -> Robot:
    return current_context().get()


def step(ms: int) -> int:
    return current_context().step(ms)


def is_open() -> bool:
    return current_context().is_open()


def close() -> None:
    current_context().close()
