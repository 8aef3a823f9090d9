"""``report.html`` as a reader meets it: what is not clear first, worst first, over every
network; the matrices and the curves without a figure here or with room to spare folded;
the figures it embeds within their budget, the worst curves' first, the others named by
their file; lean markup."""

from __future__ import annotations

import base64
import html
import math
import re
from collections import Counter
from html.parser import HTMLParser
from pathlib import Path

import pytest

from clearance.networks.samples.build import sample_networks
from clearance.reports.documents.embedding import figure_img, png_size
from clearance.reports.documents.markdown import markdown
from clearance.reports.documents.not_clear import not_clear_first, not_clear_html
from clearance.reports.documents.report import (
    Section,
    anchor,
    build_sections,
    figure_order,
    html_document,
    is_not_clear,
)
from clearance.reports.results.records import VERDICT_ORDER
from clearance.reports.study.run import Study, run_study
from clearance.vehicles.table import bundled_table_paths, load_tables

#: Two sample networks: with the method analytic, the bus cannot turn, fails or encroaches
#: on a dozen of the intersection's curves and on two of the garage's, and clears two more
#: of the garage's with less than 0.25 m to spare.
NETS = [p for p in sample_networks() if p.stem.startswith(("intersection", "garage"))]
VEHICLES = ["P", "CITY-BUS"]


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> tuple[Study, list[Section], Path]:
    folder = tmp_path_factory.mktemp("layout")
    study = run_study(NETS, load_tables(bundled_table_paths(), VEHICLES), method="analytic",
                      workers=1)
    return study, build_sections(study, folder), folder


@pytest.fixture(scope="module")
def page(built) -> str:
    study, sections, _ = built
    return html_document(study, sections)


