"""``ego run --realtime``: the controller steps on SCHED_FIFO, or is refused in one line
saying what it needs; without the flag the controller stays an ordinary process."""

from __future__ import annotations

import ctypes
import os
import subprocess
from pathlib import Path

import pytest
from helpers import ego_command

CONTROLLER = (
    "import os\nfrom controller import Robot\nrobot = Robot()\nrobot.step(32)\n"
    "print('fifo', os.sched_getscheduler(0) == os.SCHED_FIFO)\n"
)
#: prctl(2) PR_CAPBSET_DROP, and capability(7) CAP_SYS_NICE.
PR_CAPBSET_DROP, CAP_SYS_NICE = 24, 23


def _run(
    tmp_path: Path, *flags: str, unprivileged: bool = False
) -> subprocess.CompletedProcess[str]:
    (tmp_path / "rt.py").write_text(CONTROLLER)

    def drop_nice() -> None:  # in the child, before exec: as a user without the right
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_CAPBSET_DROP, CAP_SYS_NICE, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP)")

    return subprocess.run(
        [*ego_command(), "run", "--port", "sim", *flags, "rt.py"],
        capture_output=True, text=True, cwd=tmp_path, timeout=60,
        preexec_fn=drop_nice if unprivileged else None,
    )  # fmt: skip


@pytest.mark.skipif(os.geteuid() != 0, reason="SCHED_FIFO needs root or CAP_SYS_NICE here")
def test_realtime_steps_on_sched_fifo(tmp_path: Path) -> None:
    done = _run(tmp_path, "--realtime")
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["fifo", "True"]


def test_without_realtime_the_controller_stays_an_ordinary_process(tmp_path: Path) -> None:
    done = _run(tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["fifo", "False"]


@pytest.mark.skipif(os.geteuid() != 0, reason="dropping CAP_SYS_NICE needs root to have it")
def test_realtime_without_the_right_is_refused_in_one_line(tmp_path: Path) -> None:
    done = _run(tmp_path, "--realtime", unprivileged=True)
    assert done.returncode == 1 and done.stdout == ""
    assert done.stderr.splitlines() == [
        "ego: error: --realtime: cannot run the controller on SCHED_FIFO ([Errno 1] Operation "
        "not permitted); it needs root, CAP_SYS_NICE, or 'ulimit -r 1' (rtprio 1 in "
        "/etc/security/limits.conf)"
    ]
