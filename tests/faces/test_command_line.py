"""The ``ego`` command line (issue 23, item 5): options that never eat a positional, the
secret file reaching a served robot, missing extras named, ``ego replay --emulate``
failing where the controller parts from the recording and pacing at ``--speed``, a
Ctrl-C that says it stopped, and help that names what it takes."""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from fakes import FAST_LINK
from helpers import ego_command

from ego.app.cli import build_parser, main
from ego.serial.link import Link
from ego.serial.transport import SerialTransport
from ego.servers.socket.server import Server
from ego.servers.socket.server_thread import ServerThread
from firmware_sim import Emulator

SECRET = "a-shared-secret-of-some-length"

#: A Webots controller that steps a few times and says so.
STEPPER = """\
from controller import Robot
robot = Robot()
for _ in range(3):
    robot.step(32)
print("stepped", flush=True)
"""

#: Steps of 64 ms at full speed with ps0 and the encoders on, until the run ends; then how
#: long its steps took, wall time.
PACED = """\
import time
from controller import Robot
robot = Robot()
robot.getDevice("ps0").enable(64)
robot.getDevice("left wheel sensor").enable(64)
for side in ("left", "right"):
    motor = robot.getDevice(side + " wheel motor")
    motor.setPosition(float("inf"))
    motor.setVelocity(6.28)
times = []
while robot.step(64) != -1:
    times.append(time.monotonic())
print("paced", len(times), times[-1] - times[0], flush=True)
"""

#: Asks for the light sensors from the first step: never recorded.
DIVERGING = """\
from controller import Robot
robot = Robot()
robot.getDevice("ls0").enable(64)
while robot.step(64) != -1:
    pass
print("ended", flush=True)
"""

#: Steps until stopped, saying once that it runs.
FOREVER = """\
from controller import Robot
robot = Robot()
robot.step(32)
print("running", flush=True)
while robot.step(32) != -1:
    pass
"""


def _ego(*args: str, cwd: Path, timeout_s: float = 60) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("EGO_SECRET", "EGO_SECRET_FILE")}
    return subprocess.run([*ego_command(), *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=timeout_s, check=False)  # fmt: skip


def _error_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.startswith("ego: error:")]


# -- --dashboard: a switch, never eating what follows it ----------------------------------


@pytest.mark.parametrize(
    ("argv", "name", "value"),
    [
        (["run", "--port", "sim", "--dashboard", "avoid.py"], "controller", "avoid.py"),
        (["swarm", "--dashboard", "avoid.py"], "controllers", ["avoid.py"]),
        (["replay", "--dashboard", "run.mcap"], "recording", "run.mcap"),
    ],
)
def test_the_dashboard_switch_never_eats_the_positional_after_it(
    argv: list[str], name: str, value: object
) -> None:
    args = build_parser().parse_args(argv)
    assert getattr(args, name) == value
    assert args.dashboard == "127.0.0.1:8765"


@pytest.mark.parametrize("command", [["run"], ["swarm"], ["replay"], ["serve"], ["demo"]])
def test_dashboard_address_and_the_old_one_word_form_name_where_it_listens(
    command: list[str],
) -> None:
    tail = {"run": ["x.py"], "swarm": ["x.py"], "replay": ["run.mcap"]}.get(command[0], [])
    parser = build_parser()
    assert parser.parse_args([*command, "--dashboard-address", "[::1]:9", *tail]).dashboard == (
        "[::1]:9"
    )
    # The address wins, whichever comes first; --dashboard=HOST:PORT is still read.
    both = [*command, "--dashboard-address", "127.0.0.1:7", "--dashboard", *tail]
    assert parser.parse_args(both).dashboard == "127.0.0.1:7"
    assert parser.parse_args([*command, "--dashboard=127.0.0.1:5", *tail]).dashboard == (
        "127.0.0.1:5"
    )


