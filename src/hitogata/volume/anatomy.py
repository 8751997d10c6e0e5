"""Anatomical constants of the layered tissue model, with their sources.

The body asset has a skin and a skeleton but no inside, so the inside is
built from layers and capsules whose sizes come from the literature below.
All lengths in metres.
"""

from __future__ import annotations

import numpy as np

# Tissue regions, in the order of their ids. The paper's four trunk regions are
# spine, viscera, muscle and skin; "bone" is its spine grown to every bone the
# model includes (pelvis, shoulder girdle, and the limbs in the whole body).
REGIONS = ("bone", "viscera", "muscle", "skin")
BONE, VISCERA, MUSCLE, SKIN = range(4)

# Named muscle regions: the same names as the muscle list, so one muscle can both
# move a joint and load the tissue. +X is the body's left, hence "_l" for x > 0.
MUSCLES = (
    "rectus_abdominis",
    "external_oblique_l", "external_oblique_r",
    "erector_spinae_l", "erector_spinae_r",
    "pectoralis_major_l", "pectoralis_major_r",
    "gluteus_maximus_l", "gluteus_maximus_r",
)

# Epidermis + dermis on the trunk: 1.5–2.5 mm by ultrasound at the standard
# trunk sites (Störchle 2019, PhD thesis, Medical University of Graz).
DERMIS = 0.002


def subcutaneous_fat(bmi: float, sex: float) -> float:
    """Trunk subcutaneous fat thickness (m) for a BMI (kg/m²) and sex (0 female … 1 male).

    Standardized ultrasound (Störchle et al. 2017, Ultrasound Med Biol 43:427)
    found 8-site sums of 12–245 mm over BMI 18.6–40.3: a site mean rising by
    about 1.3 mm per BMI unit, with the trunk sites (upper and lower abdomen,
    erector spinae) about 1.5× the mean, hence 2 mm per BMI unit here. At equal
    BMI women carry more (8-site sums three times higher in female than in male
    athletes: Müller et al. 2020, Sports Med 50:597), hence 16 mm (women) and
    10 mm (men) at BMI 22. Clipped to 3–60 mm, the range of those studies.
    """
    at_22 = 0.016 - 0.006 * sex
    return float(np.clip(at_22 + 0.002 * (bmi - 22.0), 0.003, 0.060))


def skin_thickness(bmi: float, sex: float) -> float:
    """Thickness (m) of the 'skin' region: dermis plus subcutaneous fat."""
    return DERMIS + subcutaneous_fat(bmi, sex)


# Muscle wall between the skin+fat layer and the viscera. The abdominal wall
# is about 20 mm of muscle: rectus abdominis ~10 mm at the front, external +
# internal oblique + transversus ~6 + 8 + 4 mm at the side (ultrasound in
# healthy adults: Rankin, Stokes & Newham 2006, Muscle Nerve 34:320); the chest
# wall (pectoralis, intercostals and ribs) is of the same order.
WALL = 0.020

# Bone capsule radii per rig bone (name prefix → m): half the bone's width.
# Vertebral bodies 40–50 mm wide in the lumbar spine, ~30–35 mm in the thoracic
# (Zhou et al. 2000, Eur Spine J 9:242; Panjabi et al. 1991, Spine 16:888);
# cervical ~17 mm. Pelvis: the ilium and pubis reduced to bars from the sacrum
# to each acetabulum, 40 mm thick. Shaft diameters: clavicle ~13 mm, humerus
# ~21 mm, radius + ulna together ~20 mm, femur ~28 mm, tibia + fibula ~26 mm
# (e.g. Ruff 2002, Am J Phys Anthropol; standard anatomy texts); metacarpal
# shafts ~10 mm, phalanges of fingers and toes ~8 mm. The head is taken as
# rigid: skull and brain move as one at apparel time scales.
BONE_RADII = {
    "spine": 0.018,
    "neck": 0.010,
    "pelvis": 0.020,
    "clavicle": 0.007,
    "shoulder01": 0.012,
    "upperarm": 0.011,
    "lowerarm": 0.010,
    "wrist": 0.010,
    "upperleg": 0.014,
    "lowerleg": 0.013,
    "foot": 0.012,
    "metacarpal": 0.005,
    "finger": 0.004,
    "toe": 0.004,
    "head": 0.060,
}

