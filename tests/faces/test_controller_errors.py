"""An error in the user's controller shows its traceback into the user's file, ego's own
frames left out; ``ego run -v``/``-q`` after the subcommand work."""

from __future__ import annotations

import subprocess
from pathlib import Path

from helpers import ego_command

import ego

CONTROLLERS = Path(__file__).parent / "controllers"
EGO_DIR = str(Path(ego.__file__).resolve().parent)


def _run(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*ego_command(), *args], capture_output=True, text=True, cwd=cwd, timeout=60
    )


def test_the_traceback_ends_in_the_users_own_line(tmp_path: Path) -> None:
    result = _run("run", "--port", "sim", str(CONTROLLERS / "failing_controller.py"), cwd=tmp_path)
    assert result.returncode == 1
    err = result.stderr
    assert "Traceback (most recent call last):" in err
    assert 'failing_controller.py", line 8, in setup' in err
    assert 'robot.getDevice("ps9x").enable(32)' in err
    assert 'Device "ps9x" was not found on robot "e-puck"' in err  # Webots' own warning
    assert EGO_DIR not in err  # ego's own frames are left out
    last = err.rstrip().splitlines()[-1]
    assert last.startswith("ego: error: failing_controller.py: AttributeError: ")


def test_minus_vv_after_the_subcommand_shows_every_frame(tmp_path: Path) -> None:
    result = _run(
        "run", "-vv", "--port", "sim", str(CONTROLLERS / "failing_controller.py"), cwd=tmp_path
    )
    assert result.returncode == 1
    assert EGO_DIR in result.stderr  # the whole traceback, ego included
    assert "INFO ego." in result.stderr  # and -vv after "run" turned logging up


def test_minus_q_leaves_only_errors(tmp_path: Path) -> None:
    controller = tmp_path / "warns.py"
    controller.write_text(
        "import logging\nlogging.getLogger('ego').warning('a warning')\n"
        "logging.getLogger('ego').error('an error')\n"
    )
    quiet = _run("run", "-q", "--port", "sim", str(controller), cwd=tmp_path)
    loud = _run("run", "--port", "sim", str(controller), cwd=tmp_path)
    assert quiet.returncode == loud.returncode == 0
    assert "a warning" in loud.stderr and "a warning" not in quiet.stderr
    assert "an error" in quiet.stderr