def test_the_old_form_after_the_controller_is_the_controllers_own() -> None:
    args = build_parser().parse_args(
        ["run", "--dashboard=127.0.0.1:5", "x.py", "--dashboard=mine", "--", "--dashboard=2"]
    )
    assert args.dashboard == "127.0.0.1:5"
    assert args.controller == "x.py"
    assert args.args == ["--dashboard=mine", "--", "--dashboard=2"]


def test_ego_run_serves_its_dashboard_with_the_switch_before_the_controller(
    tmp_path: Path,
) -> None:
    (tmp_path / "stepper.py").write_text(STEPPER)
    done = _ego("run", "--port", "sim", "--dashboard-address", "127.0.0.1:0", "--dashboard",
                "stepper.py", cwd=tmp_path)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "stepped" in done.stdout
    assert re.search(r"dashboard at http://127\.0\.0\.1:\d+", done.stderr + done.stdout)


# -- the secret file reaches a served robot -------------------------------------------------


@pytest.fixture
def served_with_secret(tmp_path: Path) -> Iterator[tuple[str, Path]]:
    """A robot served on loopback that wants SECRET: its URL, and a file holding it."""
    secret_file = tmp_path / "secret"
    secret_file.write_text(SECRET + "\n")
    secret_file.chmod(0o600)
    with Emulator("webots", seed=3) as emu, contextlib.ExitStack() as stack:
        link = Link(SerialTransport(emu.path), settings=FAST_LINK)
        stack.callback(link.close)
        server = Server(link, listen="tcp://127.0.0.1:0", secret=SECRET)
        served = stack.enter_context(ServerThread(server))
        yield served.urls[0], secret_file


@pytest.mark.parametrize("supervised", ["--no-supervised", "--supervised"])
def test_ego_run_gives_the_secret_file_to_a_served_robot(
    served_with_secret: tuple[str, Path], tmp_path: Path, supervised: str
) -> None:
    url, secret_file = served_with_secret
    (tmp_path / "stepper.py").write_text(STEPPER)
    done = _ego("run", supervised, "--port", url, "--secret-file", str(secret_file),
                "stepper.py", cwd=tmp_path)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "stepped" in done.stdout


def test_a_missing_secret_is_asked_for_in_the_command_lines_words(
    served_with_secret: tuple[str, Path], tmp_path: Path
) -> None:
    url, _ = served_with_secret
    (tmp_path / "stepper.py").write_text(STEPPER)
    done = _ego("run", "--port", url, "stepper.py", cwd=tmp_path)
    assert done.returncode == 1
    assert _error_lines(done.stderr) == [
        f"ego: error: {url} requires a shared secret: pass --secret-file FILE (ego secret "
        "makes one), or set EGO_SECRET_FILE"
    ], done.stderr
    assert "secret=" not in done.stderr  # Python's words, not the command line's


# -- a missing extra: one line naming it ------------------------------------------------------

#: ``ego`` with the import of one module refused, as where its package is not installed.
WITHOUT = (
    "import sys; sys.modules[sys.argv.pop(1)] = None; "
    "from ego.app.cli import main; sys.exit(main(sys.argv[1:]))"
)


