"""Open a page in a real headless Chromium (Debian's ``chromium``) through Playwright.

``require_browser`` skips the test when Playwright or Chromium is missing, except when
the environment variable ``CI`` is set, where it fails: CI installs both.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

CHROMIUM_FLAGS = [
    "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]


def require_browser() -> str:
    """The Chromium executable, or skip (fail when ``CI`` is set)."""
    executable = os.environ.get("EXPRESS_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        executable = None
    if executable is None:
        if os.environ.get("CI", ""):
            pytest.fail("Chromium and Playwright are required in CI (CI is set): apt-get install chromium")
        pytest.skip("Chromium or Playwright is not installed")
    return executable


def artifact_dir() -> Path:
    """Where tests keep screenshots (``test-artifacts/`` at the repository root)."""
    path = Path(os.environ.get("EXPRESS_TEST_ARTIFACTS", Path(__file__).resolve().parents[1] / "test-artifacts"))
    path.mkdir(parents=True, exist_ok=True)
    return path


def inspect_page(path: Path, screenshot: Path, viewport: tuple[int, int] | None = None) -> dict:
    """Load ``path`` and return console errors, network requests other than the file,
    the rendered sizes of figures and formulas, how far the page overflows its window
    sideways (``overflow_px``, 0 when nothing does) and the text of the page; keep a
    full-page screenshot. ``viewport``: window (width, height) [px]."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=require_browser(), args=CHROMIUM_FLAGS)
        page = browser.new_page(**({"viewport": {"width": viewport[0], "height": viewport[1]}} if viewport else {}))
        errors: list[str] = []
        requests: list[str] = []
        page.on("console", lambda message: errors.append(message.text) if message.type == "error" else None)
        page.on("pageerror", lambda error: errors.append(str(error)))
        page.on("request", lambda request: requests.append(request.url))
        page.goto(path.resolve().as_uri())
        page.wait_for_load_state("load")
        sizes = page.eval_on_selector_all(
            "figure svg", "els => els.map(e => [e.getBoundingClientRect().width, e.getBoundingClientRect().height])")
        formulas = page.eval_on_selector_all(
            "math", "els => els.map(e => [e.getBoundingClientRect().width, e.getBoundingClientRect().height])")
        sections = page.eval_on_selector_all("section h2", "els => els.map(e => e.textContent)")
        overflow = page.evaluate(  # how far a part of a section sticks out of the page's column, or the window
            "Math.max(document.documentElement.scrollWidth - document.documentElement.clientWidth, ...Array.from("
            "document.querySelectorAll('section > *')).map(e => e.getBoundingClientRect().right - "
            "document.body.getBoundingClientRect().right))")
        text = page.evaluate("document.body.innerText")
        page.screenshot(path=str(screenshot), full_page=True)
        browser.close()
    return {"errors": errors, "requests": [r for r in requests if not r.startswith("file:")],
            "figures": sizes, "formulas": formulas, "sections": sections, "overflow_px": overflow, "text": text}
