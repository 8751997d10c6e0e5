"""The skin's contact settings (`skin.settings`): the defaults are the ones the decision documents, a bad value
is refused in one line, and a changed setting reaches the code that reads it (small synthetic cases)."""

from __future__ import annotations

import dataclasses
import math
import pickle
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from hitogata.errors import HitogataError
from hitogata.geometry.barrier_contact import BarrierSettings, barrier_resolve
from hitogata.geometry.contact import SelfContact
from hitogata.geometry.offset_limit import OffsetLimiter, OffsetLimitSettings
from hitogata.geometry.strain import principal_stretches
from hitogata.skin.contact import crease_tether
from hitogata.skin.settings import SKIN_DEFAULTS, CreaseSettings, SkinSettings, SlideSettings
from hitogata.skin.skin_slide import SlideResult, slide_fine_skin
from samples import two_spheres

DECISION = Path(__file__).resolve().parents[2] / "docs" / "decisions" / "0046-skin-settings.md"


def _leaves(settings: object, prefix: str = "") -> dict[str, object]:
    """Every field of a settings tree by its dotted path, nested dataclasses opened."""
    out: dict[str, object] = {}
    for f in dataclasses.fields(settings):  # type: ignore[arg-type]
        value = getattr(settings, f.name)
        if dataclasses.is_dataclass(value):
            out.update(_leaves(value, f"{prefix}{f.name}."))
        else:
            out[f"{prefix}{f.name}"] = value
    return out


def _documented() -> dict[str, object]:
    """The decision's table of defaults: field path -> value (a Python literal, or radians(...))."""
    table = DECISION.read_text(encoding="utf-8").split("### The defaults")[1].split("\n### ")[0]
    rows = re.findall(r"^\| `([a-z_.]+)` \| `([^`]+)` \|", table, flags=re.M)
    return {name: eval(text, {"__builtins__": {}}, {"radians": math.radians}) for name, text in rows}


def test_the_defaults_are_the_ones_the_decision_documents():
    documented, code = _documented(), _leaves(SKIN_DEFAULTS)
    assert sorted(documented) == sorted(code)  # every field has its row, and no row names a field that is not
    for name, value in code.items():
        assert value == documented[name] and type(value) is type(documented[name]), name
    # the values derived from the barrier's reach, as its reasons say
    assert SKIN_DEFAULTS.barrier.apart == 4e-3 and SKIN_DEFAULTS.barrier.ccd_gap == pytest.approx(1e-5, rel=1e-15)
    assert SkinSettings() == SKIN_DEFAULTS and hash(SkinSettings()) == hash(SKIN_DEFAULTS)
    assert pickle.loads(pickle.dumps(SKIN_DEFAULTS)) == SKIN_DEFAULTS  # as `HeldFrames` hands them to its workers


@pytest.mark.parametrize(("make", "message"), [
    (lambda: BarrierSettings(dhat=-1e-3), "BarrierSettings.dhat = -0.001: allowed a number above 0"),
    (lambda: BarrierSettings(iterations=0), "BarrierSettings.iterations = 0: allowed a whole number at least 1"),
    (lambda: BarrierSettings(min_step=0.2), "BarrierSettings.min_step = 0.2: allowed at most max_step (0.1 m)"),
    (lambda: OffsetLimitSettings(width=float("nan")), "OffsetLimitSettings.width = nan: allowed a distance (m) above 0"),
    (lambda: SlideSettings(iterations=0), "SlideSettings.iterations = 0: allowed a whole number at least 1"),
    (lambda: SlideSettings(reach=-0.15), "SlideSettings.reach = -0.15: allowed a distance (m) above 0"),
    (lambda: CreaseSettings(stretch=(0.4, 0.7)), "CreaseSettings.stretch = (0.4, 0.7): allowed two stretches s0 > s1 > 0"),
    (lambda: CreaseSettings(share=1.5), "CreaseSettings.share = 1.5: allowed a share from 0 to 1"),
    (lambda: replace(SKIN_DEFAULTS, approach_steps=2.5), "SkinSettings.approach_steps = 2.5: allowed a whole number"),
    (lambda: replace(SKIN_DEFAULTS, barrier=None), "SkinSettings.barrier = None: allowed a BarrierSettings"),
])
def test_a_bad_value_is_refused_in_one_line_naming_the_field(make, message):
    with pytest.raises(HitogataError) as caught:
        make()
    text = str(caught.value)
    assert text.startswith(message) and "\n" not in text


