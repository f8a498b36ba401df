"""The dashboard on a phone, in a real headless Chromium: STOP is on screen and works at
360 and 412 px wide (and stays there as the page scrolls), nothing overflows sideways,
and a stopped robot shows a banner on every page until it is resumed."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from dashboard_support import served_robot
from helpers import wait_until

import ego

PHONES = [(360, 740), (412, 915)]


@contextmanager
def phone(browser: Any, width: int, height: int) -> Iterator[Any]:
    # bypass_csp: Playwright's wait_for_function evaluates strings, which the page's CSP
    # forbids (the CSP itself is checked by test_dashboard_login.py).
    context = browser.new_context(
        viewport={"width": width, "height": height}, has_touch=True, bypass_csp=True
    )
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    try:
        yield page
    finally:
        context.close()
    assert errors == [], errors


def _open(page: Any, url: str) -> None:
    page.goto(url)
    page.wait_for_function("document.getElementById('link-status').textContent === 'live'")
    page.wait_for_function("document.getElementById('ray-0') !== null")


def _on_screen(page: Any, selector: str) -> bool:
    """Whether the element's whole box lies inside the viewport."""
    return bool(page.evaluate(
        """(selector) => {
            const r = document.querySelector(selector).getBoundingClientRect();
            return r.width > 0 && r.height > 0 && r.left >= 0 && r.top >= 0
                && r.right <= window.innerWidth && r.bottom <= window.innerHeight;
        }""",
        selector,
    ))  # fmt: skip


def _drive_on(robot: ego.Robot) -> None:
    robot.motors.set_speed(300, 300)


@pytest.mark.parametrize(("width", "height"), PHONES)
def test_stop_is_on_screen_and_stops_the_robot_on_a_phone(
    tmp_path: Path, browser: Any, width: int, height: int
) -> None:
    with served_robot(tmp_path, _drive_on) as served, phone(browser, width, height) as page:
        _open(page, served.url)
        assert _on_screen(page, "#stop") and _on_screen(page, "#take")
        # Nothing is wider than the screen: no sideways scrolling to reach a button.
        assert page.evaluate("document.documentElement.scrollWidth") <= width
        page.tap("#take")
        page.wait_for_function("document.getElementById('role').textContent === 'in control'")
        assert wait_until(lambda: served.world.speeds == (300, 300), 3)
        page.evaluate("window.scrollTo(0, document.body.scrollHeight)")  # down at the plot
        page.wait_for_function("window.scrollY > 300")
        assert _on_screen(page, "#stop")  # the header, and STOP in it, stay on screen
        page.tap("#stop")  # a real tap where STOP is drawn: nothing covers it
        assert wait_until(lambda: served.world.speeds == (0, 0), 1)
        page.wait_for_function("!document.getElementById('stopped-banner').hidden")
        assert _on_screen(page, "#stopped-banner")
        assert "stopped" in page.inner_text("#stopped-banner").lower()
        assert _on_screen(page, "#resume") and _on_screen(page, "#stop")
        page.tap("#resume")
        page.wait_for_function("document.getElementById('stopped-banner').hidden")
        assert wait_until(lambda: served.world.speeds == (300, 300), 2)


def test_every_page_shows_the_banner_while_the_robot_is_stopped(
    tmp_path: Path, browser: Any
) -> None:
    with (
        served_robot(tmp_path, _drive_on) as served,
        phone(browser, 360, 740) as driver,
        phone(browser, 412, 915) as viewer,
    ):
        _open(driver, served.url)
        _open(viewer, served.url)
        assert viewer.is_hidden("#stopped-banner")
        driver.tap("#take")
        driver.wait_for_function("document.getElementById('role').textContent === 'in control'")
        driver.tap("#stop")
        viewer.wait_for_function("!document.getElementById('stopped-banner').hidden")
        assert _on_screen(viewer, "#stopped-banner")
        assert "until the page in control resumes" in viewer.inner_text("#stopped-banner")
        assert wait_until(lambda: served.world.speeds == (0, 0), 1)


@pytest.mark.parametrize(("width", "height"), [*PHONES, (1280, 800)])
def test_the_cards_fit_the_screen_at_any_width(
    tmp_path: Path, browser: Any, width: int, height: int
) -> None:
    with served_robot(tmp_path, _drive_on) as served, phone(browser, width, height) as page:
        _open(page, served.url)
        page.wait_for_function("document.getElementById('h-time').textContent !== '–'")
        page.wait_for_function("!view.dirty && !view.mapDirty")  # drawn since
        boxes = page.evaluate(
            "[...document.querySelectorAll('.card, header, header *, canvas, svg, select')]"
            ".filter((e) => e.getBoundingClientRect().width > 0).map((e) => "
            "[e.id || e.tagName, e.getBoundingClientRect().left, e.getBoundingClientRect().right])"
        )
        header = page.evaluate("document.querySelector('header').getBoundingClientRect().height")
    for name, left, right in boxes:
        assert left >= 0 and right <= width, (name, left, right, width)
    assert header < height / 4  # the sticky header leaves the screen to the cards
