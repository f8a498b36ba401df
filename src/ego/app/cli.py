"""The ``ego`` command: demo, run, sim, serve, secret, replay, swarm, plot, doctor, bench."""

from __future__ import annotations

import argparse
import logging
import re
import subprocess
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ego import __version__
from ego.app.cli_options import (
    DEFAULT_DASHBOARD,
    CommandParser,
    add_dashboard_options,
    camera_size,
    deadline_ms,
    demo_dashboard,
    error_line,
    firmware_parent,
    missing_extra,
    positive,
    replay_speed,
    robot_parent,
    seed_parent,
    world_parent,
)
from ego.app.doctor import add_doctor_command
from ego.errors import ControllerError, ControllerTerminated, EgoError
from ego.faces import runtime

__all__ = ["build_parser", "main"]


def _cmd_demo(args: argparse.Namespace) -> int:
    from ego.app.demo import run_demo
    from ego.core.scheduler import tune_for_stepping

    tune_for_stepping()  # the CLI owns the process: precise steps (see its docstring)
    dashboard = demo_dashboard(args)
    if args.pipuck:
        from ego.app.demo import run_pipuck_demo

        return run_pipuck_demo(args.duration, args.robot, args.seed, args.world, dashboard)
    run_demo(args.duration, args.firmware, args.seed, world=args.world, dashboard=dashboard,
             record=args.record, robot=args.robot)  # fmt: skip
    return 0


def _cmd_replay(args: argparse.Namespace) -> int:
    if args.emulate:
        from ego.app.observers import observe_run
        from ego.app.runner import run_controller

        if not args.controller:
            raise SystemExit("ego replay --emulate needs a controller file after the recording")
        # The replay paces the controller's steps at --speed times real time.
        options = runtime.RunOptions(port=f"replay://{args.recording}?speed={args.speed:g}")
        with observe_run(options, dashboard=args.dashboard, secret_file=args.secret_file):
            run_controller(args.controller[0], options, args.controller[1:])
        return 0
    if args.controller:
        raise SystemExit(f"ego replay: {args.controller[0]!r}: a controller runs only with "
                         "--emulate")  # fmt: skip
    from ego.app.play import play

    return play(args.recording, args.dashboard or DEFAULT_DASHBOARD, args.secret_file,
                args.speed, args.duration)  # fmt: skip


def _cmd_swarm(args: argparse.Namespace) -> int:
    from ego.app.swarm import Swarm

    if args.ros2:  # the robots in a ROS 2 graph: ROS drives them, no controller runs
        return _swarm_ros2(args)
    if not args.controllers:
        raise EgoError("ego swarm needs a controller file for its robots (or --ros2)")

    _no_address_for_a_controller(args.controllers)
    with Swarm(args.robots, args.world, args.firmware, args.seed, args.zenoh_endpoint,
               robot=args.robot) as swarm:
        if args.dashboard:
            secret = _secret(args)
            url = swarm.serve_dashboard(args.dashboard, secret)
            print(f"ego swarm: dashboard at {url}", file=sys.stderr, flush=True)
        print(f"ego swarm: {args.robots} emulated e-pucks, {', '.join(swarm.member_names)}, "
              f"in one world, Zenoh on {args.zenoh_endpoint}",
              file=sys.stderr, flush=True)  # fmt: skip
        statuses = swarm.run_controllers(args.controllers, args.args, args.duration)
    failed = [swarm.member_names[i] for i, status in enumerate(statuses) if status != 0]
    if failed:
        print(f"ego swarm: the controllers of {', '.join(failed)} failed", file=sys.stderr)
        return 1
    return 0


def _swarm_ros2(args: argparse.Namespace) -> int:
    from ego.app.swarm import run_ros2

    if args.controllers:
        raise EgoError(f"ego swarm --ros2: {args.controllers[0]!r}: ROS 2 drives the robots, "
                       "no controller file runs (a controller may join through "
                       "ego.ros2.topic)")  # fmt: skip
    return run_ros2(args.robots, args.world, args.firmware, args.seed,
                    args.router or ["tcp/127.0.0.1:7447"], args.distro, args.domain,
                    args.duration)  # fmt: skip


def _cmd_plot(args: argparse.Namespace) -> int:
    from ego.app.plot import plot_recording

    for path in plot_recording(args.recording, args.out):
        print(path)
    return 0


