"""``ego serve``: its command-line options, and the loop that serves until a signal.

The ``ego`` command wires it as a subcommand::

    serve = sub.add_parser("serve", help="let another machine drive this robot")
    ego.app.serve.add_arguments(serve)
    serve.set_defaults(func=ego.app.serve.run)     # then: sys.exit(args.func(args))
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import logging
import signal
import sys
import threading
from typing import TYPE_CHECKING, Any

from ego.app.cli_options import add_dashboard_options, deadline_ms, error_line
from ego.camera.v4l2 import DEFAULT_CAMERA_DEVICE
from ego.core.environment import Environment, read_environment
from ego.core.safety import TERMINATING_SIGNALS
from ego.errors import EgoError
from ego.net.auth import load_secret
from ego.seam.channel import Channel
from ego.seam.profile import FIRMWARE_CHOICES
from ego.servers.robot import ServedRobot, open_robot
from ego.servers.socket.server import DEFAULT_DEADLINE_S, DEFAULT_LISTEN, Server, check_listen

if TYPE_CHECKING:
    pass

__all__ = ["add_arguments", "run"]

log = logging.getLogger(__name__)




def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``ego serve``."""
    parser.add_argument(
        "--port",
        default=None,
        help="serial port of the dsPIC, 'sim' for the built-in emulator, or 'pipuck' on a "
        "Pi-puck's Pi (default: $EGO_PORT, else /dev/ttyS0)",
    )
    parser.add_argument(
        "--robot", choices=("epuck", "epuck2"), default=None,
        help="which robot: the emulated one (port sim), or the one a Pi-puck carries "
        "(port pipuck; default: detected)",
    )
    parser.add_argument(
        "--listen",
        action="append",
        metavar="URL",
        help=f"tcp://HOST:PORT or udp://HOST:PORT to serve on, repeatable "
        f"(default: {DEFAULT_LISTEN}); off 127.0.0.1 a --secret-file is required",
    )
    parser.add_argument(
        "--secret-file",
        metavar="FILE",
        help="file holding the shared secret clients must prove they know (chmod 600); "
        "also given to a --port that wants one (tcp://, udp://, unix://)",
    )
    parser.add_argument(
        "--firmware",
        choices=FIRMWARE_CHOICES,
        metavar="{auto,gctronic,webots}",
        default="auto",
        help="dsPIC firmware (default: ask the robot); with --port sim, the one emulated",
    )
    parser.add_argument(
        "--deadline-ms",
        type=deadline_ms,
        default=round(DEFAULT_DEADLINE_S * 1000),
        help="stop the motors when the client is silent this long (default: %(default)s)",
    )
    parser.add_argument(
        "--zenoh",
        action="store_true",
        help="serve the robot as a Zenoh node instead of on --listen: ego/NAME/... "
        "(docs/zenoh.md); controllers reach it as zenoh://NAME",
    )
    _add_zenoh_arguments(parser)
    add_dashboard_options(
        parser, "a dashboard of the robot as the client drives it, with a stop button",
        secret=False,  # --secret-file above serves the dashboard too
    )  # fmt: skip
    parser.add_argument(
        "--camera",
        metavar="DEVICE",
        default=None,
        help=f"video device to serve (default: $EGO_CAMERA, else {DEFAULT_CAMERA_DEVICE} if it "
        "exists; the emulator's camera with --port sim); 'none' serves no camera",
    )


def _add_zenoh_arguments(parser: argparse.ArgumentParser) -> None:
    """``ego serve --zenoh`` and its session's options."""
    parser.add_argument("--name", default="epuck", help="the robot's Zenoh name (default epuck)")
    parser.add_argument(
        "--zenoh-listen",
        action="append",
        metavar="ENDPOINT",
        help="Zenoh endpoint to listen on, repeatable (default tcp/127.0.0.1:7447); off "
        "loopback a --zenoh-config with Zenoh's authentication is required",
    )
    parser.add_argument(
        "--zenoh-connect", action="append", metavar="ENDPOINT",
        help="Zenoh endpoint (a router, another peer) to connect to, repeatable",
    )  # fmt: skip
    parser.add_argument("--zenoh-config", metavar="FILE", help="a Zenoh JSON5 configuration")


