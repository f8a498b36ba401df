"""The dashboard's login in a real headless Chromium: a DNS-rebinding page cannot move the
robot; the printed URL logs the browser in (cookie, URL cleaned) and the page fills and
drives under its own Content-Security-Policy; and every command that serves a dashboard
(ego run, ego serve, ego swarm), on loopback and off it, fills with its token and refuses
a browser without it."""

from __future__ import annotations

import socket
import subprocess
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import pytest
from dashboard_support import LineReader, served_robot
from helpers import ego_command, wait_for_more, wait_until

import ego

REBINDING = "--host-resolver-rules=MAP evil.test 127.0.0.1"
#: The attacker's script, run by its page: open the dashboard's socket, take control and
#: drive for 1.5 s. It answers whether the socket ever opened.
ATTACK = """(url) => new Promise((done) => {
  const ws = new WebSocket(url);
  ws.onerror = () => done("refused");
  ws.onopen = () => {
    ws.send(JSON.stringify({type: "take"}));
    const drive = setInterval(
      () => ws.send(JSON.stringify({type: "drive", left: 700, right: -700})), 100);
    setTimeout(() => { clearInterval(drive); done("opened"); }, 1500);
  };
})"""


def _hold_still(robot: ego.Robot) -> None:
    if not robot.proximity.enabled:
        robot.proximity.enable(32)
    robot.motors.set_speed(0, 0)


@pytest.fixture(scope="module")
def rebinding_browser(launch_browser: Callable[..., Any]) -> Any:
    """A Chromium in which evil.test resolves to 127.0.0.1, as the attacker's DNS makes it."""
    return launch_browser(REBINDING)


def test_a_dns_rebinding_page_cannot_move_the_robot(
    tmp_path: Path, rebinding_browser: Any
) -> None:
    with served_robot(tmp_path, _hold_still) as served:
        port = served.dashboard.server.port  # type: ignore[union-attr]
        context = rebinding_browser.new_context()
        try:
            page = context.new_page()
            response = page.goto(f"http://evil.test:{port}/")
            start = served.world.snapshot()
            outcome = page.evaluate(ATTACK, f"ws://evil.test:{port}/ws")
            # The controller's next 10 steps: each would apply a drive that got in.
            assert wait_for_more(lambda: served.robot.steps, 10)
            end = served.world.snapshot()
        finally:
            context.close()
        assert end == start, (start, end)  # never turned, never moved
        assert served.world.speeds == (0, 0)
        assert outcome == "refused"
        assert response is not None and response.status == 421


def test_the_printed_url_logs_in_cleans_the_url_and_the_page_fills_and_drives(
    tmp_path: Path, browser: Any
) -> None:
    """Content-Security-Policy enforced: the page needs nothing it forbids."""
    with served_robot(tmp_path, _hold_still) as served:
        context = browser.new_context()
        try:
            page = context.new_page()
            blocked: list[str] = []
            page.on("console", lambda m: blocked.append(m.text)
                    if "Content Security Policy" in m.text else None)  # fmt: skip
            page.goto(served.url)
            assert page.url == served.url.split("?")[0]  # the token left the URL bar
            cookies = [c for c in context.cookies() if c["name"].startswith("ego-dashboard-")]
            assert len(cookies) == 1 and cookies[0]["httpOnly"]
            assert cookies[0]["sameSite"] == "Strict" and cookies[0]["path"] == "/"
            assert page.evaluate("document.cookie") == ""  # no script can read it
            _wait_for(page, "document.getElementById('link-status').textContent === 'live'")
            _wait_for(page, "document.getElementById('ray-0') !== null")
            page.click("#take")
            _wait_for(page, "document.getElementById('role').textContent === 'in control'")
            start = served.world.snapshot().x_m
            page.keyboard.down("ArrowUp")
            moved = wait_until(lambda: served.world.snapshot().x_m > start + 0.02, 5)
            page.keyboard.up("ArrowUp")
            page.reload()  # the cookie alone opens the page again
            _wait_for(page, "document.getElementById('link-status').textContent === 'live'")
        finally:
            context.close()
        assert moved
        assert blocked == []


def test_the_printed_url_clicked_on_another_sites_page_logs_in_too(
    tmp_path: Path, browser: Any
) -> None:
    """A SameSite=Strict cookie does not go along a navigation another site started:
    the page asks again from its own origin."""
    with served_robot(tmp_path, _hold_still) as served:
        context = browser.new_context(bypass_csp=True)
        try:
            page = context.new_page()
            link = f'<a id="go" href="{served.url}">the dashboard</a>'
            page.route("http://chat.example/", lambda route: route.fulfill(
                body=link, content_type="text/html"))  # fmt: skip
            page.goto("http://chat.example/")
            page.click("#go")
            page.wait_for_function(
                "document.getElementById('link-status')?.textContent === 'live'")  # fmt: skip
            assert page.url == served.url.split("?")[0]
        finally:
            context.close()


def _wait_for(page: Any, expression: str, timeout_s: float = 10) -> None:
    """Poll ``expression`` in the page (wait_for_function would eval it, which the
    page's policy forbids)."""
    assert wait_until(lambda: bool(page.evaluate(expression)), timeout_s), expression


# -- every command that serves a dashboard -------------------------------------------------