def _no_address_for_a_controller(files: Sequence[str]) -> None:
    """Refuse a missing controller file named like ``HOST:PORT``: the older command line
    ``--dashboard HOST:PORT file.py`` now means the dashboard, then the controller
    ``HOST:PORT``."""
    for name in files:
        if not Path(name).exists() and re.fullmatch(r"\[?[\w.:-]*\]?:\d+", name):
            raise EgoError(
                f"controller file {name!r} does not exist: a dashboard's address goes "
                f"after --dashboard-address (ego run --dashboard-address {name} file.py)"
            )


def _secret(args: argparse.Namespace) -> bytes | None:
    """The shared secret in ``--secret-file``, or None."""
    from ego.net.auth import load_secret

    return load_secret(args.secret_file) if args.secret_file else None


def _cmd_run(args: argparse.Namespace) -> int:
    from ego.app.observers import observe_run
    from ego.app.runner import run_controller
    from ego.core.environment import read_environment
    from ego.core.ports import resolve_port
    from ego.core.registry import takes_option
    from ego.core.scheduler import tune_for_stepping
    from ego.servers.supervisor import wants_supervision

    _no_address_for_a_controller([args.controller])
    if args.record_format != "ego" and not args.record:
        raise EgoError(f"--record-format {args.record_format} says how to record: it needs "
                       "--record FILE.mcap too")  # fmt: skip
    if args.fast and args.port != "sim":
        raise EgoError(f"--fast runs the emulator in virtual time: it needs --port sim, "
                       f"not {args.port or 'a real robot'}")  # fmt: skip
    secret = _secret(args)
    if args.supervised is None:
        args.supervised = wants_supervision(args.port)
    if args.supervised:
        return _run_supervised(args, secret)
    tune_for_stepping(args.realtime)  # the CLI owns the process: precise steps (its doc)
    # The secret goes to the robot's backend when it takes one (a served robot's), and to
    # the dashboard; an emulator or a serial port takes none.
    wanted = takes_option(resolve_port(args.port, read_environment().port), "secret")
    options = runtime.RunOptions(
        port=args.port, firmware=args.firmware, duration_s=args.duration,
        basic_time_step_ms=args.time_step, seed=args.seed, strict=args.strict,
        camera_size=args.camera, world=args.world, secret=secret if wanted else None,
        fast=args.fast, robot=args.robot,
    )  # fmt: skip
    ros2 = args.ros2_distro if args.record_format == "ros2" else None
    with observe_run(options, dashboard=args.dashboard, secret_file=args.secret_file,
                     record=args.record, record_ros2=ros2):  # fmt: skip
        run_controller(args.controller, options, args.args)
    return 0


def _run_supervised(args: argparse.Namespace, secret: bytes | None) -> int:
    """``ego run --supervised``: this process holds the port, a child runs the controller."""
    from ego.servers.supervisor import run_supervised

    passed = [
        *(["--duration", str(args.duration)] if args.duration is not None else []),
        "--time-step",
        str(args.time_step),
        *(["-" + "v" * args.verbose] if args.verbose > 0 else []),
        *(["-q"] if args.verbose < 0 else []),
        *(["--strict"] if args.strict else []),
        *(["--realtime"] if args.realtime else []),
        *(["--camera", "{}x{}".format(*args.camera)] if args.camera else []),
        *(["--dashboard-address", args.dashboard] if args.dashboard else []),
        *(["--secret-file", args.secret_file] if args.secret_file else []),
        *(["--record", args.record] if args.record else []),
        *(["--record-format", args.record_format, "--ros2-distro", args.ros2_distro]
          if args.record and args.record_format != "ego" else []),
    ]
    try:
        return run_supervised(
            args.controller, passed, args.args, port=args.port,
            firmware=args.firmware or "auto", deadline_s=args.supervisor_deadline_ms / 1000,
            secret=secret, robot_kind=args.robot,
        )  # fmt: skip
    except KeyboardInterrupt:
        return 130  # the controller, which had the Ctrl-C too, said it stopped


def _cmd_sim(args: argparse.Namespace) -> int:
    from ego.core.registry import find_backend

    # The emulator's own command line, reached through its backend (ego.backends): the
    # library never imports the emulator.
    backend: Any = find_backend("sim")
    return int(backend.main(args.args, prog="ego sim"))


def _cmd_serve(args: argparse.Namespace) -> int:
    from ego.app.serve import run

    return run(args)


def _cmd_secret(args: argparse.Namespace) -> int:
    from ego.net.auth import new_secret, write_secret

    if args.out is None:
        print(new_secret())
        return 0
    try:
        write_secret(args.out)
    except FileExistsError:
        print(f"ego secret: {args.out} exists; it is not overwritten", file=sys.stderr)
        return 1
    print(f"ego secret: wrote a new secret to {args.out} (mode 600)", file=sys.stderr)
    return 0


