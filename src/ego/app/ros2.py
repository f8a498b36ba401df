"""``ego ros2``: a robot (any port) as a ROS 2 node, seen through a ROS machine's rmw_zenohd.

The ``ego`` command wires it as a subcommand (``add_arguments``, then ``run``). The robot
publishes epuck_ros2's topics and takes ``cmd_vel`` and the LEDs
(:mod:`ego.servers.ros2_node`) until a signal (SIGINT, SIGTERM, SIGHUP...) ends it;
then the robot stops and every token is withdrawn. docs/ros2.md tells the ROS side.
"""

from __future__ import annotations

import argparse
import contextlib
import signal
import sys
import threading
from contextlib import ExitStack
from typing import Any

from ego.app.cli_options import deadline_ms
from ego.core.safety import TERMINATING_SIGNALS

__all__ = ["add_arguments", "run", "wait_for_signal"]

#: rmw_zenoh's default router (config/DEFAULT_RMW_ZENOH_SESSION_CONFIG.json5:43-46).
DEFAULT_ROUTER = "tcp/127.0.0.1:7447"




def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``ego ros2`` (the firmware, seed and world come from parents)."""
    parser.add_argument("--port", default=None, help="the robot: a serial port, 'sim', "
                        "epuck2://, tcp://, zenoh://... (default: EGO_PORT, "
                        "else /dev/ttyS0)")  # fmt: skip
    parser.add_argument("--router", action="append", metavar="ENDPOINT",
                        help=f"the ROS machine's rmw_zenohd, repeatable (default "
                        f"{DEFAULT_ROUTER}); ego is a Zenoh client of it. Off loopback "
                        "a --zenoh-config giving ego Zenoh credentials is required")  # fmt: skip
    parser.add_argument("--zenoh-config", metavar="FILE", help="a Zenoh JSON5 configuration "
                        "(its transport.auth.usrpwd user and password: docs/ros2.md)")  # fmt: skip
    parser.add_argument("--allow-unauthenticated-router", action="store_true",
                        help="connect to a router off loopback without credentials: anyone "
                        "who reaches that router can then drive the robot")  # fmt: skip
    parser.add_argument("--domain", type=int, default=0, help="ROS_DOMAIN_ID (default 0)")
    parser.add_argument("--namespace", default="/", help="the node's namespace (default /; "
                        "a relative one goes under /, as in ROS)")  # fmt: skip
    parser.add_argument("--node-name", default="epuck_driver",
                        help="the node's name (default epuck_driver, epuck_ros2's)")  # fmt: skip
    parser.add_argument("--distro", default="jazzy", choices=("jazzy", "humble", "kilted"),
                        help="the ROS 2 distribution whose rmw_zenoh format to speak "
                        "(default jazzy)")  # fmt: skip
    parser.add_argument("--period-ms", type=deadline_ms, default=64,
                        help="step and publish period, ms (default 64, epuck_ros2's)")  # fmt: skip
    parser.add_argument("--deadline-ms", type=deadline_ms, default=500,
                        help="stop the wheels when cmd_vel is silent this long "
                        "(default 500)")  # fmt: skip
    parser.add_argument("--duration", type=float, default=None,
                        help="stop after this many seconds (default: until a signal)")  # fmt: skip


def run(args: argparse.Namespace) -> int:
    """Bridge the robot until a signal (or ``--duration``) ends it."""
    from ego.core.environment import read_environment
    from ego.ros2.extras import check_installed
    from ego.ros2.names import check_node_name, node_namespace
    from ego.zenoh_net.sessions import ZenohSettings

    environment = read_environment()  # once, at the edge
    args.namespace = node_namespace(args.namespace)  # "epuck" is "/epuck", as in rcl
    check_node_name(args.node_name)
    check_installed()
    settings = ZenohSettings.from_environment(
        environment, listen=None, connect=args.router or [DEFAULT_ROUTER],
        config_file=args.zenoh_config,
    )  # fmt: skip
    with ExitStack() as stack:
        bridged = open_bridged(stack, args, settings, environment)
        where = f"{args.namespace.rstrip('/')}/{args.node_name}"
        print(f"ego ros2: {bridged.robot.port} as ROS 2 node {where} ({args.distro}, domain "
              f"{args.domain}) via {', '.join(settings.connect)}: "
              f"{len(bridged.bridge.published)} topics published, "
              f"{len(bridged.bridge.subscribed)} subscribed",
              file=sys.stderr, flush=True)  # fmt: skip
        wait_for_signal(bridged.runner.ended, args.duration)
        if bridged.runner.error is not None:
            raise bridged.runner.error
    return 0


class Bridged:
    """What ``ego ros2`` opened for one robot: the robot, node, bridge and runner."""

    def __init__(self, robot: Any, node: Any, bridge: Any, runner: Any) -> None:
        self.robot, self.node, self.bridge, self.runner = robot, node, bridge, runner


def open_bridged(stack: ExitStack, args: argparse.Namespace, settings: Any,
                 environment: Any) -> Bridged:  # fmt: skip
    """Open the session, the robot, the node and its bridge, and start stepping; each
    closed by ``stack`` in the reverse order (the runner joined first, the robot stopped
    before the tokens go)."""
    from ego.core.registry import takes_option
    from ego.core.robot import Robot
    from ego.ros2.participant import Participant
    from ego.seam.profile import Firmware
    from ego.servers.ros2_node.bridge import Ros2Bridge
    from ego.servers.ros2_node.router import open_router_session
    from ego.servers.ros2_node.runner import NodeRunner

    allow = bool(getattr(args, "allow_unauthenticated_router", False))
    session = open_router_session(settings.connect, settings.config_file,
                                  allow_unauthenticated=allow)  # fmt: skip
    stack.callback(session.close)
    options: dict[str, Any] = {"firmware": Firmware.choose(args.firmware or "auto")}
    if (args.port or "") == "sim":
        options.update(seed=args.seed, world=args.world, robot=args.robot)
    elif args.robot is not None and takes_option(args.port or "", "robot"):
        options.update(robot=args.robot)  # a Pi-puck's
    robot = Robot(args.port, environment=environment, **options)
    stack.callback(robot.close)
    node = Participant(session, args.node_name, namespace=args.namespace,
                       domain_id=args.domain, distro=args.distro)  # fmt: skip
    stack.callback(node.close)
    bridge = Ros2Bridge(robot, node, period_ms=args.period_ms,
                        deadline_s=args.deadline_ms / 1000).attach()  # fmt: skip
    stack.callback(bridge.close)
    runner = NodeRunner(robot, args.period_ms, args.node_name).start()
    stack.callback(runner.close)
    return Bridged(robot, node, bridge, runner)


def wait_for_signal(ended: threading.Event, duration_s: float | None) -> None:
    """Until a terminating signal, ``duration_s``, or the runner ending by itself."""
    previous = {}
    for sig in (signal.SIGINT, *TERMINATING_SIGNALS):
        with contextlib.suppress(ValueError, OSError):
            previous[sig] = signal.signal(sig, lambda *_: ended.set())
    try:
        if not ended.wait(duration_s):
            return
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
