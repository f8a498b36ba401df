"""Shared fixtures: the emulated dsPIC on a real pty, a link on it, and a leak check.

Every test folder shares this file, so the autouse check stays cheap: it compares the
emulator threads alive before and after each test, and looks for emulator directories
left behind only when a new one appeared (this process holds a leaked emulator's pty open,
which tells its directory apart from another test run's).
"""

from __future__ import annotations

import os
import signal
import tempfile
import threading
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from fakes import FAST_LINK
from helpers import ego_command, wait_until

from ego.serial.link import Link
from ego.serial.transport import SerialTransport
from firmware_sim import Emulator, World


def pytest_configure(config: pytest.Config) -> None:
    """Give SIGINT and SIGQUIT back their defaults when the suite inherited them ignored.

    A suite started in the background by a non-interactive shell (``.ci/busy``, a CI
    runner's script) inherits both ignored, as POSIX has it, and so would every ego
    process the tests start and then interrupt: ``ego run`` would go on after its Ctrl-C
    and the tests of it would fail for the shell's reasons. A handler installed here is
    reset to the default in each child, where an ignored signal stays ignored.
    """
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if signal.getsignal(signal.SIGQUIT) is signal.SIG_IGN:
        signal.signal(signal.SIGQUIT, signal.SIG_DFL)


#: The name of the emulator's serving thread and the prefix of its pty's directory.
SIM_THREAD = "ego-sim"
SIM_DIR_GLOB = "ego-sim-*"


def _sim_threads() -> set[threading.Thread]:
    return {t for t in threading.enumerate() if t.name == SIM_THREAD and t.is_alive()}


def _sim_dirs() -> set[Path]:
    return set(Path(tempfile.gettempdir()).glob(SIM_DIR_GLOB))


def _held_by_this_process(sim_dir: Path) -> bool:
    """True when this process still has the pty behind ``sim_dir``'s symlink open."""
    try:
        pty = os.readlink(sim_dir / "ttyEPUCK")
    except OSError:
        return False
    fds = Path("/proc/self/fd")
    for fd in fds.iterdir() if fds.is_dir() else ():
        try:
            if os.readlink(fd) == pty:
                return True
        except OSError:
            continue
    return False


@pytest.fixture(autouse=True)
def no_leaked_emulator() -> Iterator[None]:
    """Fail a test that leaves an emulator thread running or its pty directory behind."""
    threads, dirs = _sim_threads(), _sim_dirs()
    yield
    leaked_threads = _sim_threads() - threads
    leaked_dirs = [d for d in _sim_dirs() - dirs if _held_by_this_process(d)]
    assert not leaked_threads, f"emulator threads left running: {leaked_threads}"
    assert not leaked_dirs, f"emulator pty directories left behind: {leaked_dirs}"


def assert_removed(emu: Emulator) -> None:
    assert not os.path.lexists(emu.path), "the pty symlink outlived the emulator"
    assert not os.path.exists(os.path.dirname(emu.path)), "its directory too"


@pytest.fixture
def emulator() -> Iterator[Emulator]:
    """The thesis firmware on a pty, serving from a background thread."""
    with Emulator("webots", seed=1) as emu:
        yield emu
    assert_removed(emu)


@pytest.fixture
def overo_emulator() -> Iterator[Emulator]:
    """The stock GCtronic firmware in Overo mode (selector 10) on a pty."""
    with Emulator("gctronic", seed=1) as emu:
        yield emu
    assert_removed(emu)


@pytest.fixture
def link(emulator: Emulator) -> Iterator[Link]:
    """A link on the thesis emulator, firmware found by the V probe, fast fault timings."""
    lnk = Link(SerialTransport(emulator.path), settings=FAST_LINK)
    yield lnk
    lnk.close()


@pytest.fixture
def world(emulator: Emulator) -> World:
    """The world behind the emulator (a folder's own ``emulator`` fixture takes precedence)."""
    return emulator.world


@pytest.fixture(name="wait_until")
def wait_until_fixture() -> Callable[..., bool]:
    """:func:`helpers.wait_until`, for tests that take it as a fixture."""
    return wait_until


@pytest.fixture(name="ego_command")
def ego_command_fixture() -> list[str]:
    """:func:`helpers.ego_command`, for tests that take it as a fixture."""
    return ego_command()
