"""Issue 35: every thread has an owner (ego.nursery): close reports a thread that will not
end, timers sleep until their deadline, no thread of ego or its emulator is a daemon, and
no thread of ego is started anywhere but by a Nursery."""

from __future__ import annotations

import ast
import gc
import subprocess
import sys
import textwrap
import threading
import time
import weakref
from pathlib import Path

import pytest

import ego
import firmware_sim
from ego.errors import ThreadLeakError
from ego.nursery import Nursery
from ego.servers.socket.server_thread import ServerThread


def test_close_joins_every_thread_it_started() -> None:
    release = threading.Event()
    nursery = Nursery("test")
    threads = [nursery.start_thread(release.wait, name=f"t{i}") for i in range(3)]
    release.set()
    nursery.close()
    assert not any(t.is_alive() for t in threads) and len(nursery) == 0


def test_a_thread_that_will_not_end_is_reported_by_name_and_not_forgotten() -> None:
    release = threading.Event()
    nursery = Nursery("the owner", join_s=0.05)
    nursery.start_thread(release.wait, name="stubborn")
    with pytest.raises(ThreadLeakError, match=r"the owner: 1 thread.*stubborn"):
        nursery.close()
    assert len(nursery) == 1  # still owned: a later close waits for it again
    release.set()
    nursery.close()
    assert len(nursery) == 0


def test_a_closed_nursery_starts_no_thread() -> None:
    nursery = Nursery("test")
    nursery.close()
    with pytest.raises(RuntimeError, match="closed"):
        nursery.start_thread(lambda: None, name="late")


def test_a_thread_closing_its_own_nursery_is_not_waited_for() -> None:
    nursery = Nursery("test", join_s=5)
    done = threading.Event()

    def close_myself() -> None:
        nursery.close()
        done.set()

    thread = nursery.start_thread(close_myself, name="self-closing")
    assert done.wait(5)
    thread.join(5)
    assert not thread.is_alive()


def test_a_timer_fires_once_its_deadline_passes_on_the_given_clock_not_before() -> None:
    fired: list[float] = []
    seen = threading.Event()

    def fire(now: float) -> float | None:
        fired.append(now)
        seen.set()
        return None

    with Nursery("test") as nursery:
        timer = nursery.start_timer(fire, name="timer")
        at = time.monotonic() + 0.05
        timer.arm(at)
        assert seen.wait(5)
    assert len(fired) == 1 and fired[0] > at  # never early, on the owner's clock


def test_a_timer_sleeps_until_its_deadline_instead_of_polling() -> None:
    fires: list[float] = []

    def fire(now: float) -> float | None:
        fires.append(now)
        return None

    with Nursery("test") as nursery:
        timer = nursery.start_timer(fire, name="timer")
        timer.arm(time.monotonic() + 3600)  # an hour away: nothing to do until then
        timer.arm(time.monotonic() + 7200)  # later than armed: changes nothing
        assert timer.deadline is not None and timer.deadline < time.monotonic() + 3601
    # Closing ended the timer's thread; it never woke to ask.
    assert timer.fired == 0 and fires == []


def test_a_timer_takes_the_deadline_its_call_answers() -> None:
    calls: list[float] = []
    done = threading.Event()

    def fire(now: float) -> float | None:
        calls.append(now)
        if len(calls) == 3:
            done.set()
            return None
        return now + 0.01

    with Nursery("test") as nursery:
        nursery.start_timer(fire, name="timer").arm(time.monotonic())
        assert done.wait(5)
    assert len(calls) == 3 and calls == sorted(calls)


def test_a_timer_whose_call_fails_keeps_running() -> None:
    calls = []
    done = threading.Event()

    def fire(now: float) -> float | None:
        calls.append(now)
        if len(calls) == 1:
            raise ValueError("a bug")
        done.set()
        return None

    with Nursery("test") as nursery:
        timer = nursery.start_timer(fire, name="timer")
        timer.arm(time.monotonic())
        assert ego.nursery is not None
        assert _wait(lambda: timer.looked == 1)
        timer.arm(time.monotonic())
        assert done.wait(5)


def _wait(condition: object) -> bool:
    from helpers import wait_until

    assert callable(condition)
    return wait_until(condition)


class _Hung:
    """A server whose close never returns (a serial line that hangs, say)."""

    def __init__(self) -> None:
        self.release = threading.Event()
        self.urls = ["tcp://127.0.0.1:1"]

    async def start(self) -> None:
        pass

    async def aclose(self) -> None:
        import asyncio

        await asyncio.to_thread(self.release.wait)


def test_a_server_thread_that_will_not_end_is_reported_not_dropped() -> None:
    hung = _Hung()
    before = set(threading.enumerate())
    running = ServerThread(hung, join_s=0.05).start()  # type: ignore[arg-type]
    (thread,) = [t for t in threading.enumerate() if t not in before and t.name == "ego-serve"]
    with pytest.raises(ThreadLeakError, match="ego-serve"):
        running.stop()
    hung.release.set()
    # It ends in its own time (0.05 s is not enough on a busy machine), then is joined.
    assert _wait(lambda: not thread.is_alive())
    running.stop()


