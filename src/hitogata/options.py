"""Every string option hitogata accepts, owned once: a `Literal` alias for type checkers and its values.

A module that takes an option annotates the parameter with the alias and
checks a run-time value against the tuple (`EXTENTS`, ...), so the help
texts, the scenario reader and the error messages all list the same words.
Imported by the computation modules, so it imports nothing.
"""

from __future__ import annotations

from typing import Literal, get_args

# the body
Sex = Literal["female", "male"]
Race = Literal["african", "asian", "caucasian"]
# posing: what to do with a muscle or angle beyond its range; skinning method
OnLimit = Literal["raise", "clamp"]
Limits = Literal["ignore", "clamp", "raise"]  # forward kinematics also accepts angles as given
Skinning = Literal["lbs", "dqs"]
# the surface the apparel answers measure: skinned, or the elastic whole body held at each frame
SurfaceSource = Literal["skinned", "elastic"]
DriveMode = Literal["contraction", "length"]
# skeleton and muscle specs
Axis = Literal["x", "-x", "y", "-y", "z", "-z", "X", "-X", "Y", "-Y", "Z", "-Z", "long", "-long", "hinge", "-hinge"]
Frame = Literal["bone", "world"]
End = Literal["head", "tail"]
MuscleKind = Literal["flexion", "rotation"]
Distribution = Literal["range", "same"]
# the volume and elastic models
Extent = Literal["trunk", "body"]
# How the bones enter the mesh: "conforming" meshes the soft tissue around the bone capsules
# (their surface nodes are held, no bone tets); "labelled" meshes the whole body and labels the
# lattice tets inside the capsules as bone (for elastic bone).
BoneMesh = Literal["conforming", "labelled"]
Element = Literal["P2", "P1"]
BoneMode = Literal["rigid", "elastic"]
CutMode = Literal["free", "attached"]
Dilatation = Literal["full", "mean"]
# the shipped tissue materials: the literature's values, or those identified from measured people; the default
# (docs/decisions/0047-the-identified-materials-wait-for-the-skin.md)
MaterialsPreset = Literal["literature", "calibrated"]
DEFAULT_MATERIALS: MaterialsPreset = "literature"
EigenSolver = Literal["auto", "dense", "scipy", "superlu-nd", "pardiso"]
FactorMethod = Literal["auto", "superlu-nd", "pardiso", "superlu"]
# scenarios and their files
Interpolation = Literal["linear", "smoothstep"]
ChannelKind = Literal["contraction", "angle", "clinical"]
OutputFile = Literal["glb", "pvd", "png", "gif"]
ViewName = Literal["front", "side", "back", "right", "top"]
MuscleLines = Literal["none", "given", "all"]

SEXES: tuple[Sex, ...] = get_args(Sex)
RACES: tuple[Race, ...] = get_args(Race)
ON_LIMIT: tuple[OnLimit, ...] = get_args(OnLimit)
LIMIT_MODES: tuple[Limits, ...] = get_args(Limits)
SKINNING: tuple[Skinning, ...] = get_args(Skinning)
SURFACE_SOURCES: tuple[SurfaceSource, ...] = get_args(SurfaceSource)
DRIVE_MODES: tuple[DriveMode, ...] = get_args(DriveMode)
AXES: tuple[Axis, ...] = get_args(Axis)
FRAMES: tuple[Frame, ...] = get_args(Frame)
ENDS: tuple[End, ...] = get_args(End)
MUSCLE_KINDS: tuple[MuscleKind, ...] = get_args(MuscleKind)
DISTRIBUTIONS: tuple[Distribution, ...] = get_args(Distribution)
EXTENTS: tuple[Extent, ...] = get_args(Extent)
BONE_MESHES: tuple[BoneMesh, ...] = get_args(BoneMesh)
ELEMENTS: tuple[Element, ...] = get_args(Element)
BONE_MODES: tuple[BoneMode, ...] = get_args(BoneMode)
CUT_MODES: tuple[CutMode, ...] = get_args(CutMode)
DILATATIONS: tuple[Dilatation, ...] = get_args(Dilatation)
MATERIALS_PRESETS: tuple[MaterialsPreset, ...] = get_args(MaterialsPreset)
EIGEN_SOLVERS: tuple[EigenSolver, ...] = get_args(EigenSolver)
FACTOR_METHODS: tuple[FactorMethod, ...] = get_args(FactorMethod)
INTERPOLATIONS: tuple[Interpolation, ...] = get_args(Interpolation)
CHANNEL_KINDS: tuple[ChannelKind, ...] = get_args(ChannelKind)
OUTPUT_FILES: tuple[OutputFile, ...] = get_args(OutputFile)
VIEW_NAMES: tuple[ViewName, ...] = get_args(ViewName)
MUSCLE_LINES: tuple[MuscleLines, ...] = get_args(MuscleLines)
