"""A real headless Chromium (the system's, driven by Playwright) to look at dashboards.

The one place that decides whether browser tests run: where there is no Chromium they
skip, with one reason that says how to enable them, unless ``EGO_REQUIRE_BROWSER=1``
(which ``.ci/run`` sets) turns that skip into a failure, so that CI never silently
stops running them.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

#: Where the system's Chromium is (Debian's package: .ci/run installs it when missing).
CHROMIUM = os.environ.get("EGO_CHROMIUM", "/usr/bin/chromium")
#: Set (to 1) where the browser tests must run: a missing Chromium fails them.
REQUIRE_BROWSER = os.environ.get("EGO_REQUIRE_BROWSER", "") not in ("", "0")
#: What a headless Chromium needs on a closed network, as root, with no GPU.
CHROMIUM_FLAGS = [
    "--no-sandbox", "--disable-gpu", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-quic",
]  # fmt: skip


def _missing_browser() -> str | None:
    """Why the browser tests cannot run here (None: they can)."""
    if not Path(CHROMIUM).is_file():
        return f"no Chromium at {CHROMIUM}"
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "no Playwright (pip install -e '.[dev]')"
    return None


def need_browser() -> None:
    """Skip (or, with EGO_REQUIRE_BROWSER=1, fail) the test when no browser can run."""
    missing = _missing_browser()
    if missing is None:
        return
    reason = (f"browser tests need Chromium: {missing}; enable them with "
              "'apt-get install chromium' (or EGO_CHROMIUM=/path/to/chromium)")  # fmt: skip
    if REQUIRE_BROWSER:
        pytest.fail(f"{reason} [EGO_REQUIRE_BROWSER=1: they may not skip]", pytrace=False)
    pytest.skip(reason)


@pytest.fixture(scope="session")
def launch_browser() -> Iterator[Callable[..., Any]]:
    """``launch_browser(*flags)``: a headless Chromium with CHROMIUM_FLAGS and ``flags``,
    closed at the end of the session."""
    need_browser()
    from playwright.sync_api import sync_playwright

    launched: list[Any] = []
    with sync_playwright() as playwright:

        def launch(*flags: str) -> Any:
            chromium = playwright.chromium.launch(executable_path=CHROMIUM,
                                                  args=[*CHROMIUM_FLAGS, *flags])  # fmt: skip
            launched.append(chromium)
            return chromium

        yield launch
        for chromium in launched:
            chromium.close()


@pytest.fixture(scope="session")
def browser(launch_browser: Callable[..., Any]) -> Any:
    return launch_browser()


@pytest.fixture
def page(browser: Any) -> Iterator[Any]:
    # Playwright's wait_for_function evaluates its predicate with eval, which the page's
    # Content-Security-Policy forbids: these tests look past it; test_dashboard_login's
    # keep it and check that the page breaks none of it.
    context = browser.new_context(viewport={"width": 1300, "height": 950}, bypass_csp=True)
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    yield page
    context.close()
    assert errors == [], errors  # the page's script never failed
