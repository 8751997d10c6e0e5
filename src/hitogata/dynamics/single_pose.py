"""The documented elastic-pose names at their old path, `hitogata.dynamics.single_pose`: each is
`hitogata.skin.single_pose`'s, with a DeprecationWarning on import; write
`from hitogata.skin import elastic_dynamics, elastic_pose` (docs/howto/elastic-pose-with-contact.md)."""

from typing import TYPE_CHECKING

from hitogata.lazy import moved_names

if TYPE_CHECKING:
    from hitogata.skin.single_pose import ELEMENT_SIZE, ElasticPose, elastic_dynamics, elastic_pose, held_dynamics

__all__ = ["ELEMENT_SIZE", "ElasticPose", "elastic_dynamics", "elastic_pose", "held_dynamics"]
__getattr__, __dir__ = moved_names(globals(), "hitogata.skin.single_pose", __all__)
