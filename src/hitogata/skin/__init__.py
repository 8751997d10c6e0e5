"""The body's skin above the dynamics: where it meets itself, creases, slides over the fascia, and the fine
skin it is measured on, for a held posture and through a motion.

- `contact`: the skin's contact groups (parts held in shape by their bones, parted at every joint where a
  crease forms), the self-contact test of a poser's skin (`skin_contact`), the path of skinned postures the
  barrier follows (`approach`), the crease tether and the hold-back of crossings;
- `creases`: the elastic skin's self-contact with its creases folded, one solve for a held pose and for a
  motion's frame;
- `single_pose`: the elastic skin of one held posture (`elastic_pose`, behind `hitogata pose --elastic`)
  and the whole-body elastic model it needs, built once per body (`elastic_dynamics`, `held_dynamics`);
- `motion_contact`: self-contact through a motion, frame to frame (`resolve_frames`), and `simulate`, the
  dynamics' motion with it handed in (the front door's `hitogata.simulate`);
- `held_frames`: held postures of one body on the free cores (`HeldFrames`, for a garment's ease);
- `skin_slide`: the skin sliding over the fascia where its fine skin is stretched beyond what skin takes;
- `fine_skin`: the skin Loop-subdivided, carried like the skin itself, to measure strain on;
- `settings`: every tuning constant of the above in one frozen dataclass (`SkinSettings`, the defaults
  `SKIN_DEFAULTS`), with its unit and reason; the entry points take `settings=`.

The mesh algorithms they use know nothing of a body and stay in `hitogata.geometry`, below the body that
uses them too: the penetration test (`geometry.contact.SelfContact`), the IPC barrier
(`geometry.barrier_contact`) and the offset limiter (`geometry.offset_limit`); a heavy body's rest skin
touching itself is the body's own (`hitogata.body.rest_contact`). The names below are imported on first use
(`hitogata.lazy`): importing the package loads none of the dynamics.
"""

from typing import TYPE_CHECKING

from hitogata.lazy import lazy_names

if TYPE_CHECKING:
    from hitogata.skin.contact import skin_contact
    from hitogata.skin.fine_skin import FineSkin, FineSkinning, body_fine_skin, body_fine_skinning
    from hitogata.skin.held_frames import HeldFrames
    from hitogata.skin.motion_contact import resolve_frames, simulate
    from hitogata.skin.settings import SKIN_DEFAULTS, CreaseSettings, SkinSettings, SlideLevel, SlideSettings
    from hitogata.skin.single_pose import ElasticPose, elastic_dynamics, elastic_pose, held_dynamics
    from hitogata.skin.skin_slide import SkinSlide, slide_posed_skin

__all__ = [
    "SKIN_DEFAULTS",
    "CreaseSettings",
    "ElasticPose",
    "FineSkin",
    "FineSkinning",
    "HeldFrames",
    "SkinSettings",
    "SkinSlide",
    "SlideLevel",
    "SlideSettings",
    "body_fine_skin",
    "body_fine_skinning",
    "elastic_dynamics",
    "elastic_pose",
    "held_dynamics",
    "resolve_frames",
    "simulate",
    "skin_contact",
    "slide_posed_skin",
]
__getattr__, __dir__ = lazy_names(globals(), {
    "skin_contact": "hitogata.skin.contact",
    "FineSkin": "hitogata.skin.fine_skin",
    "FineSkinning": "hitogata.skin.fine_skin",
    "body_fine_skin": "hitogata.skin.fine_skin",
    "body_fine_skinning": "hitogata.skin.fine_skin",
    "HeldFrames": "hitogata.skin.held_frames",
    "resolve_frames": "hitogata.skin.motion_contact",
    "simulate": "hitogata.skin.motion_contact",
    "ElasticPose": "hitogata.skin.single_pose",
    "elastic_dynamics": "hitogata.skin.single_pose",
    "elastic_pose": "hitogata.skin.single_pose",
    "held_dynamics": "hitogata.skin.single_pose",
    "SkinSlide": "hitogata.skin.skin_slide",
    "SKIN_DEFAULTS": "hitogata.skin.settings",
    "CreaseSettings": "hitogata.skin.settings",
    "SkinSettings": "hitogata.skin.settings",
    "SlideLevel": "hitogata.skin.settings",
    "SlideSettings": "hitogata.skin.settings",
    "slide_posed_skin": "hitogata.skin.skin_slide",
})