# Rig bones boned in each model: the trunk (spine, pelvis, shoulder girdle) and
# the whole body (plus head, neck and limbs).
TRUNK_BONES = (
    "spine05", "spine04", "spine03", "spine02", "spine01", "neck01",
    "pelvis.L", "pelvis.R", "clavicle.L", "clavicle.R", "shoulder01.L", "shoulder01.R",
)
LIMB_BONES = tuple(
    f"{name}.{side}" for side in ("L", "R") for name in (
        "upperarm01", "upperarm02", "lowerarm01", "lowerarm02", "wrist",
        "upperleg01", "upperleg02", "lowerleg01", "lowerleg02", "foot",
    )
)
# The hands' and feet's small bones, which the skeleton moves too. Without them the whole
# body's lowest modes were the fingers and toes flapping on the wrist and foot capsules
# (male, 30 mm: 0.8-2.1 Hz); with them the lowest is the abdomen's (2.0 Hz).
HAND_AND_TOE_BONES = tuple(
    f"{name}.{side}" for side in ("L", "R") for name in (
        *(f"metacarpal{i}" for i in range(1, 5)),
        *(f"finger{i}-{j}" for i in range(1, 6) for j in range(1, 4)),
        "toe1-1", "toe1-2", *(f"toe{i}-{j}" for i in range(2, 6) for j in range(1, 4)),
    )
)
BODY_BONES = TRUNK_BONES + ("neck02", "neck03", "head") + LIMB_BONES + HAND_AND_TOE_BONES

# Bones whose skin belongs to an arm (for cutting the arms off the trunk).
ARM_PREFIXES = ("upperarm", "lowerarm", "wrist", "finger", "metacarpal")


# Smallest capsule radius: the tissue this close to a bone's axis moves with the bone (a bone
# plus its periosteum, tendons and the deep muscle fixed to it). A fixed length, so the model's
# geometry does not change with the element size, and one a coarse lattice still resolves.
BONE_MIN_RADIUS = 0.020


def capsule_radii(names: tuple[str, ...], element_size: float | None = None) -> np.ndarray:
    """Capsule radii (m) of rig bones: the anatomical radius, at least `BONE_MIN_RADIUS`, or with
    an element_size (m) at least half an element instead (the labelled lattice's bones)."""
    least = BONE_MIN_RADIUS if element_size is None else 0.5 * element_size
    return np.maximum([bone_radius(n) for n in names], least)


def bone_radius(name: str) -> float:
    """Capsule radius (m) of a rig bone."""
    for prefix, radius in BONE_RADII.items():
        if name.startswith(prefix):
            return radius
    raise KeyError(f"no capsule radius for bone {name!r}")


# Heights on the trunk as a fraction s of the span from the hip joints (s = 0)
# to the base of the neck (s = 1). From stature fractions (Drillis & Contini
# 1966, as in Winter 2009, Biomechanics and Motor Control, Fig. 4.1: hip 0.530 H,
# nipple 0.720 H, shoulder 0.818 H) and a neck base near 0.85 H: pubis ~0 (the
# pubic crest is level with the hip joints), iliac crest ~0.25, xiphoid and the
# 5th–6th ribs ~0.6, clavicle ~0.9.
LEVEL_ILIAC_CREST = 0.25
LEVEL_XIPHOID = 0.62
LEVEL_CLAVICLE = 0.92
LEVEL_LOW_BACK = 0.10  # erector spinae from the sacrum up; gluteus maximus below
LEVEL_GLUTEAL_FOLD = -0.18  # the fold under the buttock, ~9 cm below the hip joints
# Half-width of the rectus abdominis band (two recti + linea alba, each ~7 cm
# wide: Rankin et al. 2006) and of the erector spinae (6–8 cm beside the
# spinous processes), as a fraction of the distance between the hip joints.
RECTUS_HALF_WIDTH = 0.40
ERECTOR_HALF_WIDTH = 0.40
# How far from the midline the sternum reaches (pectoralis starts beside it), m.
STERNUM_HALF_WIDTH = 0.02
# The insertion of pectoralis major on the humerus (crest of the greater
# tubercle) lies ~6 cm below the humeral head centre; that of gluteus maximus
# (gluteal tuberosity, iliotibial tract) ~8 cm below and ~4 cm lateral of the
# hip joint centre.
PECTORALIS_INSERTION = 0.06
GLUTEUS_INSERTION_DOWN = 0.08
GLUTEUS_INSERTION_OUT = 0.04
