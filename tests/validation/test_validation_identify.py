"""`hitogata.validation.identify` recovers the constants that generated its data, and its Ritz model is the
full model's at the reference."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.elastic.materials import load_materials
from hitogata.validation import answer_dataset, load_dataset
from hitogata.validation.identify import NAMES, constants_of, identify, materials_of, reduce_body

SIZE = 60.0  # mm: a coarse whole body keeps the test to a minute; the method does not depend on it
SOURCE = """
[[source]]
id = "model"
authors = "hitogata"
year = 2026
title = "The model's own answers at known constants"
journal = "this test"
method = "the elastic whole body at 60 mm"
n = 1
subjects = { sex = "female" }
"""
# regions the 60 mm lattice models on the default female (`elastic.resonance.MIN_COVERAGE`: not her upper arm)
ROWS = [("stiffness", "muscle.shear_modulus.thigh", "kPa"), ("stiffness", "fat.youngs_modulus.thigh", "kPa"),
        ("frequency", "thigh", "Hz"), ("frequency", "calf", "Hz"), ("frequency", "abdomen", "Hz"),
        ("frequency", "breast", "Hz"), ("damping", "thigh", "1"), ("damping", "calf", "1"),
        ("damping", "breast", "1")]


def truth() -> np.ndarray:
    theta = constants_of(load_materials())
    changes = {"skin.youngs_modulus": 1.6, "muscle.youngs_modulus": 0.7, "damping.alpha": 1.5, "damping.beta": 0.6}
    for name, factor in changes.items():
        theta[NAMES.index(name)] *= factor
    return theta


def rows_file(tmp_path, values: list[float] | None = None) -> str:
    text = SOURCE
    for k, (kind, quantity, unit) in enumerate(ROWS):
        mean = 1.0 if values is None else values[k]
        text += (f'\n[[row]]\nid = "r{k}"\nsource = "model"\nkind = "{kind}"\nwhere = "-"\nmean = {mean!r}\n'
                 f'sd = {0.01 * abs(mean)!r}\nunit = "{unit}"\nquantity = "{quantity}"\ndefinition = "-"\n')
    path = tmp_path / "rows.toml"
    path.write_text(text)
    return str(path)


@pytest.mark.slow
def test_identification_recovers_the_constants_that_made_its_data(tmp_path):
    base = load_materials()
    true = truth()
    made = answer_dataset(load_dataset(rows_file(tmp_path)), materials_of(true, base), element_size=SIZE)
    values = [a.answers["elastic"].value for a in made]
    assert all(v is not None and v > 0 for v in values)
    fit = identify(load_dataset(rows_file(tmp_path, values)), base, element_size=SIZE)
    pinned = {n for n, p in zip(NAMES, fit.pinned) if p}
    assert {"skin.youngs_modulus", "muscle.youngs_modulus", "damping.alpha", "damping.beta"} <= pinned
    for k, name in enumerate(NAMES):
        if name in ("skin.youngs_modulus", "muscle.youngs_modulus"):
            assert fit.constants[k] == pytest.approx(true[k], rel=0.02), name  # what the rows pin directly
        elif fit.pinned[k]:  # pinned together with others (alpha and beta by damping at 5-8 Hz, the viscera by
            # the abdomen's frequency alone): within its 95 % interval
            low, high = fit.interval[k]
            assert low <= true[k] <= high, (name, fit.constants[k], fit.interval[k])
        else:
            assert fit.constants[k] == true[k], name  # left at its start, which is the truth
    assert np.abs(fit.z).max() < 0.5  # the fit meets its own data within half an SD (1 % of each value)


@pytest.mark.slow
def test_the_ritz_model_is_the_full_model_at_its_reference(female):
    from hitogata.validation.answers import RESONANCE_MODES
    from hitogata.elastic.model import bone_segments, build_elastic_model
    from hitogata.elastic.resonance import region_nodes, resonance

    base = load_materials()
    theta = constants_of(base)
    reduced = reduce_body(female, base, theta, element_size=SIZE)
    model = build_elastic_model(female, extent="body", element_size=SIZE, n_modes=RESONANCE_MODES, materials=base,
                                volume=reduced.volume)
    heads, tails = bone_segments(model.volume, female.rig)
    for region in ("thigh", "calf", "abdomen"):
        nodes = region_nodes(model.points, model.volume.bone_names, heads, tails, region)
        full = resonance(model.M, model.modes.eigenvalues, model.modes.vectors, nodes, model.alpha, model.beta, region)
        assert reduced.resonance(theta, region) == pytest.approx((full.frequency, full.damping_ratio), rel=1e-6)
