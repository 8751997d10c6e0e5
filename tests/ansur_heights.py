"""ANSUR II's adults' heights on stature (`data/ansur2_heights.toml`, written by `tools/fit_ansur2_heights.py`
from the survey's public per-subject tables): where a body's landmark height lies among measured people of
its sex and stature."""

from __future__ import annotations

import tomllib
from functools import cache
from importlib import resources


@cache
def reference() -> dict:
    with resources.files("hitogata").joinpath("data", "ansur2_heights.toml").open("rb") as f:
        return tomllib.load(f)


def height_z(sex: str, stature: float, name: str, height: float) -> float:
    """How many SDs of measured people's scatter about ANSUR II's line a body's height (m) lies from the
    line at its stature (m); name: `iliocristale_height` or `crotch_height`."""
    line = reference()[sex][name]
    return (1000.0 * height - (line["intercept"] + line["slope"] * 1000.0 * stature)) / line["sd"]
