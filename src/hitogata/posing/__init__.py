"""Posing: a body posed by its muscles or joint angles, beside the skeleton and muscles it drives.

- `pose`: `Poser` (a body's skeleton and muscles placed once, then posed), `PosedBody`, `pose_body`
  and `poser_for` (the poser kept with a body);
- `skinning`: the skin carried by the posed skeleton (linear blend, dual quaternions);
- `names`: muscle and joint names as a person writes them, resolved to the lists' names;
- `body_split`: each skin vertex's owning part (`vertex_parts`) and every split of the body the
  library uses, as named sets of parts (`SPLITS`).

The names below are imported on first use (`hitogata.lazy`).
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.posing.body_split import SPLITS, vertex_parts
    from hitogata.posing.pose import PosedBody, Poser, pose_body, poser_for

__all__ = ["SPLITS", "PosedBody", "Poser", "pose_body", "poser_for", "vertex_parts"]
__getattr__, __dir__ = lazy_names(globals(), {
    "SPLITS": "hitogata.posing.body_split",
    "vertex_parts": "hitogata.posing.body_split",
    "PosedBody": "hitogata.posing.pose",
    "Poser": "hitogata.posing.pose",
    "pose_body": "hitogata.posing.pose",
    "poser_for": "hitogata.posing.pose",
})
