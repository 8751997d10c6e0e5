"""The body core: a human body at rest from MakeHuman's shape parameters or real units, its rig and
skinning weights, and the data they are made from. It imports nothing above itself: posing, the
elastic model, measurement and garments take a `Body` and keep what they prepare from it
(`Body.prepared`).

- `model`: `Body`, built from parameters or from stature and mass, and the default bodies;
- `shape`: MakeHuman's shape parameters and the blending of its targets;
- `rig`: the default rig placed on a body;
- `assets`: the base mesh, targets and skinning weights read from the package data;
- `growth`: children's growth references (WHO, CDC) for the default child and its checks;
- `rest_contact`: a heavy body's skin touching itself at rest.

The names below are imported on first use (`hitogata.lazy`), so importing one module of the body
does not build or load the others.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.body.model import Body, default_body, default_measurements, mass_range, sex_value

__all__ = ["Body", "default_body", "default_measurements", "mass_range", "sex_value"]
__getattr__, __dir__ = lazy_names(globals(), {
    "Body": "hitogata.body.model",
    "default_body": "hitogata.body.model",
    "default_measurements": "hitogata.body.model",
    "mass_range": "hitogata.body.model",
    "sex_value": "hitogata.body.model",
})
