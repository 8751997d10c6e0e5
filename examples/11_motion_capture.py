"""Motion capture in and out: a motion written as BVH, read back onto the 65-part skeleton.

    python examples/11_motion_capture.py [OUT_FOLDER]

A shipped scenario's skeleton motion is exported as BVH (the file a motion-capture tool, Blender
or another body model would read), then read and retargeted as any BVH is — CMU, Mixamo or this
library's own joint names, any up axis, rest pose, channel order and unit (docs/motion.md). The
joint angles that come back are compared with those that went out. With a file of your own:
`hitogata motion import walk.bvh --out walk.toml`, then `hitogata ease --motions walk.toml`.
"""

import sys
import tempfile
from pathlib import Path

import numpy as np

import hitogata as hg
from hitogata.motion.bvh import read_bvh, write_bvh  # the functions behind `hitogata motion`
from hitogata.motion.clip import scenario_clip
from hitogata.motion.joint_map import choose_joint_map
from hitogata.motion.retarget import export_bvh, retarget

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp(prefix="hitogata-11-"))
out.mkdir(parents=True, exist_ok=True)

body = hg.default_body("male")
skeleton = hg.poser_for(body).skeleton
scenario = hg.load_scenario(hg.shipped_scenarios()["mobility_reach_forward"])
clip = scenario_clip(scenario, hg.poser_for(body), rate=20)  # the skeleton's motion, 20 frames per second

path = out / "reach.bvh"
path.write_text(write_bvh(export_bvh(skeleton, clip, "mobility_reach_forward")), encoding="utf-8")
print(f"wrote {path}: {len(clip.times)} frames of {len(skeleton.names)} parts")

bvh = read_bvh(path)
joint_map = choose_joint_map(bvh.names, skeleton)  # the map whose joint names match the file best
back = retarget(bvh, skeleton, joint_map)
error = np.degrees(np.abs(back.clip.angles - clip.angles).max())
print(f"read back: {len(back.clip.times)} frames, {len(back.mapped)} joints mapped, "
      f"largest joint-angle difference {error:.1e}°")