def _daemons(root: Path) -> list[str]:
    found = []
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.keyword) and node.arg == "daemon":
                found.append(f"{path.relative_to(root.parent)}:{node.lineno}")
            if isinstance(node, ast.Attribute) and node.attr in ("daemon", "setDaemon"):
                found.append(f"{path.relative_to(root.parent)}:{node.lineno}")
    return found


def test_no_thread_of_ego_or_its_emulator_is_a_daemon() -> None:
    roots = (Path(ego.__file__).parent, Path(firmware_sim.__file__).parent)
    found = [d for root in roots for d in _daemons(root)]
    assert found == []


def _made_daemons(root: Path) -> list[str]:
    """Where ``root``'s code makes a thread a daemon (reading ``.daemon`` is allowed)."""
    found = []
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            made = (
                (isinstance(node, ast.keyword) and node.arg == "daemon")
                or (isinstance(node, ast.Assign)
                    and any(isinstance(t, ast.Attribute) and t.attr == "daemon"
                            for t in node.targets))
                or (isinstance(node, ast.Attribute) and node.attr == "setDaemon")
            )  # fmt: skip
            if made:
                found.append(f"{path.relative_to(root.parent)}:{node.lineno}")
    return found


def test_no_thread_of_the_tests_or_benchmarks_is_a_daemon_either() -> None:
    repository = Path(__file__).resolve().parents[2]
    found = [d for name in ("tests", "benchmarks", "tools") for d in
             _made_daemons(repository / name)]  # fmt: skip
    assert found == []


def test_a_nursery_lets_its_ended_threads_go() -> None:
    # An owner that starts a thread a step (stepBegin) must not keep every one it started.
    nursery = Nursery("test")
    first = nursery.start_thread(lambda: None, name="first")
    first.join(5)
    gone = weakref.ref(first)
    del first
    nursery.start_thread(lambda: None, name="second").join(5)
    gc.collect()
    assert gone() is None
    nursery.close()


def test_open_robots_are_stopped_before_any_owner_ends_its_threads_at_exit() -> None:
    # A robot left open at exit is stopped through its link (a WiFi socket, an I2C bus)
    # before that link's at_exit ends it, whichever of ego.core.safety and ego.nursery
    # was imported first.
    program = textwrap.dedent("""
        from ego.core.safety import OPEN_ROBOTS
        from ego.nursery import Nursery

        class Link:
            def __init__(self):
                self.nursery = Nursery("link", at_exit=self.close)

            def close(self):
                print("link closed", flush=True)
                self.nursery.close()

        class Robot:
            def __init__(self):
                self.link = Link()

            def close(self):
                print("stop lost" if self.link.nursery.closed else "stopped", flush=True)
                self.link.close()

        robot = Robot()
        OPEN_ROBOTS.opened(robot)
    """)
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                          timeout=60)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == ["stopped", "link closed"]


_STARTERS = ("Thread", "Timer", "start_new_thread", "start_new")


def _starts(expr: ast.expr, modules: set[str], direct: set[str]) -> bool:
    """Whether ``expr`` names threading's Thread or Timer, or _thread's starters."""
    if isinstance(expr, ast.Name):
        return expr.id in direct
    return (
        isinstance(expr, ast.Attribute)
        and expr.attr in _STARTERS
        and isinstance(expr.value, ast.Name)
        and expr.value.id in modules
    )


def _thread_starts(root: Path) -> list[str]:
    """Where a module under ``root`` starts a thread itself: a call of threading.Thread
    or threading.Timer (however imported or aliased), a class derived from them, or
    _thread.start_new_thread."""
    found = []
    for path in sorted(root.rglob("*.py")):
        tree = ast.parse(path.read_text())
        modules = {"threading"}  # names bound to the threading or _thread module
        direct: set[str] = set()  # names bound to one of their starters
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                modules |= {a.asname or a.name for a in node.names
                            if a.name in ("threading", "_thread")}  # fmt: skip
            elif isinstance(node, ast.ImportFrom) and node.module in ("threading", "_thread"):
                direct |= {a.asname or a.name for a in node.names if a.name in _STARTERS}
        lines = sorted(
            node.lineno
            for node in ast.walk(tree)
            if (isinstance(node, ast.Call) and _starts(node.func, modules, direct))
            or (
                isinstance(node, ast.ClassDef)
                and any(_starts(base, modules, direct) for base in node.bases)
            )
        )
        found += [f"{path.relative_to(root.parent).as_posix()}:{line}" for line in lines]
    return found


def test_no_module_of_ego_starts_a_thread_but_the_nursery() -> None:
    root = Path(ego.__file__).parent
    found = [f for f in _thread_starts(root) if not f.startswith("ego/nursery.py:")]
    assert found == [], "start these threads with an ego.nursery.Nursery"


def test_the_check_sees_every_way_of_starting_a_thread(tmp_path: Path) -> None:
    source = textwrap.dedent("""
        import threading
        import threading as t
        import _thread
        from threading import Thread as T, Timer

        threading.Thread(target=print)
        t.Thread(target=print)
        T(target=print)
        Timer(1, print)
        _thread.start_new_thread(print, ())

        class Mine(threading.Thread):
            pass

        threading.Event()
        x: threading.Thread | None = None
    """)
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "a.py").write_text(source)
    assert _thread_starts(tmp_path / "pkg") == [f"pkg/a.py:{n}" for n in (7, 8, 9, 10, 11, 13)]
