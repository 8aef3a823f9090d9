"""``report.html`` in a real browser: headless Chromium (Debian's package) driven by
playwright. No console error, every link target exists, every image loads; a screenshot is
written for a person to look at (``CLEARANCE_SCREENSHOT_DIR``, default the test's folder).

Skipped only when ``/usr/bin/chromium`` is absent outside CI; in CI (``CI=true``) it must
run (``.ci/run`` installs the package). The browser is never downloaded (no
``playwright install``).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from clearance.networks.samples.build import sample_networks
from clearance.reports.cli.main import main

CHROMIUM = Path("/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--no-first-run"]
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")


@pytest.fixture(scope="module")
def browser():
    if not CHROMIUM.is_file():
        if IN_CI:
            pytest.fail(f"{CHROMIUM} is missing in CI: .ci/run installs the Debian package "
                        "chromium (apt-get install -y chromium)")
        pytest.skip(f"{CHROMIUM} is absent (apt-get install chromium); the test runs in CI")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError as exc:  # the test extra has it
        if IN_CI:
            raise
        pytest.skip(f"playwright is not installed ({exc}); pip install -e '.[test]'")
    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=str(CHROMIUM), args=ARGS, headless=True)
        try:
            yield b
        finally:
            b.close()


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    net = next(p for p in sample_networks() if p.stem.startswith("intersection"))
    out = tmp_path_factory.mktemp("html") / "report"
    assert main(["report", "-n", str(net), "-o", str(out), "--vehicle", "P", "--vehicle",
                 "CITY-BUS", "--method", "analytic"]) == 0
    return out / "report.html"


CHECKS = """() => {
  const ids = new Set([...document.querySelectorAll('[id]')].map(e => e.id));
  const links = [...document.querySelectorAll('a[href]')].map(a => a.getAttribute('href'));
  const images = [...document.images].map(i => ({alt: i.alt, ok: i.complete && i.naturalWidth > 0,
                                                  w: i.naturalWidth}));
  const cells = document.querySelectorAll('.matrix td a').length;
  return {ids: [...ids], links, images, cells,
          height: document.documentElement.scrollHeight};
}"""


def test_the_report_opens_in_chromium(browser, report: Path, tmp_path: Path):
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    errors: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(report.as_uri(), wait_until="load")
    # lazy images load when they come into view: have each load now and wait for it
    decoded = page.evaluate("""() => Promise.all([...document.images].map(i => {
        i.loading = 'eager'; return i.decode().then(() => true, () => false); }))""")
    assert decoded and all(decoded)
    got = page.evaluate(CHECKS)
    assert errors == []
    internal = [h for h in got["links"] if h.startswith("#")]
    assert internal and all(not h.startswith(("http:", "https:")) for h in got["links"])
    missing = sorted({h for h in internal if h[1:] not in got["ids"]})
    assert missing == [], f"links without a target: {missing[:5]}"
    assert got["images"] and all(i["ok"] for i in got["images"]), \
        [i["alt"] for i in got["images"] if not i["ok"]]
    assert got["cells"] > 0  # matrix cells are links to their curves
    # a cell's link leads to the curve's section, which lists every vehicle of the curve
    first = page.locator(".matrix td a").first
    target = first.get_attribute("href")
    first.click()
    page.wait_for_timeout(100)
    section = page.locator(f"[id='{target[1:]}']")
    assert section.count() == 1
    assert page.evaluate("window.location.hash") == target
    shots = Path(os.environ.get("CLEARANCE_SCREENSHOT_DIR", tmp_path))
    shots.mkdir(parents=True, exist_ok=True)
    page.evaluate("window.scrollTo(0, 0)")
    page.screenshot(path=str(shots / "report_top.png"))
    page.locator(".matrix").first.scroll_into_view_if_needed()
    page.screenshot(path=str(shots / "report_matrix.png"))
    page.emulate_media(media="print")
    pdf_like = page.evaluate("getComputedStyle(document.querySelector('.matrix')).overflow")
    assert pdf_like == "visible"  # printed, the matrix is not clipped by a scroll box
    assert (shots / "report_top.png").stat().st_size > 10_000
    page.close()


STICKY = """() => {
  const box = document.querySelector('.matrix');
  const head = box.querySelector('thead th');
  const first = box.querySelector('tbody td.id');
  const before = head.getBoundingClientRect().top - box.getBoundingClientRect().top;
  box.scrollTop = 60;
  const after = head.getBoundingClientRect().top - box.getBoundingClientRect().top;
  return {scrolls: box.scrollHeight > box.clientHeight, before, after,
          rowMoved: first.getBoundingClientRect().top, boxTop: box.getBoundingClientRect().top,
          idWidth: first.getBoundingClientRect().width, boxWidth: box.clientWidth};
}"""


def test_matrix_headings_stay_in_view_when_it_scrolls(browser, report: Path):
    """In a short window the matrix scrolls inside its box: its heading row stays at the
    box's top while the rows pass under it (position: sticky inside the scrolling box)."""
    page = browser.new_page(viewport={"width": 1280, "height": 220})
    page.goto(report.as_uri(), wait_until="load")
    got = page.evaluate(STICKY)
    assert got["scrolls"], "the matrix should scroll in a 220 px window"
    assert abs(got["before"]) < 2 and abs(got["after"]) < 2, got
    assert got["rowMoved"] < got["boxTop"]  # the first row went up under the heading
    assert got["idWidth"] < got["boxWidth"] / 2  # the curve column leaves room for verdicts
