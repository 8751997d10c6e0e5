"""The muscles (the paper's active organ): list, eq. 1 and eq. 2, contraction → joint angles."""

from hitogata.muscles.activation import (
    Drive,
    MuscleLimitWarning,
    angles_from_muscles,
    contractions_of,
    muscle_lengths,
)
from hitogata.muscles.equations import flexion_angle, flexion_length, rotation_angle, rotation_length
from hitogata.muscles.geometry import MuscleSet, place_muscles
from hitogata.muscles.spec import MuscleListSpec, load_muscle_spec

__all__ = [
    "Drive",
    "MuscleLimitWarning",
    "MuscleListSpec",
    "MuscleSet",
    "angles_from_muscles",
    "contractions_of",
    "flexion_angle",
    "flexion_length",
    "load_muscle_spec",
    "muscle_lengths",
    "place_muscles",
    "rotation_angle",
    "rotation_length",
]
