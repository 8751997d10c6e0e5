"""The measurements' names and values, apart from how they are taken (`measurements`), so that a
command line can list and check them without loading the measuring (and its libraries)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import asdict, dataclass, fields

from hitogata.errors import HitogataError


@dataclass(frozen=True)
class Measurements:
    """ISO 8559-1 measurements of one body in one posture, metres (NaN: not measurable there)."""

    stature: float
    neck_girth: float
    chest_girth: float  # bust girth for women
    underbust_girth: float
    waist_girth: float  # at ISO 8559-1's waist level
    omphalion_waist_girth: float  # at the navel
    iliac_crest_waist_girth: float  # at the iliac crest (NHANES's waist)
    hip_girth: float
    thigh_girth: float
    upper_arm_girth: float
    armscye_girth: float
    knee_girth: float
    calf_girth: float
    ankle_girth: float
    wrist_girth: float
    back_waist_length: float
    across_back_width: float
    across_front_width: float
    shoulder_width: float
    shoulder_length: float
    arm_length: float
    waist_to_hip_length: float
    crotch_length: float
    front_rise: float  # the crotch length's front part: centre front waist to the crotch
    back_rise: float  # its back part: the crotch to the centre back waist
    iliocristale_height: float  # the iliac crest's height at the side
    inside_leg: float  # crotch height

    @staticmethod
    def names() -> tuple[str, ...]:
        """The measurements' names, in the table's order."""
        return tuple(f.name for f in fields(Measurements))

    def get(self, name: str) -> float:
        """One value by name; an unknown name is a one-line error listing the known ones."""
        check_names([name])
        return float(getattr(self, name))

    def as_dict(self) -> dict[str, float]:
        """Every measurement by name, metres (stature and lengths too)."""
        return {k: float(v) for k, v in asdict(self).items()}


MEASUREMENT_NAMES = Measurements.names()

GIRTHS = ("neck_girth", "chest_girth", "underbust_girth", "waist_girth", "omphalion_waist_girth",
          "iliac_crest_waist_girth", "hip_girth", "thigh_girth", "upper_arm_girth", "armscye_girth", "knee_girth",
          "calf_girth", "ankle_girth", "wrist_girth")

# Vertical distances above the lowest skin point (the floor): in a posture, heights in that posture
HEIGHTS = ("stature", "iliocristale_height", "inside_leg")


# Why a measurement is undefined (NaN) in a posture, where its definition says so; any other NaN is a tape that
# found nothing of its part in its plane (`NOT_CUT`).
KNEE_ALONG_LIMBS = ("the knee girth's plane (the bisector of femur and tibia) runs along the thigh and the calf in "
                    "deep knee flexion, so a tape in it goes round them, not round the knee")
UNDEFINED_BECAUSE = {"knee_girth": KNEE_ALONG_LIMBS}
NOT_CUT = "its plane cuts nothing of the part it goes round in this posture"


def undefined_because(name: str) -> str:
    """Why the measurement `name` is undefined where it is (NaN): its definition's reason, or `NOT_CUT`."""
    return UNDEFINED_BECAUSE.get(name, NOT_CUT)


def check_names(names: Iterable[str]) -> None:
    """Raise a one-line error for any name that is not a measurement."""
    unknown = [n for n in names if n not in MEASUREMENT_NAMES]
    if unknown:
        raise HitogataError(f"measurement {unknown[0]!r}: allowed {', '.join(MEASUREMENT_NAMES)}")


def aliases() -> dict[str, str]:
    """Every name a measurement may be asked by → its name in `measure`: the name itself and, for
    a girth, the name without `_girth` (chest → chest_girth)."""
    out = {name: name for name in MEASUREMENT_NAMES}
    out.update({name.removesuffix("_girth"): name for name in MEASUREMENT_NAMES if name.endswith("_girth")})
    return out
