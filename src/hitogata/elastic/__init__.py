"""The body's elastic model: tissue-region finite elements and modal analysis (the paper's §2.3).

Typical use::

    from hitogata.body.model import default_body
    from hitogata.elastic import build_elastic_model

    model = build_elastic_model(default_body("female"))     # trunk, P2, 40 modes, shipped materials
    model.modes.frequencies                                 # Hz, ascending
    f = model.muscle_load("rectus_abdominis", -0.05)        # stretch the rectus abdominis by 5 %
    u_skin = model.skin_displacement(u)                     # (V, 3) from nodal displacements (3N,)

Modules: `materials` (the TOML presets, checked), `model` (the model:
`assemble_system` lifts the volume mesh, attaches bone and cut nodes to the
skeleton and assembles K and M; `build_elastic_model` adds modes, damping and
the skin map), `mapping` (FE nodes -> skin vertices), `refine` (uniform
refinement for convergence studies), `files` (frequencies CSV, VTU, pictures).
See docs/elastic.md.
"""

from hitogata.elastic.materials import Materials, default_materials_path, load_materials
from hitogata.elastic.model import (
    BONE_MODES,
    CUT_MODES,
    DEFAULT_DAMPING,
    DEFAULT_ELEMENT_SIZES,
    ELEMENTS,
    ElasticModel,
    ElasticSystem,
    assemble_system,
    build_elastic_model,
)

__all__ = [
    "BONE_MODES",
    "CUT_MODES",
    "DEFAULT_DAMPING",
    "DEFAULT_ELEMENT_SIZES",
    "ELEMENTS",
    "ElasticModel",
    "ElasticSystem",
    "Materials",
    "assemble_system",
    "build_elastic_model",
    "default_materials_path",
    "load_materials",
]
