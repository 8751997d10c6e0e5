"""A body's elastic dynamics read from the disk cache, else built and stored there (`hitogata.elastic.cache`).

An entry holds the elastic model (mesh, K and M, modes, the skin's map) and what
`BodyDynamics.build` makes from it at length: the FE nodes' part weights, the
skin bound to the nodes, the muscles' unit loads, and the skin's crossings at
rest (its offset limiter's whole test of the skin). The rest (the quasi-statics'
factor, the mass-weighted modes, the skin's fade) is made again from those arrays
in a fraction of a second: a factor is not an array to store. The model's K and M
(four fifths of the entry) are read when first used: a held posture never does.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from hitogata.body.model import Body
from hitogata.dynamics.motion import BodyDynamics
from hitogata.dynamics.rigging import NodeRig
from hitogata.disk_cache import cached
from hitogata.elastic.cache import model_key, model_options
from hitogata.elastic.model import build_elastic_model
from hitogata.elastic.stored import from_arrays, to_arrays
from hitogata.options import Skinning
from hitogata.posing.pose import poser_for
from hitogata.posing.skinning import prepare_skin

DYNAMICS = "dynamics"  # the entry kind
MODEL, PARTS = "model.", "parts."  # the entry's two values' array name prefixes
MATRICES = (MODEL + ".K.", MODEL + ".M.")  # the arrays of the model's K and M, read when first used


def cached_dynamics(body: Body, skinning: Skinning = "dqs", cache: bool | None = None, **options: Any) -> BodyDynamics:
    """`BodyDynamics.build(body, build_elastic_model(body, **options), skinning)`, read from the disk cache
    when this body's was built before with the same options, materials and code (`cache`: see
    `disk_cache.enabled`)."""
    chosen = model_options(**options)

    def build() -> BodyDynamics:
        return BodyDynamics.build(body, build_elastic_model(body, **chosen), skinning)

    if chosen["volume"] is not None:
        return build()
    key = {**model_key(body, chosen), "skinning": skinning}
    return cached(DYNAMICS, key, build, _encode, lambda arrays: _decode(body, skinning, arrays), cache,
                  deferred=lambda name: name.startswith(MATRICES))


def _encode(dynamics: BodyDynamics) -> dict[str, np.ndarray]:
    parts = {"weights": dynamics.rig.weights, "skin_map": dynamics.rig.skin_map, "loads": dynamics.unit_loads,
             "skin_crossings": dynamics.skin_limiter.crossing_at_rest}
    return {**to_arrays(dynamics.model, MODEL), **to_arrays(parts, PARTS)}


def _decode(body: Body, skinning: Skinning, arrays: Mapping[str, np.ndarray]) -> BodyDynamics:
    model, parts = from_arrays(arrays, MODEL), from_arrays(arrays, PARTS)
    poser = poser_for(body)
    rig = NodeRig(prepare_skin(model.points, parts["weights"], poser.skeleton.parents), skinning, parts["skin_map"])
    return BodyDynamics.build(body, model, skinning, poser, rig=rig, unit_loads=parts["loads"],
                              skin_crossings=parts["skin_crossings"])
