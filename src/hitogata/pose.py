"""The documented posing names at their old path, `hitogata.pose`: each is `hitogata.posing`'s, with a
DeprecationWarning on import; write `from hitogata.posing import poser_for` (docs/posing.md)."""

from typing import TYPE_CHECKING

from hitogata.lazy import moved_names

if TYPE_CHECKING:
    from hitogata.posing import PosedBody, Poser, pose_body, poser_for

__all__ = ["PosedBody", "Poser", "pose_body", "poser_for"]
__getattr__, __dir__ = moved_names(globals(), "hitogata.posing", __all__)
