"""Fuzzing the user's edge: whatever a person types or writes in a file, the answer is a value or one HitogataError.

hypothesis generates unit strings (numbers with and without units, junk,
unicode) and scenario documents (nested tables, lists, strings, numbers of
every kind); any other exception is a bug that would reach the user as a
traceback.
"""

from __future__ import annotations

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hitogata import units
from hitogata.motion.scenario import CHANNELS, SECTIONS, parse_scenario
from hitogata.errors import HitogataError

TABLES = [units.LENGTH_UNITS, units.MASS_UNITS, units.ANGLE_UNITS, units.FRACTION_UNITS]
UNIT_WORDS = sorted({u for table in TABLES for u in table} | {"s", "ms", "Hz", "deg", "%", "e", "E", "-", "+", "."})

quantities = st.one_of(
    st.text(max_size=20),
    st.builds(lambda n, u, pad: f"{pad}{n}{u}{pad}", st.floats(allow_nan=True, allow_infinity=True),
              st.sampled_from(UNIT_WORDS), st.sampled_from(["", " ", "\t"])),
    st.builds(lambda a, b: f"{a}{b}", st.sampled_from(UNIT_WORDS), st.text(max_size=5)),
    st.integers(), st.floats(), st.booleans(), st.none(),
)


@settings(max_examples=400, deadline=None)
@given(text=quantities, table=st.sampled_from(TABLES))
def test_the_unit_parser_answers_a_finite_number_or_one_line(text, table):
    try:
        value = units.parse_quantity(text, table, "value")
    except HitogataError as err:
        assert "\n" not in str(err)
    else:
        assert math.isfinite(value)


leaves = st.one_of(st.text(max_size=12), st.integers(), st.floats(), st.booleans(), quantities)
documents = st.recursive(leaves, lambda inner: st.one_of(
    st.lists(inner, max_size=3), st.dictionaries(st.text(max_size=8), inner, max_size=3)), max_leaves=12)
keys = st.sampled_from(sorted(SECTIONS | {"time", "duration", "rate", "views", *CHANNELS, "stature", "mass"}))
keyframe = st.dictionaries(st.sampled_from(["time", "interpolation", *CHANNELS]), documents, max_size=4)
scenario_documents = st.fixed_dictionaries(
    {"keyframe": st.lists(keyframe, max_size=3)},
    optional={k: st.dictionaries(keys, documents, max_size=4) for k in ("body", "model", "time", "timeline", "output")},
)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(document=st.one_of(scenario_documents, st.dictionaries(keys, documents, max_size=5)))
def test_the_scenario_reader_answers_a_scenario_or_one_line(document):
    try:
        parse_scenario(document, "fuzz.toml")
    except HitogataError as err:
        assert "\n" not in str(err) and str(err).startswith("fuzz.toml")