HOLD_STILL = """from controller import Robot
robot = Robot()
robot.getDevice("ps0").enable(32)
while robot.step(32) != -1:
    pass
"""
DRIVE = """from controller import Robot
robot = Robot()
robot.getDevice("ps0").enable(32)
for name in ("left wheel motor", "right wheel motor"):
    motor = robot.getDevice(name)
    motor.setPosition(float("inf"))
    motor.setVelocity(2.0)
while robot.step(32) != -1:
    pass
"""


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


@contextmanager
def _running(
    args: list[str], cwd: Path, env: dict[str, str] | None = None, stderr: Any = subprocess.PIPE
) -> Iterator[LineReader | None]:
    import os

    proc = subprocess.Popen([*ego_command(), *args], stdout=subprocess.DEVNULL,
                            stderr=stderr, text=True, cwd=cwd,
                            env={**os.environ, **(env or {})})  # fmt: skip
    reader = LineReader(proc.stderr) if proc.stderr is not None else None
    try:
        yield reader
    finally:
        proc.terminate()
        try:
            proc.wait(15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        if reader is not None:
            reader.close()


@contextmanager
def _dashboard_of(command: str, bind: str, tmp_path: Path) -> Iterator[str]:
    """Run ``command`` with its dashboard on ``bind`` (off loopback with a secret); the
    URL it printed."""
    secret = tmp_path / "secret"
    secret.write_text("an-ego-test-secret-of-32-bytes!!\n")
    secret.chmod(0o600)
    with_secret = ["--secret-file", str(secret)] if bind != "127.0.0.1" else []
    dashboard = f"--dashboard={bind}:0"  # '=': with a flag or an optional value alike
    if command == "run":
        (tmp_path / "still.py").write_text(HOLD_STILL)
        args = ["run", dashboard, "--port", "sim", *with_secret, "still.py"]
        with _running(args, tmp_path) as err:
            assert err is not None
            yield err.find(r"dashboard at (\S+)")
    elif command == "serve":
        (tmp_path / "drive.py").write_text(DRIVE)
        args = ["serve", dashboard, "--port", "sim", "--listen", "tcp://127.0.0.1:0", *with_secret]
        with _running(args, tmp_path) as err:
            assert err is not None
            url = err.find(r"dashboard at (\S+)")
            robot = err.find(r" on (tcp://\S+)")
            env = {"EGO_SECRET_FILE": str(secret)} if with_secret else {}
            log = tmp_path / "client.log"  # read by nobody unless the test fails
            with log.open("w") as out, _running(["run", "--port", robot, "drive.py"],
                                                tmp_path, env, out):  # fmt: skip
                yield url
    else:
        (tmp_path / "drive.py").write_text(DRIVE)
        args = ["swarm", dashboard, "--robots", "2", "--zenoh-endpoint",
                f"tcp/127.0.0.1:{_free_port()}", *with_secret, "drive.py"]  # fmt: skip
        with _running(args, tmp_path) as err:
            assert err is not None
            yield err.find(r"dashboard at (\S+)")


def _open(page: Any, url: str) -> None:
    page.goto(url)
    page.wait_for_function("document.getElementById('link-status').textContent === 'live'")
    page.wait_for_function("document.getElementById('ray-0') !== null")
    page.click("#take")
    page.wait_for_function("document.getElementById('role').textContent === 'in control'")


def _drives(page: Any, command: str) -> None:
    """What the page's control does: ego run's page drives; ego serve's and ego swarm's,
    whose controllers run elsewhere, stop the wheels their controllers keep turning."""
    speed = "Number(document.getElementById('speed-left').textContent)"
    if command == "run":
        page.keyboard.down("ArrowUp")
        page.wait_for_function(f"{speed} > 0")
        page.keyboard.up("ArrowUp")
    else:
        page.wait_for_function(f"{speed} > 0")
        page.click("#stop")
        page.wait_for_function(f"{speed} === 0")


@pytest.mark.parametrize("command", ["run", "serve", "swarm"])
def test_on_loopback_the_printed_url_fills_and_drives(
    command: str, tmp_path: Path, page: Any
) -> None:
    with _dashboard_of(command, "127.0.0.1", tmp_path) as url:
        assert url.startswith("http://127.0.0.1:") and "?token=" in url
        _open(page, url)
        _drives(page, command)


@pytest.mark.parametrize("command", ["run", "serve", "swarm"])
def test_off_loopback_only_the_token_opens_it(
    command: str, tmp_path: Path, page: Any, browser: Any
) -> None:
    """Bound to every interface, reached through a second loopback address."""
    with _dashboard_of(command, "0.0.0.0", tmp_path) as printed:
        parts = urlsplit(printed)
        assert parts.hostname == socket.gethostname().lower() and "0.0.0.0" not in printed
        url = printed.replace(parts.netloc, f"127.0.0.2:{parts.port}", 1)
        bare = url.split("?")[0]
        stranger = browser.new_context().new_page()
        try:
            for attempt in (bare, bare + "?token=" + "0" * 32):
                response = stranger.goto(attempt)
                assert response is not None and response.status == 403, attempt
            assert "needs its token" in stranger.goto(bare).text()  # type: ignore[union-attr]
        finally:
            stranger.context.close()
        _open(page, url)
        assert page.url == bare
        _drives(page, command)
