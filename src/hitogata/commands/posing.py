"""Pose a body from the command line's words: build it, apply the request, report clamping.

Shared by `hitogata pose` and `hitogata skeleton`.
"""

from __future__ import annotations

import argparse
import sys
import warnings

from hitogata.commands.body_file import body_of
from hitogata.commands.pose_args import PoseRequest, pose_request
from hitogata.muscles.activation import MuscleLimitWarning
from hitogata.posing.pose import PosedBody, Poser, poser_for


def pose_from_args(args: argparse.Namespace) -> tuple[Poser, PoseRequest, PosedBody]:
    """The body, the checked request and the posed body; clamping notes go to stderr. The poser is the body's
    own (`poser_for`): an elastic pose of it then shares it, not making another."""
    poser = poser_for(body_of(args))
    request = pose_request(args, poser)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MuscleLimitWarning)
        posed = poser.pose(
            contractions=request.contractions,
            lengths=request.lengths,
            clinical=request.clinical,
            skinning=request.skinning,
            on_limit=request.on_limit,
        )
    for warning in caught:
        if issubclass(warning.category, MuscleLimitWarning):
            print(f"hitogata: note: {warning.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    return poser, request, posed
