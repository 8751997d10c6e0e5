"""`hitogata fit-report`: the page shows the tables it wrote, opens offline in Chromium, refuses bad input.

Kept cheap: the default female through reach-forward at 2 frames per second (its hold at 1.5 s is
sampled), a −15 % garment of a 400 N/m fabric, and a 2-body × 1-motion study of 3 frames run in a
plain loop. Mistakes are found before any body is built (`body_from_args` is replaced by a failure).
"""

from __future__ import annotations

import csv
import html
import io
import json
import shutil
from html.parser import HTMLParser
from pathlib import Path

import pytest

from hitogata import cli
from hitogata.commands import fit_report
from hitogata.study.runner import run_serial
from hitogata.study.spec import load_study
from waiting import PATIENCE

STUDIES = Path(__file__).parents[2] / "src" / "hitogata" / "data" / "studies"
CHART = "size,sex,stature_cm,mass_kg\nS,female,155,50\nL,male,185,90\n"
REPORT = ["fit-report", "--motions", "reach", "--rate", "2", "--garment-ease=-15%", "--fabric", "400N/m"]


class Tables(HTMLParser):
    """Every <table id=…> of a page as rows of cell texts; the <img> sources."""

    def __init__(self, text: str) -> None:
        super().__init__()
        self.tables: dict[str, list[list[str]]] = {}
        self.images: list[str] = []
        self._table: list[list[str]] | None = None
        self._cell: list[str] | None = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "table" and "id" in a:
            self._table = self.tables.setdefault(a["id"], [])
        elif tag == "tr" and self._table is not None:
            self._table.append([])
        elif tag in ("td", "th") and self._table is not None:
            self._cell = []
        elif tag == "img":
            self.images.append(a["src"])

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None and self._table is not None:
            self._table[-1].append("".join(self._cell).strip())
            self._cell = None
        elif tag == "table":
            self._table = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def rows(path: Path) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(path.read_text(encoding="utf-8"))))


def agree(page: list[str], table: list[str]) -> bool:
    """The page's one-decimal figures are the CSV's (4 significant digits) rounded: within 0.05."""
    return len(page) == len(table) and all(a == b == "undefined" or abs(float(a) - float(b)) <= 0.0501
                                           for a, b in zip(page, table))


