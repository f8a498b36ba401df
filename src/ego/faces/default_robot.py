"""A controller run's context, for every face: its options, its environment, its robot.

A :class:`FaceContext` holds a run's options (:class:`~ego.faces.runtime.RunOptions`),
the environment's settings (read once, here at the faces' edge: :mod:`ego.core.environment`)
and the one robot that ``wb_robot_init()`` or ``overo_serial_init()`` opens; every face
opens its robot through :meth:`FaceContext.new_robot`, so that each port gets its own
options and rate. ``ego run`` runs its controller inside :func:`run_context` (a context of
its own, active while the controller runs, whose robots are all stopped and closed at
the end); the C-style functions, which take no such argument by their nature, find it
with :func:`current_context`: the context activated in this ``contextvars`` context, else
one made (with default options) at first use, as a plain script gets. Nothing here is a
module global holding a robot: two contexts never share one, and a thread (which starts
in a fresh ``contextvars`` context) gets its own.

The module-level functions (``open_robot``, ``get``, ``step``, ``is_open``, ``close``,
``current_options``, ``set_options``) act on the current context.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar

from ego.core.environment import Environment, read_environment
from ego.core.ports import call_baud, resolve_port
from ego.core.robot import Robot
from ego.core.safety import RobotKeeper
from ego.errors import EgoError
from ego.faces.runtime import RunOptions
from ego.faces.termination import Termination
from ego.seam.profile import Firmware

__all__ = [
    "FaceContext",
    "activate",
    "close",
    "current_context",
    "current_options",
    "get",
    "is_open",
    "open_robot",
    "run_context",
    "set_options",
    "step",
]


class FaceContext:
    """A run's options and environment, and the robot the C-style faces drive in it (none
    until opened).

    ``environment`` None: this process's, read now. ``make_robot`` opens a robot (the
    core :class:`~ego.core.robot.Robot`; a test passes its own to see what a face asks).
    """

    def __init__(
        self,
        options: RunOptions | None = None,
        environment: Environment | None = None,
        make_robot: Callable[..., Robot] = Robot,
    ) -> None:
        self.options = options if options is not None else RunOptions()
        self.environment = environment if environment is not None else read_environment()
        self._make_robot = make_robot
        self._robot: Robot | None = None
        #: What ``wbr_has_failed()`` answers: ``wbr_init`` failed, or a step returned -1.
        self.failed = False
        #: The Webots Python face's Robot of this run: Webots allows one a process, and
        #: R2023b's constructors by name (``Motor("left wheel motor")``) find it here.
        self.webots_robot: object | None = None
        #: When this run's step first returned -1: a controller going on past the grace
        #: after it is ended, as Webots ends it (ego.faces.termination).
        self.termination = Termination()

    def new_robot(
        self,
        port: str | None = None,
        baudrate: int | None = None,
        options: RunOptions | None = None,
    ) -> Robot:
        """A robot on ``port`` (None: the options', else EGO_PORT, else /dev/ttyS0) with
        the run's ``options`` (None: this context's), opened for a face that holds it
        itself (the Webots Robot, which then calls the options' ``on_robot`` callbacks).

        ``baudrate`` is what a controller's own call asks for (``overo_serial_init``): it
        applies only where the controller sets the line, the Overo's own UART with the
        stock firmware (:func:`ego.core.ports.call_baud`); every other port opens at its
        own rate (a Webots-firmware or Bluetooth port at 115200), and a served robot, a
        Zenoh node or a recording is given none.
        """
        options = options if options is not None else self.options
        resolved = resolve_port(port or options.port, self.environment.port)
        given = options.robot_options()
        rate = call_baud(resolved, Firmware.choose(options.firmware), baudrate)
        if rate is not None:
            given["baudrate"] = rate
        return self._make_robot(resolved, environment=self.environment, **given)

    def open_robot(self, port: str | None = None, baudrate: int | None = None) -> Robot:
        """Open the C-style faces' robot (closing a previous one): :meth:`new_robot`,
        then each of the options' ``on_robot`` callbacks."""
        self.close()
        robot = self._robot = self.new_robot(port, baudrate)
        for callback in self.options.on_robot:
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
        if self._robot is None and self.termination.ended_at is not None:
            return self.termination.ended("")  # closed at the first -1: the grace runs
        robot = self.get()
        if self.options.time_is_up(robot.time_s):
            self.close()
            return self.termination.ended(self.options.time_up_reason())
        result = robot.step(ms)
        return self.termination.ended(ended_reason(robot)) if result == -1 else result

    def is_open(self) -> bool:
        return self._robot is not None

    def close(self) -> None:
        robot, self._robot = self._robot, None
        if robot is not None:
            robot.close()

    def __repr__(self) -> str:
        return f"<FaceContext robot={self._robot!r} options={self.options!r}>"


def ended_reason(robot: Robot) -> str:
    """Why ``robot``'s step returned -1 (its own answer, not the run's duration)."""
    return "the robot was closed" if robot.closed else "the link to the robot was lost"


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


@contextmanager
def run_context(
    options: RunOptions, environment: Environment | None = None
) -> Iterator[FaceContext]:
    """A controller run's own context, active inside the ``with`` block: its faces read
    ``options`` there, and every robot opened meanwhile (by a face, or by ``ego.Robot``
    itself) is kept, then stopped and closed when the block ends, however it ends."""
    context = FaceContext(options, environment)
    with RobotKeeper(), activate(context):
        try:
            yield context
        finally:
            context.close()


def current_options() -> RunOptions:
    """The options of the current face context (what ``ego run`` was given)."""
    return current_context().options


def set_options(options: RunOptions) -> None:
    """Give the current face context ``options`` (its robot, if any, stays open)."""
    current_context().options = options


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
