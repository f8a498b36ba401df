"""``ego run --supervised``: a small process owns the port and stops the robot however the
controller ends, SIGKILL, an out-of-memory kill or a hung loop included.

The dsPIC has no serial watchdog: it keeps the last speeds it was given. A controller
process cannot stop the robot once it is killed, so another process must hold the port.
The supervisor is ``ego serve`` on a Unix socket, in the process that started the run:

* it opens the robot's port and serves it on ``unix://<private dir>/robot.sock`` (a
  directory only this user can enter, a socket of mode 600);
* it starts the controller as a child, ``python -m ego run --port unix://...``, which
  talks to it through the backend registry like any remote robot;
* when the child's connection closes (whatever ended the process: the kernel closes its
  sockets) the server stops the robot at once; when the child stops stepping for longer
  than the deadline (a hung loop keeps its socket open but sends nothing new) the
  server's deadman, in its own thread, stops it;
* a signal to the supervisor is passed to the controller; once the controller has ended,
  the supervisor stops the robot once more itself and closes the port.
"""

from __future__ import annotations

import contextlib
import logging
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from ego.core.safety import SignalExit, install_signal_handlers, send_stop
from ego.errors import EgoError
from ego.servers.robot import open_robot
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread

__all__ = ["DEFAULT_DEADLINE_S", "run_supervised", "wants_supervision"]

log = logging.getLogger(__name__)

#: How long a controller may go without stepping before its robot is stopped.
DEFAULT_DEADLINE_S = 0.5
#: How long a controller gets to end after the supervisor passed it a signal.
GRACE_S = 5.0


def wants_supervision(port: str | None) -> bool:
    """Whether ``ego run`` supervises by default: on the robot's own UART (the Overo's
    /dev/ttyS*, /dev/ttyO*), or a port whose backend says ego runs on the robot (its
    ``on_robot``: a Pi-puck's), where nothing else could stop a killed controller's robot."""
    from ego.core.ports import is_robot_uart, resolve_port
    from ego.core.registry import find_backend, scheme_of

    resolved = resolve_port(port)
    if is_robot_uart(resolved):
        return True
    try:
        backend = find_backend(scheme_of(resolved))
    except EgoError:
        return False  # the run itself says the port is unknown, in its words
    return bool(getattr(backend, "on_robot", False))


def run_supervised(
    controller: str | os.PathLike[str],
    run_arguments: Sequence[str],
    controller_arguments: Sequence[str] = (),
    *,
    port: str | None = None,
    firmware: str = "auto",
    deadline_s: float = DEFAULT_DEADLINE_S,
    secret: bytes | None = None,
    robot_kind: str | None = None,
) -> int:
    """Run ``controller`` under supervision (see the module); its exit status.

    ``run_arguments`` are passed to the child's ``ego run`` (``--duration``...), never a
    ``--port``: the child's port is the supervisor's socket. ``secret`` (``--secret-file``)
    goes to the robot's port if it takes one (and ``robot_kind``, ``--robot``, as its
    ``robot`` option), and guards the socket: the child, given the
    same ``--secret-file`` for its dashboard, proves it knows it there.
    """
    if not 0 < deadline_s <= 60:
        raise ValueError(f"supervisor deadline {deadline_s} s is outside 0..60 s")
    install_signal_handlers()
    folder = Path(tempfile.mkdtemp(prefix="ego-supervisor-"))  # mode 700
    robot = open_robot(port, firmware, secret=secret, robot_kind=robot_kind)
    try:
        url = f"unix://{folder / 'robot.sock'}"
        server = Server(robot.channel, listen=url, secret=secret, deadline_s=deadline_s,
                        frame_source=robot.camera)  # fmt: skip
        with ServerThread(server):
            log.info("supervising %s on %s", controller, robot.channel.name)
            return _run_child(url, controller, run_arguments, controller_arguments)
    finally:
        with contextlib.suppress(EgoError, OSError):
            send_stop(robot.channel)  # once more: the server stopped it already
        robot.close()
        shutil.rmtree(folder, ignore_errors=True)


def _run_child(
    url: str,
    controller: str | os.PathLike[str],
    run_arguments: Sequence[str],
    controller_arguments: Sequence[str],
) -> int:
    command = [sys.executable, "-m", "ego", "run", *run_arguments, "--port", url]
    command += [str(controller), *controller_arguments]
    child = subprocess.Popen(command, env={**os.environ, "EGO_PORT": url})
    try:
        status = child.wait()
    except KeyboardInterrupt:
        # Ctrl-C reached the controller too (one process group): let it end.
        _end(child, None)
        raise
    except SignalExit as exc:
        _end(child, exc.signum)  # passed on: the controller ends its own way
        raise
    return 128 - status if status < 0 else status  # killed by signal N: 128 + N


def _end(child: subprocess.Popen[bytes], signum: int | None) -> None:
    """Give ``child`` ``signum`` (if any) and GRACE_S to end, then kill it."""
    if signum is not None:
        with contextlib.suppress(ProcessLookupError):
            child.send_signal(signum)
    try:
        child.wait(timeout=GRACE_S)
    except subprocess.TimeoutExpired:
        child.kill()
        child.wait()
