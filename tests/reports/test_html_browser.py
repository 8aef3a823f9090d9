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
    """Two sample networks: the bus does not clear a dozen curves of the intersection and
    two of the garage, and clears two more of the garage's with little to spare."""
    nets = [p for p in sample_networks() if p.stem.startswith(("intersection", "garage"))]
    out = tmp_path_factory.mktemp("html") / "report"
    assert main(["report", *(a for n in nets for a in ("-n", str(n))), "-o", str(out),
                 "--vehicle", "P", "--vehicle", "CITY-BUS", "--method", "analytic"]) == 0
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
    # the matrix is folded: its summary opens it, and a cell's link leads to the curve's
    # section, which lists every vehicle of the curve
    first = page.locator(".matrix td a").first
    assert not first.is_visible()
    page.locator("details.fold:has(.matrix) > summary").first.click()
    assert first.is_visible()
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
    page.evaluate("document.querySelectorAll('details').forEach(d => d.open = false)")
    page.emulate_media(media="print")
    pdf_like = page.evaluate("getComputedStyle(document.querySelector('.matrix')).overflow")
    assert pdf_like == "visible"  # printed, the matrix is not clipped by a scroll box
    # ... nor by its fold: closed on the screen, a folded part prints open
    printed = page.evaluate("[...document.querySelectorAll('details.fold')].map("
                            "d => d.getBoundingClientRect().height)")
    assert printed and min(printed) > 100, printed
    assert (shots / "report_top.png").stat().st_size > 10_000
    page.close()


STICKY = """() => {
  document.querySelector('details.fold:has(.matrix)').open = true;
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


LAYOUT = """() => {
  const top = e => e.getBoundingClientRect().top + window.scrollY;
  const height = () => document.documentElement.scrollHeight;
  const folds = [...document.querySelectorAll('details.fold')];
  const figures = [...document.querySelectorAll('figure.curve')]
    .filter(f => !f.closest('details'));
  const closed = {height: height(), folds: folds.map(d => d.getBoundingClientRect().height),
                  list: top(document.querySelector('.first')),
                  network: top(document.querySelector('h2[id^="net-"]')),
                  figures: figures.reduce((a, f) => a + f.getBoundingClientRect().height, 0),
                  networks: document.querySelectorAll('h2[id^="net-"]').length};
  folds.forEach(d => d.open = true);
  const opened = {height: height(), folds: folds.map(d => d.getBoundingClientRect().height)};
  folds.forEach(d => d.open = false);
  return {closed, opened};
}"""


def test_the_page_opens_with_what_is_not_clear_and_folds_the_rest(browser, report: Path):
    """The first screen shows the list of what is not clear; the matrices and the tight
    curves are folded, taking a line each until opened; the page's height is the worst
    curves' figures and little else."""
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    page.goto(report.as_uri(), wait_until="load")
    got = page.evaluate(LAYOUT)
    closed, opened = got["closed"], got["opened"]
    assert closed["list"] < 900 - 100  # the list starts on the first screen
    assert closed["list"] < closed["network"]
    assert len(closed["folds"]) >= 3  # two matrices and the tight curves of the garage
    assert max(closed["folds"]) < 60  # a folded part is its summary line
    assert all(o > 150 for o in opened["folds"]), opened
    grown = sum(opened["folds"]) - sum(closed["folds"])
    assert opened["height"] - closed["height"] == pytest.approx(grown, abs=5)
    # beside the open curves' figures, each network takes at most 3000 px (its summary,
    # plan and worst curves) and the head and the list 1500 px
    assert closed["figures"] > 0
    assert closed["height"] - closed["figures"] < 1500 + 3000 * closed["networks"], closed
    page.close()


def test_a_link_into_a_folded_part_opens_it(browser, report: Path):
    """The worst curves under a plan link to their sections, a tight one's folded: the
    browser opens the fold and shows the section (no script)."""
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    page.goto(report.as_uri(), wait_until="load")
    target = page.evaluate("""() => [...document.querySelectorAll('details.fold h4[id]')]
        .map(h => h.id).find(id => document.querySelector(`a[href="#${id}"]`
                                                          + ':not(details a)'))""")
    assert target, "no link outside a fold to a curve inside one"
    heading = page.locator(f"[id='{target}']")
    assert not heading.is_visible()
    page.locator(f"a[href='#{target}']:not(details a)").first.click()
    page.wait_for_timeout(100)
    assert heading.is_visible()
    assert page.evaluate(f"document.getElementById('{target}').closest('details').open")
    page.close()