class Layout(HTMLParser):
    """Where each part of a page is: the ids and the classed elements inside a folded
    ``<details>`` and outside any."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.depth = 0
        self.opened = 0
        self.ids: dict[str, bool] = {}  # id: folded
        self.classes: Counter[tuple[str, bool]] = Counter()  # (tag.class, folded)
        self.feed(text)

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if tag == "details":
            self.opened += "open" in a
            self.depth += 1
        if a.get("id"):
            self.ids[str(a["id"])] = self.depth > 0
        if a.get("class"):
            self.classes[f"{tag}.{a['class']}", self.depth > 0] += 1

    def handle_endtag(self, tag: str) -> None:
        self.depth -= tag == "details"


def expected_order(study: Study) -> list[tuple[str, str]]:
    """The curves with a run not clear, worst first, from the runs themselves."""
    worst: dict[tuple[str, str], tuple[int, float]] = {}
    for r in study.records:
        m = r.margin_m if math.isfinite(r.margin_m) else -math.inf
        key = (r.network, r.curve_id)
        worst[key] = min(worst.get(key, (99, math.inf)), (VERDICT_ORDER[r.verdict], m))
    bad = [k for k, rank in worst.items() if rank[0] < VERDICT_ORDER["clear"]]
    return sorted(bad, key=lambda k: worst[k])


def not_clear_rows(text: str) -> list[tuple[str, str, str, str]]:
    """The rows of the opening list: network, full curve id, link target, verdict."""
    box = text.split('<div class="first">', 1)[1].split("</div>", 1)[0]
    rows = re.findall(r'<tr><td>\d+</td><td class="id">([^<]+)</td><td class="id" '
                      r'title="([^"]+)"><a href="#([^"]+)">[^<]+</a></td><td class="tx">'
                      r'[^<]+</td><td class="\w">\S+ ([a-z-]+)</td>', box)
    return [(html.unescape(n), html.unescape(c), t, v) for n, c, t, v in rows]


def test_the_page_opens_with_what_is_not_clear_worst_first(built, page):
    study, sections, _ = built
    order = expected_order(study)
    assert len(order) >= 10 and len({n for n, _ in order}) == 2  # both networks in it
    # first after the contents, before any network's section
    body = page.split("</nav>", 1)[1]
    assert body.lstrip().startswith('<h2 id="not-clear">Not clear, worst first</h2>')
    assert body.index('<div class="first">') < body.index(f'id="{anchor(sections[0].name)}"')
    rows = not_clear_rows(page)
    assert [(n, c) for n, c, _, _ in rows] == order
    # cannot-turn before fails before encroaches, each linked to the curve's section
    ranks = [VERDICT_ORDER[v] for *_, v in rows]
    assert ranks == sorted(ranks) and {"cannot-turn", "fails"} <= {v for *_, v in rows}
    ids = Layout(page).ids
    assert all(t == anchor(n, c) and t in ids for n, c, t, _ in rows)
    assert 'href="#not-clear"' in page.split("</nav>", 1)[0]  # in the contents


def test_matrices_and_tight_curves_are_folded_the_worst_curves_open(built, page):
    _, sections, _ = built
    layout = Layout(page)
    assert layout.depth == 0 and layout.opened == 0  # every <details> closed, and ended
    # every matrix is folded: none of its cells takes room until it is opened
    assert layout.classes["div.matrix", False] == 0
    assert layout.classes["div.matrix", True] == len(sections)
    tight = [(s.name, c) for s in sections for c in s.curves if not is_not_clear(c)]
    assert len(tight) >= 2
    assert all(layout.ids[anchor(name, c.curve_id)] for name, c in tight)
    # each curve not clear has its section open with its figure (all fit the budget here)
    failing = [(s.name, c) for s in sections for c in s.curves if is_not_clear(c)]
    assert not any(layout.ids[anchor(name, c.curve_id)] for name, c in failing)
    assert layout.classes["figure.curve", False] == len(failing)
    assert layout.classes["div.first", False] == 1  # the opening list is never folded


def test_embedded_figures_keep_to_their_budget_the_worst_first(built, page):
    study, sections, folder = built
    ranked = not_clear_first((s.name, c.curve_id, c.runs) for s in sections for c in s.curves)
    order = figure_order(sections, ranked)
    assert len(order) == sum(c.figure is not None for s in sections for c in s.curves) >= 10
    assert all(png.is_file() for png, _ in order)
    # each network's worst curve first, then the curves not clear worst first, the tight last
    rows = not_clear_rows(page)
    firsts: dict[str, tuple[str, str]] = {}
    for n, c, *_ in rows:
        firsts.setdefault(n, (n, c))
    keys = list(dict.fromkeys([*firsts.values(), *((n, c) for n, c, *_ in rows)]))
    assert keys[0] == rows[0][:2] and len(firsts) == 2
    assert [alt for _, alt in order][:len(keys)] == [c for _, c in keys]
    # a budget for the first three
    budget = sum(len(figure_img(png, alt)) for png, alt in order[:3])
    small = html_document(study, sections, figure_bytes=budget)
    layout = Layout(small)
    assert layout.classes["figure.curve", False] == 3
    assert len(small) < len(page) - 5_000 * (len(order) - 3)
    opened = {i for i, folded in layout.ids.items() if i.startswith("curve-") and not folded}
    assert opened == {anchor(n, c) for n, c in keys[:3]}
    # the others name their full-resolution figure, which is there, in a folded part
    named = re.findall(r"<code>figures/([^<]+)</code>", small)
    assert len(named) == len(order) - 3
    assert all((folder / "figures" / html.unescape(n)).is_file() for n in named)
    assert not re.findall(r'(?:src|href)="(?!data:image/png;base64,|#)', small)
    # with no budget, no curve figure: every curve's section folded, the plans still there
    bare = html_document(study, sections, figure_bytes=0)
    none = Layout(bare)
    assert none.classes["figure.curve", False] == none.classes["figure.curve", True] == 0
    assert all(folded for i, folded in none.ids.items() if i.startswith("curve-"))
    others = len(sections) + sum(v.figure is not None for s in sections for v in s.vertical)
    assert bare.count("<img") == others and small.count("<img") == others + 3


def test_each_image_has_its_size_so_a_folded_one_takes_no_room(page):
    images = re.findall(r'<img alt="[^"]*"(?: loading="lazy")? width="(\d+)" height="(\d+)" '
                        r'src="data:image/png;base64,([^"]+)">', page)
    assert len(images) == page.count("<img") >= 12
    for width, height, data in images:
        assert png_size(base64.b64decode(data)) == (int(width), int(height))


def test_the_markup_is_lean(page):
    """A matrix cell is its class, its link and its text: the report used to give each of
    its thousands of cells an inline style and a tooltip (a tenth of the default study's
    page). The page is its figures and little else."""
    cells = re.findall(r'<td class="[a-z]"><a href="#[^"]+">[^<]*</a></td>', page)
    assert len(cells) >= 20
    for cell in cells:
        href = re.search(r'href="#([^"]+)"', cell)[1]
        assert len(cell.encode()) - len(href) <= 45, cell
    text = re.sub(r"<img [^>]*>", "", page)
    assert "style=" not in text
    assert len(text.encode()) < 60_000


def test_report_md_opens_with_the_same_list(built):
    study, sections, folder = built
    md = markdown(study, sections, folder)
    part = md.split("## Not clear, worst first", 1)[1].split("\n## ", 1)[0]
    assert md.index("## Not clear, worst first") < md.index(f"## {sections[0].name}")
    rows = re.findall(r"^\| \d+ \| (\S+) \| `([^`]+)` \| [^|]+ \| ([a-z-]+) \|", part,
                      flags=re.M)
    assert [(n, c) for n, c, _ in rows] == expected_order(study)


def test_a_row_says_what_it_rests_on_and_whether_a_waiver_accepts_it():
    from types import SimpleNamespace as R

    runs = [R(vehicle="BUS", verdict="fails", margin_m=-0.5, paved_margin_m=-0.1,
              geometry="lane width default 3.2 m"),
            R(vehicle="P", verdict="clear", margin_m=0.4, paved_margin_m=0.9, geometry="data")]
    rows = not_clear_first([("n", "turn:J:a_0->b_0", runs)])
    links = {("n", "turn:J:a_0->b_0"): "curve-x"}
    text = "".join(not_clear_html(rows, links, "ft", 1, waived={("n", "turn:J:a_0->b_0",
                                                                    "BUS")}))
    assert '<a href="#curve-x">turn:J:a_0-&gt;b_0</a>' in text
    assert ">BUS (waived)<" in text and "1 of 2: BUS" in text
    assert "1.64 ft beyond its lanes, 0.33 ft beyond the pavement" in text
    assert "lane width default 10.5 ft" in text
    assert "<th>network</th>" not in text  # one network: no column for it
    assert ">BUS<" in "".join(not_clear_html(rows, links, "m", 2))


def test_a_curve_lists_its_runs_not_clear_and_folds_many_clear_ones():
    from types import SimpleNamespace as R

    from clearance.reports.documents.report import MAX_CLEAR_LISTED, CurveEntry, _runs_html

    def run(v: str, verdict: str, m: float):
        return R(vehicle=v, verdict=verdict, margin_m=m, paved_margin_m=m + 1)

    bad = [run("WB-67", "fails", -2.0), run("BUS", "encroaches", -0.5)]
    clear = [run(f"CAR{i}", "clear", 0.1 * i + 0.1) for i in range(MAX_CLEAR_LISTED + 2)]
    text = _runs_html(CurveEntry("c", None, bad + clear, ["WB-67"]), "m")
    shown, folded = text.split('<details class="runs">')
    assert "<li>WB-67: fails, 2.00 m beyond its lanes" in shown and "(drawn)" in shown
    assert "BUS: encroaches" in shown and "CAR" not in shown.replace("closest CAR0", "")
    assert "and 5 vehicles clear, the closest CAR0 (0.10 m inside its lanes)" in folded
    assert all(f"<li>CAR{i}: clear" in folded for i in range(len(clear)))
    # few clear runs, or none not clear: one list, nothing folded
    few = _runs_html(CurveEntry("c", None, bad + clear[:MAX_CLEAR_LISTED], []), "m")
    assert "<details" not in few and few.count("<li>") == 2 + MAX_CLEAR_LISTED
    assert "<details" not in _runs_html(CurveEntry("c", None, clear, []), "m")