def _checkout() -> Path:
    """The source checkout whose benchmarks ``ego bench`` runs: the working directory or a
    parent of it first, else the one this package was installed from in editable mode."""
    here = Path.cwd().resolve()
    for root in (here, *here.parents, Path(__file__).resolve().parents[2]):
        if (root / "benchmarks" / "__main__.py").is_file() and (root / "src" / "ego").is_dir():
            return root
    raise EgoError(
        "ego bench runs the benchmarks of a source checkout: run it inside one "
        "(benchmarks/ beside src/ego/)"
    )


def _cmd_bench(args: argparse.Namespace) -> int:
    root = _checkout()
    cmd = [sys.executable, "-m", "benchmarks", *(["--quick"] if args.quick else [])]
    cmd += [arg for section in args.only for arg in ("--only", section)]
    cmd += ["--out", args.out] if args.out else []
    return subprocess.call(cmd, cwd=root)


def _add_verbosity(parser: argparse.ArgumentParser, default: object) -> None:
    """-v/-q before or after the subcommand (``ego run -v x.py`` as ``ego -v run x.py``)."""
    parser.add_argument(
        "-v", "--verbose", action="count", default=default, help="log more (-vv: debug)"
    )
    parser.add_argument(
        "-q",
        "--quiet",
        action="store_const",
        const=-1,
        dest="verbose",
        default=default,
        help="log errors only",
    )


def _add_demo(sub: Any) -> None:
    demo = sub.add_parser(
        "demo", help="obstacle avoidance on the built-in emulator, shown live",
        parents=[firmware_parent(emulated=True, default="webots"), seed_parent(1, ""),
                 world_parent("the emulator's world"), robot_parent("the emulated robot")],
    )  # fmt: skip
    demo.add_argument("--duration", type=positive, default=20.0, help="seconds (default 20)")
    add_dashboard_options(demo, "the live dashboard, on unless --no-dashboard", secret=False,
                          off_loopback="loopback only: the demo takes no secret")  # fmt: skip
    demo.add_argument("--no-dashboard", action="store_true", help="no dashboard")
    demo.add_argument("--pipuck", action="store_true",
                      help="the robot on an emulated Pi-puck, driven over its I2C bus "
                      "(ego run --port pipuck in a child process)")  # fmt: skip
    demo.add_argument("--record", default=None, metavar="FILE.mcap", help="record the run")
    demo.set_defaults(func=_cmd_demo)


def _add_run(sub: Any) -> None:
    run = sub.add_parser(
        "run", help="run a Webots controller file unchanged",
        parents=[firmware_parent(emulated=False, default=None),
                 seed_parent(None, " (port sim)"), world_parent("the emulator's world (port sim)"),
                 robot_parent("the robot (port sim or pipuck)")],
    )  # fmt: skip
    run.add_argument("--port", default=None, help="serial port, pyserial URL, 'sim', tcp://, "
                     "udp://, unix://, zenoh://, epuck2://HOST (an e-puck2 over WiFi), "
                     "pipuck (on a Pi-puck's Pi) (default: EGO_PORT or /dev/ttyS0)")  # fmt: skip
    run.add_argument("--duration", type=positive, default=None,
                     help="stop after this many seconds of controller time")  # fmt: skip
    run.add_argument("--time-step", type=positive, default=32.0,
                     help="what getBasicTimeStep() answers, ms (default 32)")  # fmt: skip
    run.add_argument("--camera", type=camera_size, default=None, metavar="WxH",
                     help="the Webots face's camera size (default 52x39, Webots' "
                     "e-puck's)")  # fmt: skip
    run.add_argument("--strict", action="store_true", help="where Webots warns and carries "
                     "on (a device the e-puck has not), raise ego's error instead")  # fmt: skip
    run.add_argument("--realtime", action="store_true", help="step on SCHED_FIFO: other "
                     "processes cannot hold the core through a step's deadline (needs root "
                     "or CAP_SYS_NICE; a controller stuck in a loop then starves the "
                     "machine)")  # fmt: skip
    run.add_argument("--fast", action="store_true", help="port sim: run in virtual time, as "
                     "fast as the CPU allows (Webots' fast mode); the same world, sensors "
                     "and batches, but the world moves only as the controller steps")  # fmt: skip
    run.add_argument(
        "--supervised", action=argparse.BooleanOptionalAction, default=None,
        help="a supervisor process owns the port and stops the robot however the controller "
        "ends (SIGKILL, out of memory, a loop that stops stepping); default: on on the "
        "robot's own computer (the Overo's UART /dev/ttyS*, a Pi-puck), off elsewhere",
    )  # fmt: skip
    run.add_argument("--supervisor-deadline-ms", type=deadline_ms, default=500, metavar="MS",
                     help="a supervised controller that does not step for this long has its "
                     "robot stopped (1..60000, default 500)")  # fmt: skip
    add_dashboard_options(run, "a live dashboard of the robot", secret_help="the shared "
                          "secret of a served robot (tcp://, udp://, unix://) that wants one, "
                          "and of a dashboard off loopback")  # fmt: skip
    run.add_argument("--record", default=None, metavar="FILE.mcap",
                     help="record every step to MCAP")  # fmt: skip
    run.add_argument("--record-format", choices=("ego", "ros2"), default="ego",
                     help="ros2: a ROS 2 bag (epuck_ros2's topics, CDR) that ego replay "
                     "still replays; needs ego[ros2] (default: ego's JSON)")  # fmt: skip
    run.add_argument("--ros2-distro", default="jazzy", metavar="DISTRO",
                     help="the ROS 2 distribution of --record-format ros2: humble, jazzy "
                     "or kilted (default jazzy)")  # fmt: skip
    run.add_argument("controller", help="the controller's .py file")
    run.add_argument("args", nargs=argparse.REMAINDER, help="arguments for the controller")
    _add_verbosity(run, default=argparse.SUPPRESS)
    run.set_defaults(func=_cmd_run)


