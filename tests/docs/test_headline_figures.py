"""The shipped model's headline figures, pinned in tests/golden/docs/test_headline_figures.json: the ISO 8559-1
measurements of the default bodies at rest (metres) and the default trunk model's first frequencies (P2 at 40 mm,
rigid bone, free cuts, shipped materials; Hz). A change that moves them says why (`make repin`, tests/golden.py).

docs/measurements.md and docs/elastic.md quote them. The whole body's frequencies are pinned with the whole-body
model's tests.
"""

import pytest

from hitogata.body import default_body
from hitogata.elastic import build_elastic_model
from hitogata.measure import measure

@pytest.mark.parametrize("sex", ["female", "male"])
def test_default_body_measurements(request, golden, sex: str) -> None:
    values = measure(request.getfixturevalue(sex)).as_dict()
    golden.check(f"{sex}.measurements_m", values, abs=5e-5)  # 0.05 mm: the figures as docs/measurements.md rounds them


@pytest.mark.slow
@pytest.mark.parametrize("sex", ["female", "male"])
def test_default_trunk_first_frequencies(golden, sex: str) -> None:
    model = build_elastic_model(default_body(sex))
    golden.check(f"{sex}.trunk_frequencies_hz", model.modes.frequencies[:8], rel=2e-4)