def run(args: argparse.Namespace) -> int:
    """Serve until a signal ends it (SIGINT, SIGTERM, SIGHUP...), then stop the robot."""
    if not logging.getLogger().handlers:
        logging.basicConfig(level=logging.INFO, format="%(asctime)s %(levelname)s %(message)s")
    listen = args.listen or [DEFAULT_LISTEN]
    environment = read_environment()  # once, at the edge: passed down from here
    if args.zenoh and args.listen:
        print("ego serve: serve over --zenoh or on --listen, not both: one controller holds "
              "a robot", file=sys.stderr)  # fmt: skip
        return 2
    try:
        secret = load_secret(args.secret_file) if args.secret_file else None
        check_listen(listen, secret)  # before the robot is touched
    except (OSError, ValueError) as exc:
        print(f"ego serve: {exc}", file=sys.stderr)
        return 2
    try:
        robot = open_robot(args.port, args.firmware, args.camera, secret, environment,
                           args.robot)
    except EgoError as exc:
        print(f"ego serve: {error_line(exc)}", file=sys.stderr)
        return 1
    try:
        channel = _dashboard(args, robot, secret) if args.dashboard else robot.channel
        if args.zenoh:
            return _serve_zenoh(args, robot, channel, environment)
        server = Server(
            channel,
            listen=listen,
            secret=secret,
            deadline_s=args.deadline_ms / 1000,
            frame_source=robot.camera,
        )
        asyncio.run(_serve(server))
    except ValueError as exc:  # a deadline out of range
        print(f"ego serve: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # the address is in use, or not ours
        print(f"ego serve: cannot listen: {exc}", file=sys.stderr)
        return 1
    finally:
        robot.close()
    return 0


def _dashboard(args: argparse.Namespace, robot: ServedRobot, secret: bytes | None) -> Channel:
    """Start ``--dashboard`` on the served robot; the channel the server must use."""
    from ego.servers.dashboard.live import parse_address
    from ego.servers.dashboard.served import ServedFeed, WatchedChannel
    from ego.servers.dashboard.server import DashboardServer

    watched = WatchedChannel(robot.channel, world=robot.world)
    feed = ServedFeed(watched, str(args.port or "default port"))
    host, port = parse_address(args.dashboard)
    board = DashboardServer(feed, host, port, secret).start()
    feed.server = board
    robot.closers.insert(0, board.close)
    print(f"ego serve: dashboard at {board.url}", file=sys.stderr, flush=True)
    return watched


def _serve_zenoh(
    args: argparse.Namespace, robot: ServedRobot, channel: Channel, environment: Environment
) -> int:
    """Serve the robot as the Zenoh node ``--name`` until a signal ends it."""
    from ego.servers.zenoh_node.node import RobotNode
    from ego.zenoh_net.keys import check_name
    from ego.zenoh_net.sessions import DEFAULT_ENDPOINT, ZenohSettings, open_session

    try:
        check_name(args.name)
        settings = ZenohSettings.from_environment(
            environment, args.zenoh_listen or [DEFAULT_ENDPOINT], args.zenoh_connect,
            args.zenoh_config,
        )  # fmt: skip
        session: Any = open_session(settings)
    except (ValueError, EgoError) as exc:
        print(f"ego serve: {exc}", file=sys.stderr)
        return 2
    node = RobotNode(channel, session, args.name, deadline_s=args.deadline_ms / 1000,
                     world=robot.world).start()  # fmt: skip
    print(f"ego serve: {channel.name} ({channel.profile.firmware} firmware) as Zenoh node "
          f"{args.name} on {', '.join(settings.listen)}", file=sys.stderr, flush=True)  # fmt: skip
    stop = threading.Event()
    previous = {}
    for sig in (signal.SIGINT, *TERMINATING_SIGNALS):
        with contextlib.suppress(ValueError, OSError):
            previous[sig] = signal.signal(sig, lambda *_: stop.set())
    try:
        stop.wait()
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        node.close()
        session.close()
    return 0


async def _serve(server: Server) -> None:
    loop = asyncio.get_running_loop()
    stop = asyncio.Event()
    # Every signal that would end the process (an ssh session dropping sends SIGHUP)
    # stops the server first, which stops the robot; handlers set by others are kept.
    for sig in (signal.SIGINT, *TERMINATING_SIGNALS):
        if sig != signal.SIGINT and signal.getsignal(sig) is not signal.SIG_DFL:
            continue
        with contextlib.suppress(NotImplementedError, RuntimeError, ValueError):
            loop.add_signal_handler(sig, stop.set)
    try:
        await server.start()
        print(
            f"ego serve: {server.channel.name} ({server.channel.profile.firmware} firmware) "
            f"on {', '.join(server.urls)}",
            file=sys.stderr,
            flush=True,
        )
        await stop.wait()
    finally:
        await server.aclose()
