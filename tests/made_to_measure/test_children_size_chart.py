"""A children's size chart: sizes by stature (EN 13402-3 body-height designations 92 … 176), each
size at the age whose median stature it is, made to measure by `hitogata body --size-chart`."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from hitogata.body import growth
from hitogata.cli import main
from hitogata.made_to_measure.size_chart import read_size_chart, shipped_size_charts

CHART = shipped_size_charts()["children_example"]


def test_the_childrens_chart_sizes_are_statures_at_their_median_ages():
    """Each size is its stature in cm, at 6 cm steps, at the age where the growth references' median
    stature of girls and boys together reaches it (within 0.5 cm: ages are given to 0.1 year); the
    two largest, taller than the median 17-year-old girl and boy together, at 17.5 years."""
    chart = read_size_chart(CHART)
    assert [size for size, _, _ in chart] == [str(s) for s in range(92, 177, 6)]
    for size, asked, age in chart:
        assert asked == {"stature": pytest.approx(int(size) / 100)} and age is not None
        median = growth.median("stature", 0.5, age)
        if age < 17.5:
            assert abs(median - asked["stature"]) < 0.005, (size, age, median)
        else:
            assert median < asked["stature"]
        for sex in (0.0, 1.0):  # within the references' percentiles for either sex
            growth.check_within("stature", sex, age, asked["stature"])


@pytest.mark.slow
def test_body_size_chart_makes_every_childrens_size(tmp_path: Path, capsys):
    """Every size made at its stature; its mass, which made to measure leaves to the build path, lies
    within the weight-for-age's 5th–95th percentiles for the size's age (boys)."""
    out = tmp_path / "sizes"
    assert main(["body", "--sex", "male", "--size-chart", "children_example", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    ages = {size: age for size, _, age in read_size_chart(CHART)}
    assert sorted(p.name for p in out.iterdir()) == sorted([*(f"{s}.glb" for s in ages), "sizes.csv"])
    rows = list(csv.DictReader((out / "sizes.csv").read_text(encoding="utf-8").splitlines()))
    assert all(abs(float(r["difference"])) < 0.05 for r in rows) and len(rows) == len(ages)
    for line in printed.splitlines()[:-1]:
        size = Path(line.split(":")[0]).stem
        mass = float(line.split("mass ")[1].split(" kg")[0])
        age = ages[size]
        assert age is not None
        low, high = (growth.at_percentile("mass", 1.0, age, p) for p in (5, 95))
        assert low <= mass <= high, (size, age, mass, low, high)


@pytest.mark.parametrize("content, message", [
    ("size,stature_cm,age_years\n92,92,0.5\n", "row 2, column age_years: '0.5'; allowed years, 1..90"),
    ("size,stature_cm,age_years\n92,92,15\n", "size 92: stature 92.0 cm at age 15: allowed"),
    ("size,stature_cm\n116,116\n", "size 116: stature 116.0 cm: allowed 140–210 cm"),
])
def test_a_childrens_chart_mistake_is_one_line_before_any_body(tmp_path: Path, capsys, monkeypatch, content, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "chart.csv").write_text(content, encoding="utf-8")
    assert main(["body", "--sex", "female", "--size-chart", "chart.csv", "--out", "sizes"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("hitogata: error: chart.csv") and message in err, err
    assert not (tmp_path / "sizes").exists()