def test_ego_plot_without_matplotlib_names_the_extra(tmp_path: Path) -> None:
    (tmp_path / "stepper.py").write_text(STEPPER)
    recorded = _ego("run", "--port", "sim", "--record", "run.mcap", "stepper.py", cwd=tmp_path)
    assert recorded.returncode == 0, recorded.stderr
    done = subprocess.run([sys.executable, "-c", WITHOUT, "matplotlib", "plot", "run.mcap"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=60)  # fmt: skip
    assert done.returncode == 1
    assert done.stderr.splitlines() == [
        "ego: error: ego plot needs matplotlib: pip install 'ego[plot]'"
    ]


def test_another_missing_module_is_a_bug_and_keeps_its_traceback(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-c", WITHOUT, "ego.recording.records", "plot", "run.mcap"],
        cwd=tmp_path, capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 1
    assert "Traceback" in done.stderr and "ego.recording.records" in done.stderr


def _without(module: str, *words: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", WITHOUT, module, *words],
                          cwd=cwd, capture_output=True, text=True, timeout=120)  # fmt: skip


def test_ego_demo_without_aiohttp_runs_without_its_dashboard_and_says_so(tmp_path: Path) -> None:
    """The dashboard is on by default: a board without the dashboard extra (issue 34)
    runs the demo to its summary, with one line saying why there is no dashboard."""
    done = _without("aiohttp", "demo", "--duration", "1", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    said = [line for line in done.stderr.splitlines() if "dashboard" in line]
    assert said == ["ego demo: no dashboard (aiohttp is missing: pip install 'ego[dashboard]')"]
    assert "Traceback" not in done.stderr
    assert "summary:" in done.stdout and "dashboard" not in done.stdout


@pytest.mark.parametrize(
    ("module", "words", "line"),
    [
        ("aiohttp", ["demo", "--dashboard"],
         "ego demo needs aiohttp: pip install 'ego[dashboard]'"),
        ("aiohttp", ["run", "--port", "sim", "--dashboard"],
         "ego run needs aiohttp: pip install 'ego[dashboard]'"),
        ("mcap", ["run", "--port", "sim", "--record", "run.mcap"],
         "ego run needs mcap: pip install 'ego[record]'"),
    ],
)  # fmt: skip
def test_a_feature_asked_for_without_its_extra_is_one_line(
    tmp_path: Path, module: str, words: list[str], line: str
) -> None:
    (tmp_path / "stepper.py").write_text(STEPPER)
    extra = [] if words[0] == "demo" else ["stepper.py"]
    done = _without(module, *words, "--duration", "1", *extra, cwd=tmp_path)
    assert done.returncode == 1
    assert done.stderr.splitlines()[-1] == f"ego: error: {line}"
    assert "Traceback" not in done.stderr


# -- ego replay --emulate ---------------------------------------------------------------------


@pytest.fixture(scope="module")
def paced_recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """3 s of 64 ms steps of PACED on the emulator, recorded."""
    folder = tmp_path_factory.mktemp("paced")
    (folder / "paced.py").write_text(PACED)
    done = _ego("run", "--port", "sim", "--seed", "2", "--duration", "3", "--record",
                "run.mcap", "paced.py", cwd=folder)  # fmt: skip
    assert done.returncode == 0, done.stderr
    return folder / "run.mcap"


def test_a_controller_parting_from_the_recording_fails_saying_where(
    paced_recording: Path, tmp_path: Path
) -> None:
    (tmp_path / "diverging.py").write_text(DIVERGING)
    done = _ego("replay", "--emulate", str(paced_recording), "diverging.py", cwd=tmp_path)
    assert done.returncode == 1, done.stderr
    errors = _error_lines(done.stderr)
    assert len(errors) == 1, done.stderr
    assert re.fullmatch(
        r"ego: error: replay://\S+run\.mcap: at step 1 the controller asks O, but the "
        r"recorded run asked [A-Za-z ]*N[A-Za-z ]*: the replay cannot answer what was never "
        r"recorded",
        errors[0],
    ), errors[0]
    assert "ended" not in done.stdout  # the run failed there, not ended as recorded


def test_replay_at_speed_4_paces_the_steps_at_four_times_real_time(
    paced_recording: Path, tmp_path: Path
) -> None:
    (tmp_path / "paced.py").write_text(PACED)
    done = _ego("replay", "--emulate", "--speed", "4", str(paced_recording), "paced.py",
                cwd=tmp_path)  # fmt: skip
    assert done.returncode == 0, done.stderr
    _, steps, seconds = done.stdout.split()[-3:]
    assert int(steps) == 3000 // 64 + 1  # every recorded step, replayed
    # 46 steps of 64 ms: 2.9 s in real time, 0.74 s at 4x (generous bounds either side).
    assert 0.4 < float(seconds) < 1.5, seconds


#: Full speed with the encoders on, logging them; with "slow", a 0.2 s pause every 8th
#: step (a loaded machine): the encoders jump between those steps, plausibly then.
SLOWED = """\
import json
import sys
import time
from controller import Robot
robot = Robot()
wheel = robot.getDevice("left wheel sensor")
wheel.enable(64)
for side in ("left", "right"):
    motor = robot.getDevice(side + " wheel motor")
    motor.setPosition(float("inf"))
    motor.setVelocity(6.28)
log = []
while robot.step(64) != -1:
    log.append(wheel.getValue())
    if sys.argv[1] == "slow" and len(log) % 8 == 0:
        time.sleep(0.2)  # the subject: a loaded machine's pause, recorded then replayed
json.dump(log, open(sys.argv[2], "w"))
"""


def test_a_replay_judges_each_reply_at_the_time_the_recorded_one_came(tmp_path: Path) -> None:
    """Recorded on a loaded machine, replayed on an idle one (or faster): the encoders'
    jumps over the recorded pauses are as plausible as they were then, so the replay
    asks nothing again that the recorded run did not, and reads the same values."""
    (tmp_path / "slowed.py").write_text(SLOWED)
    recorded = _ego("run", "--port", "sim", "--seed", "5", "--duration", "2", "--record",
                    "run.mcap", "slowed.py", "slow", "then.json", cwd=tmp_path)  # fmt: skip
    assert recorded.returncode == 0, recorded.stderr
    replayed = _ego("replay", "--emulate", "--speed", "2", "run.mcap", "slowed.py", "--",
                    "fast", "now.json", cwd=tmp_path)  # fmt: skip
    assert replayed.returncode == 0, replayed.stderr
    assert "implausible" not in replayed.stderr
    then = json.loads((tmp_path / "then.json").read_text())
    assert json.loads((tmp_path / "now.json").read_text()) == then
    assert len(then) == 2000 // 64 + 1


# -- Ctrl-C --------------------------------------------------------------------------------


def _interrupt(command: list[str], ready: str, cwd: Path) -> tuple[int, str]:
    """Start ``ego COMMAND``, wait for ``ready`` on its output, Ctrl-C it: (status, stderr)."""
    proc = subprocess.Popen([*ego_command(), *command], cwd=cwd, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert proc.stdout is not None
        for line in proc.stdout:
            if ready in line:
                break
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, stderr


def test_ctrl_c_under_ego_run_says_the_robot_stopped(tmp_path: Path) -> None:
    (tmp_path / "forever.py").write_text(FOREVER)
    status, stderr = _interrupt(["run", "--port", "sim", "forever.py"], "running", tmp_path)
    assert status == 130
    assert stderr.splitlines()[-1] == "ego: stopped by Ctrl-C (robot stopped)", stderr


def test_ctrl_c_under_ego_demo_says_the_robot_stopped(tmp_path: Path) -> None:
    status, stderr = _interrupt(["demo", "--no-dashboard", "--duration", "60"], "t=", tmp_path)
    assert status == 130
    assert stderr.splitlines()[-1] == "ego: stopped by Ctrl-C (robot stopped)", stderr


# -- help ----------------------------------------------------------------------------------


def _help(command: str) -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), pytest.raises(SystemExit):
        main([command, "--help"])
    return out.getvalue()


def _option_help(text: str, option: str) -> str:
    """The help paragraph of ``option`` in ``--help`` output."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.lstrip().startswith(option + " "))
    end = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("  -")),
               len(lines))  # fmt: skip
    return " ".join(line.strip() for line in lines[start:end])


@pytest.mark.parametrize("command", ["demo", "run", "swarm", "sim"])
def test_world_and_seed_say_what_they_take(command: str) -> None:
    text = _help(command)
    world = _option_help(text, "--world")
    assert ".wbt" in world and "TOML" in world, world
    seed = _option_help(text, "--seed")
    assert "noise" in seed and "default" in seed, seed
    assert "TOML" in world