def _add_replay(sub: Any) -> None:
    replay = sub.add_parser("replay", help="play a recorded run back into the dashboard, "
                            "or (--emulate) feed it to a controller as if it were the "
                            "robot")  # fmt: skip
    replay.add_argument("recording", help="the .mcap file ego run --record wrote")
    replay.add_argument("controller", nargs="*",
                        help="with --emulate: the controller file, then its arguments "
                        "(after --)")  # fmt: skip
    replay.add_argument("--emulate", action="store_true", help="run CONTROLLER against the "
                        "recording: it reads exactly what the robot answered; it fails, "
                        "saying at which step, where it asks what the run did not")  # fmt: skip
    add_dashboard_options(replay, "a dashboard of the replayed robot with --emulate (a "
                          "recording played back is always shown on one)")  # fmt: skip
    replay.add_argument("--speed", type=replay_speed, default=1.0, metavar="X",
                        help="times real time: 0.25, 0.5, 1, 2 or 4 (default 1); with "
                        "--emulate, the pace of the controller's steps")  # fmt: skip
    replay.add_argument("--duration", type=positive, default=None,
                        help="stop serving after this many seconds (default: Ctrl-C)")  # fmt: skip
    replay.set_defaults(func=_cmd_replay)


def _add_swarm(sub: Any) -> None:
    swarm = sub.add_parser(
        "swarm", help="N emulated e-pucks in one world, each controller in its own process "
        "over Zenoh",
        parents=[firmware_parent(emulated=True, default="webots"),
                 seed_parent(1, " (each robot's own, derived from it and the robot's index)"),
                 world_parent("the shared world (a file may place robots: [[robots]])"),
                 robot_parent("the emulated robots")],
    )  # fmt: skip
    swarm.add_argument("--robots", type=int, default=4, help="how many (default 4)")
    swarm.add_argument("--duration", type=positive, default=None,
                       help="each controller's duration, seconds of controller time")  # fmt: skip
    swarm.add_argument("--zenoh-endpoint", default="tcp/127.0.0.1:7447", metavar="ENDPOINT",
                       help="where the robots' Zenoh node listens (default loopback)")  # fmt: skip
    add_dashboard_options(swarm, "a dashboard of the whole swarm")
    swarm.add_argument("controllers", nargs="*", metavar="controller.py",
                       help="one file for every robot, or one per robot in turn")  # fmt: skip
    swarm.add_argument("--ros2", action="store_true", help="no controllers: the robots join "
                       "a ROS 2 graph as /epuckK/epuck_driver, through --router "
                       "(docs/ros2.md)")  # fmt: skip
    swarm.add_argument("--router", action="append", metavar="ENDPOINT",
                       help="with --ros2: the ROS machine's rmw_zenohd (default "
                       "tcp/127.0.0.1:7447)")  # fmt: skip
    swarm.add_argument("--distro", default="jazzy", choices=("jazzy", "humble", "kilted"),
                       help="with --ros2: the ROS 2 distribution (default jazzy)")  # fmt: skip
    swarm.add_argument("--domain", type=int, default=0, help="with --ros2: ROS_DOMAIN_ID")
    swarm.add_argument("--args", nargs="*", default=[], help="arguments for every controller")
    swarm.set_defaults(func=_cmd_swarm)


