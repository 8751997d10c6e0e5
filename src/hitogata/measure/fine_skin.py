"""The documented fine-skin names at their old path, `hitogata.measure.fine_skin`: each is
`hitogata.skin.fine_skin`'s, with a DeprecationWarning on import; write
`from hitogata.skin import body_fine_skin, body_fine_skinning` (docs/measurements.md)."""

from typing import TYPE_CHECKING

from hitogata.lazy import moved_names

if TYPE_CHECKING:
    from hitogata.skin.fine_skin import (
        LEVELS,
        FineSkin,
        FineSkinning,
        body_fine_skin,
        body_fine_skinning,
        fine_skinning,
        subdivide,
    )

__all__ = ["LEVELS", "FineSkin", "FineSkinning", "body_fine_skin", "body_fine_skinning", "fine_skinning", "subdivide"]
__getattr__, __dir__ = moved_names(globals(), "hitogata.skin.fine_skin", __all__)
