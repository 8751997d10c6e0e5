"""Heat-map pictures of skin strain on the posed body, from the front and the back."""

from __future__ import annotations

import numpy as np

from hitogata.measure.strain import SkinStrain
from hitogata.report.surface import Colouring, render_png

MIN_RANGE = 5.0  # %: the colour scale spans at least ± this, so a tiny strain does not look alarming
STRAINED = 0.5  # %: faces strained more than this set the colour scale's reach


def strain_heatmap(vertices: np.ndarray, faces: np.ndarray, strain: SkinStrain, title: str = "") -> bytes:
    """PNG of the largest principal strain (%) on the deformed surface, front and back.

    Stretch is red, compression (λ1 < 1: the skin shortens in every direction)
    blue; the scale is symmetric about zero and reaches the 95th percentile of
    the strained faces, so a few extreme triangles do not wash out the rest.
    """
    from matplotlib.colors import TwoSlopeNorm  # here: a picture at rest has no colour scale

    values = strain.strain_max_percent
    strained = np.abs(values[np.isfinite(values)])
    strained = strained[strained > STRAINED]
    reach = max(MIN_RANGE, float(np.percentile(strained, 95.0))) if len(strained) else MIN_RANGE
    finite = np.abs(values[np.isfinite(values)])
    beyond = 100.0 * float(np.mean(finite > reach)) if len(finite) else 0.0
    colouring = Colouring(
        values=np.nan_to_num(values),
        cmap="RdBu_r",
        norm=TwoSlopeNorm(vcenter=0.0, vmin=-reach, vmax=reach),
        label=f"largest principal strain (%); colours saturate beyond ±{reach:.0f} % ({beyond:.1f} % of faces)",
    )
    return render_png(vertices, faces, ("front", "back"), colouring, title=title)