def _stretched_sheet() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A flat 12 × 12 sheet of 1 cm squares (rest, faces) and its posture with one column of squares
    stretched 4 times across (beyond the slide's +95 %), the rest of the sheet moved aside unstretched."""
    n = 12
    x, y = np.meshgrid(np.arange(n) * 0.01, np.arange(n) * 0.01, indexing="ij")
    rest = np.stack([x.ravel(), y.ravel(), np.zeros(n * n)], axis=1)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    faces = np.concatenate([np.stack([a, a + n, a + n + 1], axis=1), np.stack([a, a + n + 1, a + 1], axis=1)])
    posed = rest.copy()
    posed[rest[:, 0] > 0.055, 0] += 0.03  # the columns beyond x = 5 cm 3 cm aside: the column 5-6 cm 4x as wide
    return rest, faces, posed


def test_the_slides_threshold_and_steps_reach_the_slide():
    rest, faces, posed = _stretched_sheet()

    def slid(**changes: object) -> tuple[SlideResult, float]:
        """The sheet slid with the slide's settings changed, and its largest principal stretch after."""
        out = slide_fine_skin(rest, posed, faces, replace(SKIN_DEFAULTS, slide=replace(SKIN_DEFAULTS.slide, **changes)))
        return out, float(principal_stretches(rest, out.vertices, faces)[0].max())

    full, stretch = slid()  # the band's stretch spread over the sheet, drawn back to the limit (1.6)
    assert full.iterations > 1 and stretch == pytest.approx(SKIN_DEFAULTS.slide.limit, abs=0.05)
    later, stretch = slid(done=4.1)  # a threshold above the band's 4: nothing is beyond it, nothing slides
    assert not later.free.any() and later.moved.max() == 0.0 and later.iterations == 0 and stretch == pytest.approx(4)
    once, stretch = slid(iterations=1)  # one local/global step: one longest move, the band still beyond done
    assert once.iterations == 1 and once.moved.max() == pytest.approx(SKIN_DEFAULTS.slide.max_move)
    assert stretch > SKIN_DEFAULTS.slide.done


def test_the_creases_share_reaches_the_tether():
    rest, faces, _ = _stretched_sheet()
    squeezed = rest * [0.3, 1.0, 1.0]  # every triangle's smallest stretch 0.3: folded (below 0.4)
    folded, free = np.full(len(rest), np.radians(90.0)), np.ones(len(rest), dtype=bool)  # a joint folded past 60°
    assert crease_tether(rest, squeezed, faces, folded, free) == pytest.approx(np.full(len(rest), 0.5))
    quarter = crease_tether(rest, squeezed, faces, folded, free, replace(SKIN_DEFAULTS.creases, share=0.25))
    assert quarter == pytest.approx(np.full(len(rest), 0.25))


def test_the_offset_limits_width_reaches_the_spread():
    rest, faces, _ = _stretched_sheet()
    limiter = OffsetLimiter(rest, faces)
    assert limiter.with_settings(OffsetLimitSettings()) is limiter  # the defaults: the limiter itself
    narrow = limiter.with_settings(OffsetLimitSettings(width=0.02))
    assert narrow.graph is limiter.graph  # the surface's preparation shared
    hold = np.zeros(len(rest))
    hold[0] = 1.0  # a corner held whole: the hold fades over the width along the edges
    reached = (limiter.spread(hold) > 0).sum(), (narrow.spread(hold) > 0).sum()
    assert reached[1] < reached[0] and narrow.spread(hold)[0] == 1.0


def test_the_barriers_reach_reaches_the_barrier():
    apart, faces, groups = two_spheres(0.05, 2)
    test = SelfContact(apart(0.2), faces, groups)
    path = [apart(d) for d in (0.2, 0.15, 0.12, 0.1, 0.09)]  # the target: 10 mm of overlap
    wide = barrier_resolve(path, test)
    narrow = barrier_resolve(path, test, BarrierSettings(dhat=1e-3))
    # skin in contact ends within the barrier's reach, nearer with the narrower one
    assert 0.0 < narrow.min_distance < 1e-3 < wide.min_distance < 2e-3
