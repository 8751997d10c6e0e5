"""Held frames on worker processes: the same skins as held one by one in this process."""

import numpy as np
import pytest

from hitogata.skin import held_frames
from hitogata.skin.held_frames import HeldFrames


@pytest.mark.slow
def test_frames_held_on_two_workers_are_the_frames_held_here(female, monkeypatch):
    monkeypatch.setattr(held_frames, "MIN_FRAMES", 2)  # two frames are enough to go to the workers here
    hold = HeldFrames(female, contact=False, workers=2)
    skeleton = hold.dynamics.poser.skeleton
    angles = np.zeros((2, skeleton.n_dofs))
    angles[0, skeleton.dof_names.index("forearm_l.flexion")] = np.radians(90)
    angles[1, skeleton.dof_names.index("shank_r.flexion")] = np.radians(60)
    try:
        apart = hold(angles)
    finally:
        hold.close()
    here = HeldFrames(female, contact=False, workers=1)(angles)
    assert len(apart) == 2
    for a, b in zip(apart, here):
        assert np.abs(a - b).max() < 1e-9
    assert np.abs(here[0] - here[1]).max() > 0.01  # two postures, not one twice
