"""The string options of the library, each owned once, as a `Literal` alias and its tuple of values.

The modules that act on an option, the command line's `choices=` and the
scenario reader import them from here, so a list is never restated. No
imports beyond typing: the light configuration readers use these too.
"""

from __future__ import annotations

from typing import Literal, get_args

Extent = Literal["trunk", "body"]  # the elastic model's extent
Element = Literal["P2", "P1"]  # quadratic or linear tetrahedra
BoneMode = Literal["rigid", "elastic"]
CutMode = Literal["free", "attached"]
Dilatation = Literal["full", "mean"]
Skinning = Literal["lbs", "dqs"]
OnLimit = Literal["raise", "clamp"]  # beyond a muscle's reach or a joint's range
Interpolation = Literal["linear", "smoothstep"]

EXTENTS: tuple[Extent, ...] = get_args(Extent)
ELEMENTS: tuple[Element, ...] = get_args(Element)
BONE_MODES: tuple[BoneMode, ...] = get_args(BoneMode)
CUT_MODES: tuple[CutMode, ...] = get_args(CutMode)
DILATATIONS: tuple[Dilatation, ...] = get_args(Dilatation)
SKINNINGS: tuple[Skinning, ...] = get_args(Skinning)
ON_LIMIT: tuple[OnLimit, ...] = get_args(OnLimit)
INTERPOLATIONS: tuple[Interpolation, ...] = get_args(Interpolation)
