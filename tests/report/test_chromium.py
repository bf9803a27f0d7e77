"""End to end in a real browser: every report opens in headless Chromium without a console message, runs its script,
shows its elements, answers a hover, and renders a screenshot of the window size asked for.

Chromium is Debian's ``chromium`` package. When it is missing the session installs it (``apt-get install -y
chromium`` as root, with a timeout); where that is impossible (not root, no apt-get, no network) every test here
is skipped with the reason. The browser runs with no sandbox (containers), no GPU, no QUIC and none of its
background traffic, in a fresh profile folder, on ``file://`` pages: a report needs no server and no network.
"""

from __future__ import annotations

import os
import re
import shutil
import struct
import subprocess
from pathlib import Path

import pytest

from .conftest import ANSWER_COMMANDS

pytestmark = pytest.mark.browser

INSTALL_TIMEOUT = 900  # seconds for apt-get (a first install downloads about 100 MB)
BROWSER_TIMEOUT = 60  # seconds for one page


def _find() -> str | None:
    for name in ("chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    return None


def _install() -> str:
    """Install Debian's chromium; return why not when it cannot be done (an empty string when it was)."""
    if os.name != "posix" or os.geteuid() != 0:
        return "chromium is not installed and the tests do not run as root (apt-get install -y chromium needs root)"
    apt = shutil.which("apt-get")
    if apt is None:
        return "chromium is not installed and there is no apt-get to install it"
    env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
    try:
        done = subprocess.run([apt, "install", "-y", "--no-install-recommends", "chromium"], env=env, capture_output=True,
                              text=True, timeout=INSTALL_TIMEOUT, check=False)
        if done.returncode != 0:  # the package lists may be missing: refresh them once
            subprocess.run([apt, "update"], env=env, capture_output=True, timeout=INSTALL_TIMEOUT, check=False)
            done = subprocess.run([apt, "install", "-y", "--no-install-recommends", "chromium"], env=env,
                                  capture_output=True, text=True, timeout=INSTALL_TIMEOUT, check=False)
    except subprocess.TimeoutExpired:
        return f"apt-get install -y chromium did not finish in {INSTALL_TIMEOUT} s"
    if done.returncode != 0:
        tail = (done.stderr or done.stdout).strip().splitlines()[-1:] or ["no output"]
        return f"apt-get install -y chromium failed (exit {done.returncode}): {tail[0][:200]}"
    return ""


@pytest.fixture(scope="session")
def chromium() -> str:
    """The path of a headless-capable Chromium (installed if missing), or skip with the reason."""
    found = _find()
    if found is None:
        why = _install()
        found = _find()
        if found is None:
            pytest.skip(why or "chromium was installed but is not on PATH")
    return found


class Browser:
    """One headless Chromium run per page, in a fresh profile under ``tmp``."""

    def __init__(self, binary: str, tmp: Path) -> None:
        self.binary, self.tmp, self.runs = binary, tmp, 0

    def _run(self, page: Path, *extra: str) -> subprocess.CompletedProcess:
        self.runs += 1
        profile = self.tmp / f"profile-{self.runs}"
        args = [self.binary, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--disable-default-apps", "--hide-scrollbars", f"--user-data-dir={profile}",
                "--host-resolver-rules=MAP * ~NOTFOUND",  # no name resolves: a page that needed the network would fail
                "--enable-logging=stderr", "--v=0", *extra, page.resolve().as_uri()]
        try:
            return subprocess.run(args, capture_output=True, text=True, timeout=BROWSER_TIMEOUT, check=False)
        except subprocess.TimeoutExpired:
            pytest.fail(f"chromium did not finish {page.name} in {BROWSER_TIMEOUT} s")

    def dom(self, page: Path) -> tuple[str, list[str]]:
        """The DOM after the page loaded and its scripts ran, and every console message it produced."""
        done = self._run(page, "--dump-dom")
        assert done.returncode == 0, done.stderr[-2000:]
        return done.stdout, console_messages(done.stderr)

    def screenshot(self, page: Path, out: Path, size: tuple[int, int] = (1200, 900)) -> list[str]:
        done = self._run(page, f"--screenshot={out}", f"--window-size={size[0]},{size[1]}")
        assert done.returncode == 0, done.stderr[-2000:]
        return console_messages(done.stderr)


def console_messages(log: str) -> list[str]:
    """The page's console output in Chromium's stderr log (``...:INFO:CONSOLE(12)] "message", source: ...``)."""
    return [line for line in log.splitlines() if re.search(r":CONSOLE(\(\d+\)|:\d+)?\]", line)]


@pytest.fixture(scope="module")
def browser(chromium, tmp_path_factory) -> Browser:
    return Browser(chromium, tmp_path_factory.mktemp("chromium"))


def test_console_errors_are_seen(browser, tmp_path):
    """The control: a page with a script error does produce the console lines the other tests look for."""
    page = tmp_path / "broken.html"
    page.write_text('<!DOCTYPE html><html><head><meta charset="utf-8"><title>t</title></head><body><p id="x">x</p>'
                    "<script>undefinedFunction();</script></body></html>")
    dom, messages = browser.dom(page)
    assert '<p id="x">x</p>' in dom
    assert any("undefinedFunction is not defined" in m for m in messages), messages


# what each page must show once loaded (ids of the picture, tables and sections)
EXPECTED = {
    "plan": ['id="scene"', 'id="stages"', 'class="hover cone"', 'id="certificate-status">VALID<', 'id="plan-stages"'],
    "pareto": ['id="scene"', 'id="front"', 'id="stages"', 'id="certificate-status">VALID<'],
    "patrol": ['id="scene"', 'id="cycle-stages"', 'class="hover cone fan"', 'id="certificate-status">VALID<'],
    "funnel": ['id="scene"', 'id="funnel-positions"', 'id="certificate-status">VALID<'],
    "localize": ['id="scene"', 'id="funnel-positions"', 'id="certificate-status">VALID<'],
    "cycle": ['id="scene"', 'id="fixed-points"', 'class="hover contact"'],
    "controller": ['id="scene"', 'id="tried"', 'id="cycle-0"'],
    "study": ['class="heat"', 'id="cells"', 'class="hover cell"'],
    # the other robot models (issue #23): every kind has a report; the picture zooms and pans (the script's buttons)
    "rooms": ['id="scene"', 'id="zoom"', 'class="hover room"', 'class="hover door"', 'class="hover tree"', 'id="doors"',
              "Φ leaving i"],
    "exploration": ['id="scene"', 'class="hover view"', 'class="hover viewpoint"', 'id="viewpoints"'],
    "range-exploration": ['id="scene"', 'class="range"', 'id="viewpoints"'],
    "cut-ordering": ['id="scene"', 'class="hover chord"', 'id="ordering"'],
    "learned-ordering": ['id="scene"', 'class="hover chord"', 'id="ordering"'],
    "vertex-count": ['id="summary"', "true_winding"],
    "pursuit": ['id="scene"', 'class="hover step"', 'id="steps"'],
    "fields": ['id="scene"', 'class="hover cell"', 'class="hover trajectory"', 'id="scenarios"', 'id="fields"'],
}


@pytest.mark.parametrize("kind", list(ANSWER_COMMANDS))
def test_report_loads_without_console_messages(kind, browser, reports):
    dom, messages = browser.dom(reports[kind])
    assert messages == [], messages  # no error, no CSP violation (a blocked load would be reported here), nothing
    assert 'data-report-ready="yes"' in dom  # the inline script ran (its CSP hash matched)
    for fragment in EXPECTED[kind]:
        assert fragment in dom, (kind, fragment)
    assert 'id="command"' in dom and 'id="details"' in dom


def test_hovering_a_cone_shows_its_details_and_highlights_its_stage(browser, reports, tmp_path):
    """Drive the page's own script: a copy of the plan report whose policy admits one more script, which hovers
    the first cone of stage 2 and records what the details panel and the stage row show."""
    text = reports["plan"].read_text(encoding="utf-8")
    text = re.sub(r'<meta http-equiv="Content-Security-Policy"[^>]*>', "", text)
    probe = ("<script>(function(){var cone=document.querySelector('#scene .cone[data-stage=\"1\"]');"
             "cone.dispatchEvent(new MouseEvent('mouseover',{bubbles:true}));"
             "var row=document.querySelector('tr[data-stage=\"1\"]');"
             "document.body.setAttribute('data-probe-details',document.getElementById('details').textContent);"
             "document.body.setAttribute('data-probe-row',row.className);"
             "document.body.setAttribute('data-probe-lit',String(document.querySelectorAll('.hl').length));"
             "cone.dispatchEvent(new MouseEvent('mouseout',{bubbles:true}));"
             "document.body.setAttribute('data-probe-after',String(document.querySelectorAll('.hl').length));"
             "})();</script></body>")
    page = tmp_path / "hover.html"
    page.write_text(text.replace("</body>", probe), encoding="utf-8")
    dom, messages = browser.dom(page)
    assert messages == [], messages
    details = re.search(r'data-probe-details="([^"]*)"', dom).group(1)
    assert details.startswith("stage 2, move 51 → 46: heading interval ["), details
    assert re.search(r'data-probe-row="hl"', dom)
    lit = int(re.search(r'data-probe-lit="(\d+)"', dom).group(1))
    assert lit >= 3  # the cone, its landing segment, its label and its table row
    assert 'data-probe-after="0"' in dom


def _png_size(path: Path) -> tuple[int, int]:
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


def test_screenshot_of_the_issues_example(browser, reports, tmp_path):
    """The window the report is looked at in (1200 × 900): a PNG of that size, no console message."""
    out = tmp_path / "plan.png"
    messages = browser.screenshot(reports["plan"], out)
    assert messages == [], messages
    assert _png_size(out) == (1200, 900)
    assert out.stat().st_size > 20_000  # a picture, not a blank page (a blank 1200 × 900 PNG is ~5 kB)


def test_without_chromium_the_reason_to_skip_is_said(monkeypatch):
    """Where Chromium cannot be installed the session skips with the reason (checked without touching apt)."""
    monkeypatch.setattr(os, "geteuid", lambda: 1000)
    assert "do not run as root" in _install()
    monkeypatch.setattr(os, "geteuid", lambda: 0)
    monkeypatch.setattr(shutil, "which", lambda name: None)
    assert "no apt-get" in _install()