@pytest.fixture(scope="module")
def study(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("study")
    (folder / "chart.csv").write_text(CHART, encoding="utf-8")
    (folder / "study.toml").write_text(f'motions = ["{STUDIES / "arms_raised.toml"}"]\n[bodies]\nchart = "chart.csv"\n'
                                       "[model]\nframes = 3\n", encoding="utf-8")
    summary = run_serial(load_study(folder / "study.toml"), folder / "results")
    assert (summary.done, summary.failed) == (2, 0)
    return folder / "results"


@pytest.fixture(scope="module")
def report(study, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("report") / "report"
    assert cli.main([*REPORT, "--study", str(study), "--out", str(out)]) == 0
    return out


@pytest.mark.render
def test_the_page_shows_the_tables_it_wrote(report):
    assert sorted(p.name for p in report.iterdir()) == [
        "ease.csv", "ease.json", "fit_report.html", "measurements.csv", "non_extension.csv", "non_extension.json",
        "percentiles.csv", "pressure.csv", "stretch.csv", "summary.json"]
    page = Tables((report / "fit_report.html").read_text(encoding="utf-8"))
    ease = {r["measurement"]: r for r in rows(report / "ease.csv") if r["motion"] == "all"}
    table = {r[0]: r for r in page.tables["ease-all"][1:]}
    assert len(table) == len(ease) == 26
    for name, r in ease.items():
        assert agree(table[name.replace("_", " ")][1:4], [r["standing_cm"], r["increase_cm"], r["increase_pct"]]), name
    # pinned headline numbers (as tests/garment/test_garment_ease.py on reach-forward)
    assert table["across back width"][1:3] == ["31.0", "+6.4"] and table["across front width"][5] == "-5.6"
    stretch = {r["zone"]: r for r in rows(report / "stretch.csv")}
    shown_stretch = {r[0]: r for r in page.tables["stretch-reach_forward"][1:]}
    for zone, r in stretch.items():
        assert agree(shown_stretch[zone.replace("_", " ")][1:4],
                     [r[k] for k in ("lengthwise_pct", "crosswise_pct", "principal_pct")]), zone
    assert shown_stretch["across back"][2] == "51.6"
    pressure = rows(report / "pressure.csv")
    knee = max(float(r["peak_mmHg"]) for r in pressure if r["level"] == "knee")
    shown_knee = {r[0]: r for r in page.tables["pressure-reach_forward"][1:]}["knee"][3]
    assert agree([shown_knee], [str(knee)]) and shown_knee == "18.2"
    bands = [r for r in rows(report / "percentiles.csv") if r["group"] == "all" and r["quantity"] == "dynamic_ease"]
    shown_bands = {r[1]: r for r in page.tables["percentiles-arms_raised"][1:] if r[0] == "dynamic ease"}
    for r in bands:
        assert agree(shown_bands[r["name"].replace("_", " ")][3:6], [r[k] for k in ("p5", "p50", "p95")]), r["name"]
    summary = json.loads((report / "summary.json").read_text(encoding="utf-8"))
    risk = summary["risks"]
    assert (risk["ease"]["measurement"], round(risk["ease"]["increase_cm"], 1)) == ("across_back_width", 6.4)
    assert (risk["stretch"]["zone"], risk["stretch"]["direction"]) == ("shoulder", "lengthwise")
    assert (risk["pressure"]["level"], round(risk["pressure"]["peak_mmHg"], 1)) == ("ankle", 25.5)
    text = (report / "fit_report.html").read_text(encoding="utf-8")
    assert html.escape(summary["summary"]) in text and "+6.4 cm" in summary["summary"] and "25.5 mmHg peak" in summary["summary"]
    # each figure beside the published measurements that speak to it (the shipped validation set's rows)
    from hitogata.validation import load_dataset

    shown_rows = page.tables["measured-people"][1:]
    data = load_dataset()
    for figure, kind, quantity in (("across back width", "posture_change", "across_back_width"),
                                   ("calf girth", "posture_change", "calf_girth"), ("ankle", "pressure", "ankle")):
        expected = {r.id for r in data.rows if r.kind == kind and r.quantity == quantity}
        assert expected and {r[1].split(":")[0] for r in shown_rows if r[0] == figure} == expected, figure
    # the lines of non-extension: the JSON's are the CSV's, counted in the picture's caption (pinned)
    lines = json.loads((report / "non_extension.json").read_text(encoding="utf-8"))["reach_forward"]
    points = rows(report / "non_extension.csv")
    assert len(points) == sum(len(line["points_mm"]) for line in lines)
    assert {(r["line"], r["point"]): [float(r[k]) for k in ("x_mm", "y_mm", "z_mm")] for r in points} == {
        (str(k), str(i)): p for k, line in enumerate(lines) for i, p in enumerate(line["points_mm"])}
    assert (len(lines), round(sum(line["length_mm"] for line in lines) / 1000, 1)) == (124, 14.9)
    # snapshots, the ease plot over time, stretch map, lines of non-extension, pressure map; the overall
    # plot; the band plot
    assert len(page.images) == 7 and all(src.startswith("data:image/png;base64,") for src in page.images)
    assert "http:" not in text and "https:" not in text and "<script" not in text


@pytest.mark.render
@pytest.mark.browser
def test_the_page_opens_offline_in_chromium_without_errors_or_requests(report, tmp_path):
    sync_api = pytest.importorskip("playwright.sync_api", reason="the browser test needs playwright")
    if not Path("/usr/bin/chromium").exists():
        pytest.skip("the browser test needs Debian's chromium (apt-get install chromium)")
    url = (report / "fit_report.html").resolve().as_uri()
    problems, requests = [], []
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch_persistent_context(
            str(tmp_path / "profile"), executable_path="/usr/bin/chromium", headless=True,
            args=["--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync"], offline=True, timeout=PATIENCE * 1000)
        try:
            page = browser.new_page()
            page.set_default_timeout(PATIENCE * 1000)  # a bound for a busy machine, not a pause
            page.on("console", lambda m: problems.append(m.text) if m.type in ("error", "warning") else None)
            page.on("pageerror", lambda e: problems.append(str(e)))
            page.on("request", lambda r: requests.append(r.url))
            page.goto(url, wait_until="load")
            loaded = page.evaluate("Array.from(document.images).map(i => i.complete && i.naturalWidth > 0)")
            headings = page.locator("h2").all_inner_texts()
        finally:
            browser.close()
        shutil.rmtree(tmp_path / "profile", ignore_errors=True)
    assert problems == []
    assert requests == [url]  # the page itself; its pictures are data URIs
    assert loaded == [True] * 7
    assert headings == ["the body", "all motions", "beside measured people", "reach forward", "population"]


def test_a_study_alone_gives_the_population_section(study, tmp_path):
    assert cli.main(["fit-report", "--study", str(study), "--out", str(tmp_path / "r")]) == 0
    assert sorted(p.name for p in (tmp_path / "r").iterdir()) == ["fit_report.html", "percentiles.csv",
                                                                   "summary.json"]
    page = Tables((tmp_path / "r" / "fit_report.html").read_text(encoding="utf-8"))
    assert list(page.tables) == ["percentiles-arms_raised"] and len(page.images) == 1
    assert page.tables["percentiles-arms_raised"][0][:6] == ["quantity", "name", "unit", "all P5", "all P50", "all P95"]


def boom(*_args, **_kwargs):
    raise AssertionError("the body was built before the mistake was found")


@pytest.mark.parametrize("extra, message", [
    (["--motions", "reach,cartwheel"], "--motions: 'cartwheel'; allowed a scenario file (.toml) or arms_crossed"),
    (["--motions", "arms"], "--motions: 'arms' (stands for arms_crossed and arms_overhead); allowed"),
    (["--body", "missing.glb"], "--body: missing.glb: no such file or folder; allowed a file (.glb)"),
    (["--body", "notes.txt"], "--body: notes.txt: unknown file suffix '.txt'; allowed a file (.glb)"),
    (["--study", "not_a_study"], "--study not_a_study: no task rows (rows/motion=*/*.parquet); allowed the --out "
                                 "folder of `hitogata study`"),
    (["--study", "notes.txt"], "--study: notes.txt: is a file; allowed a folder"),
    (["--garment-ease=-15%"], "--garment-ease and --fabric: give both"),
])
def test_a_mistake_is_one_line_before_any_work_and_nothing_is_written(extra, message, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(fit_report, "body_from_args", boom)
    (tmp_path / "not_a_study").mkdir()
    (tmp_path / "notes.txt").write_text("x", encoding="utf-8")
    before = sorted(p.name for p in tmp_path.iterdir())
    assert cli.main(["fit-report", *extra, "--out", "report"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("hitogata: error: ") and message in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no report, no staging folder