def _add_servers(sub: Any) -> None:
    """sim, serve, secret: the emulator on a pty, and a robot served to others."""
    sim = sub.add_parser(
        "sim",
        help="serve the emulated dsPIC on a pty (prints its path; ego sim -h for its options)",
        add_help=False,
        prefix_chars="\0",  # every argument, -h included, goes to the emulator's parser
    )
    sim.add_argument("args", nargs=argparse.REMAINDER)
    sim.set_defaults(func=_cmd_sim)

    serve = sub.add_parser("serve", help="let a PC drive this robot over TCP or UDP")
    from ego.app.serve import add_arguments as add_serve_arguments

    add_serve_arguments(serve)
    serve.set_defaults(func=_cmd_serve)

    secret = sub.add_parser(
        "secret", help="make a random shared secret for ego serve (32 bytes, URL-safe)"
    )
    secret.add_argument(
        "--out", metavar="FILE", default=None, help="write it to FILE, mode 600 (new files only)"
    )
    secret.set_defaults(func=_cmd_secret)


def _add_ros2(sub: Any) -> None:
    from ego.app.ros2 import add_arguments, run

    ros2 = sub.add_parser(
        "ros2", help="run a robot as a ROS 2 node over rmw_zenoh (docs/ros2.md)",
        parents=[firmware_parent(emulated=False, default=None), seed_parent(1, " (port sim)"),
                 world_parent("the emulator's world (port sim)"),
                 robot_parent("the robot (port sim or pipuck)")],
    )  # fmt: skip
    add_arguments(ros2)
    ros2.set_defaults(func=run)


def _add_tools(sub: Any) -> None:
    """plot, bench: the commands around the runs."""
    plot = sub.add_parser("plot", help="PNG plots of a recorded run (sensors, path, timing; "
                          "needs matplotlib: pip install 'ego[plot]')")  # fmt: skip
    plot.add_argument("recording", help="the .mcap file ego run --record wrote")
    plot.add_argument("--out", default=".", metavar="DIR", help="where to write (default .)")
    plot.set_defaults(func=_cmd_plot)

    add_doctor_command(sub)
    bench = sub.add_parser("bench", help="reproduce the thesis' tables (benchmarks/)")
    bench.add_argument(
        "--quick", action="store_true", help="few repetitions, small sizes: a smoke test"
    )
    bench.add_argument("--only", action="append", default=[], metavar="SECTION",
                       help="run only this section (repeatable; see python -m "
                       "benchmarks -h)")  # fmt: skip
    bench.add_argument("--out", default=None, help="results folder")
    bench.set_defaults(func=_cmd_bench)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ego", description="Run e-puck controllers on the robot, the emulator or remotely."
    )
    parser.add_argument("--version", action="version", version=f"ego {__version__}")
    _add_verbosity(parser, default=0)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=CommandParser)
    for add in (_add_demo, _add_run, _add_servers, _add_replay, _add_swarm, _add_ros2,
                _add_tools):  # fmt: skip
        add(sub)
    return parser


#: What ``ego`` says when Ctrl-C ends a command that drives robots.
_STOPPED = {"run": " (robot stopped)", "demo": " (robot stopped)", "swarm": " (robots stopped)"}


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    level = (logging.ERROR, logging.WARNING, logging.INFO, logging.DEBUG)[min(args.verbose, 2) + 1]
    logging.basicConfig(level=level, format="%(levelname)s %(name)s: %(message)s")
    try:
        return int(args.func(args))
    except ControllerTerminated as exc:
        print(f"ego: {exc}", file=sys.stderr)  # the robot was stopped at the first -1
        return int(exc.code)  # type: ignore[arg-type]  # always an int: TERMINATED_STATUS
    except ControllerError as exc:
        # The user's own file and line, always: ego's frames are left out (-vv: all).
        shown = "".join(traceback.format_exception(exc.__cause__)) if args.verbose > 1 else None
        print(shown or exc.traceback, end="", file=sys.stderr)
        print(f"ego: error: {exc}", file=sys.stderr)
        return 1
    except (EgoError, FileNotFoundError) as exc:
        print(f"ego: error: {error_line(exc)}", file=sys.stderr)
        return 1
    except ModuleNotFoundError as exc:
        needed = missing_extra(exc, args.command)
        if needed is None:
            raise
        print(f"ego: error: {needed}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"ego: stopped by Ctrl-C{_STOPPED.get(args.command, '')}", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
