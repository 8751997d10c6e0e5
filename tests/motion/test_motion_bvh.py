"""BVH: round trip, a file in another tool's conventions (rest pose, channel order, units, up axis), errors."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from hitogata.cli import main
from hitogata.motion.scenario import parse_scenario
from hitogata.errors import HitogataError
from hitogata.motion.bvh import parse_bvh, read_bvh, write_bvh
from hitogata.motion.clip import scenario_clip
from hitogata.motion.joint_map import choose_joint_map
from hitogata.motion.retarget import export_bvh, retarget
from hitogata.posing import poser_for
from samples import SMALL_BVH as GOOD

LIMB_PARTS = ("upper_arm_l", "forearm_l", "hand_l", "upper_arm_r", "forearm_r", "thigh_l", "shank_l", "foot_l",
              "thigh_r", "shank_r", "foot_r")
SCENARIO = {
    "keyframe": [
        {"time": "0s"},
        {"time": "0.5s", "clinical": {"upper_arm_l.flexion": 100, "forearm_l.flexion": 120, "upper_arm_r.abduction": 95,
                                       "upper_arm_r.internal_rotation": 30, "forearm_r.pronation": 40,
                                       "hand_l.flexion": 30, "thigh_r.flexion": 70, "shank_r.flexion": 90,
                                       "thigh_l.abduction": 20, "foot_l.dorsiflexion": 15, "foot_r.inversion": 10}},
        {"time": "1s", "clinical": {"upper_arm_l.flexion": 40, "thigh_r.flexion": 20}},
    ],
    "time": {"duration": "1s", "rate": 20},
}
# (name, parent, parts it stands for: its rest position is the first part's joint, its motion the last part's)
CMU = [("Hips", None, ("pelvis",)), ("LHipJoint", "Hips", None), ("LeftUpLeg", "LHipJoint", ("thigh_l",)),
       ("LeftLeg", "LeftUpLeg", ("shank_l",)), ("LeftFoot", "LeftLeg", ("foot_l",)),
       ("LeftToeBase", "LeftFoot", ("toes_l",)), ("RHipJoint", "Hips", None),
       ("RightUpLeg", "RHipJoint", ("thigh_r",)), ("RightLeg", "RightUpLeg", ("shank_r",)),
       ("RightFoot", "RightLeg", ("foot_r",)), ("RightToeBase", "RightFoot", ("toes_r",)),
       ("LowerBack", "Hips", ("lumbar_5", "lumbar_1")), ("Spine", "LowerBack", ("thoracic_12", "thoracic_7")),
       ("Spine1", "Spine", ("thoracic_6", "thoracic_1")), ("Neck", "Spine1", ("cervical_7", "cervical_4")),
       ("Neck1", "Neck", ("cervical_3", "cervical_1")), ("Head", "Neck1", ("head",)),
       ("LeftShoulder", "Spine1", ("clavicle_l", "scapula_l")), ("LeftArm", "LeftShoulder", ("upper_arm_l",)),
       ("LeftForeArm", "LeftArm", ("forearm_l",)), ("LeftHand", "LeftForeArm", ("hand_l",)),
       ("RightShoulder", "Spine1", ("clavicle_r", "scapula_r")), ("RightArm", "RightShoulder", ("upper_arm_r",)),
       ("RightForeArm", "RightArm", ("forearm_r",)), ("RightHand", "RightForeArm", ("hand_r",))]
MIXAMO = [(f"mixamorig:{name}", parent and f"mixamorig:{parent}", parts) for name, parent, parts in [
    ("Hips", None, ("pelvis",)), ("LeftUpLeg", "Hips", ("thigh_l",)), ("LeftLeg", "LeftUpLeg", ("shank_l",)),
    ("LeftFoot", "LeftLeg", ("foot_l",)), ("LeftToeBase", "LeftFoot", ("toes_l",)),
    ("RightUpLeg", "Hips", ("thigh_r",)), ("RightLeg", "RightUpLeg", ("shank_r",)),
    ("RightFoot", "RightLeg", ("foot_r",)), ("RightToeBase", "RightFoot", ("toes_r",)),
    ("Spine", "Hips", ("lumbar_5", "lumbar_1")), ("Spine1", "Spine", ("thoracic_12", "thoracic_7")),
    ("Spine2", "Spine1", ("thoracic_6", "thoracic_1")), ("Neck", "Spine2", ("cervical_7", "cervical_1")),
    ("Head", "Neck", ("head",)), ("LeftShoulder", "Spine2", ("clavicle_l", "scapula_l")),
    ("LeftArm", "LeftShoulder", ("upper_arm_l",)), ("LeftForeArm", "LeftArm", ("forearm_l",)),
    ("LeftHand", "LeftForeArm", ("hand_l",)), ("RightShoulder", "Spine2", ("clavicle_r", "scapula_r")),
    ("RightArm", "RightShoulder", ("upper_arm_r",)), ("RightForeArm", "RightArm", ("forearm_r",)),
    ("RightHand", "RightForeArm", ("hand_r",))]]
LEAVES = {"LeftToeBase": "toes_l", "RightToeBase": "toes_r", "Head": "head", "LeftHand": "hand_l",
          "RightHand": "hand_r"}


@pytest.fixture(scope="module")
def scene(female):
    poser = poser_for(female)
    return poser, scenario_clip(parse_scenario(SCENARIO, "limbs.toml"), poser)


def limb_dofs(skeleton) -> np.ndarray:
    return np.flatnonzero(np.isin(np.array(skeleton.names)[skeleton.dof_parts], LIMB_PARTS))


def test_round_trip_export_import_gives_the_same_joint_angles(scene, tmp_path):
    poser, clip = scene
    path = tmp_path / "motion.bvh"
    path.write_text(write_bvh(export_bvh(poser.skeleton, clip)))
    bvh = read_bvh(path)
    result = retarget(bvh, poser.skeleton, choose_joint_map(bvh.names, poser.skeleton))
    assert result.unit == "cm"
    assert np.degrees(np.abs(result.clip.angles - clip.angles)).max() < 0.01  # measured 0.005° (6-decimal file)
    assert np.abs(result.clip.root - clip.root).max() < 1e-9


def other_tool_bvh(poser, clip, order: str, unit: float, turn: float, walk: float, joints=CMU) -> str:
    """The clip as a BVH of `joints` (CMU names by default) with a T-pose rest, Z up, `order` channels,
    1 file unit = `unit` m, the whole body turning by `turn` (rad) about the vertical and walking `walk` m forward."""
    sk = poser.skeleton
    clinical_t = {"upper_arm_l.abduction": np.radians(90), "upper_arm_r.abduction": np.radians(90),
                  "forearm_l.flexion": 0.0, "forearm_r.flexion": 0.0}
    t_pose = poser.kinematics.pose(poser.angles(clinical=clinical_t))
    up_z = Rotation.from_euler("x", 90, degrees=True).as_matrix()  # their world: ours turned, Z up
    n = len(clip.times)
    spin = Rotation.from_euler("y", turn * np.linspace(0, 1, n)[:, None]).as_matrix()
    root = np.tile(np.eye(4), (n, 1, 1))
    pelvis = sk.joints[0]
    root[:, :3, :3] = spin
    root[:, :3, 3] = pelvis - spin @ pelvis + np.outer(np.linspace(0, walk, n), [0, 0, 1])
    posed = poser.kinematics.pose(clip.angles, root=root)
    part = {name: sk.index(name) for name in sk.names}
    rest_t = {}  # their rest positions, our world, metres
    for name, _parent, parts in joints:
        if parts is None:  # the hip's offset bone, halfway to the thigh joint
            side = "thigh_l" if name.startswith("L") else "thigh_r"
            rest_t[name] = 0.5 * (t_pose.joints[0, 0] + t_pose.joints[0, part[side]])
        else:
            rest_t[name] = t_pose.joints[0, part[parts[0]]]
    children = {name: [c for c, p, _ in joints if p == name] for name, _, _ in joints}
    parts_of = {name: parts for name, _, parts in joints}
    parent_of = {name: parent for name, parent, _ in joints}

    def directions(name, joints, tails):
        """The joint's rest bone directions: to its mapped children, or (a leaf) to its last part's tail."""
        start = joints[part[parts_of[name][0]]]
        kids = [c for c in children[name] if parts_of[c] is not None]
        if kids:
            return [joints[part[parts_of[c][0]]] - start for c in kids]
        return [tails[part[parts_of[name][-1]]] - start]

    world = {}  # their joints' world rotations per frame, in their world
    for name, parent, parts in joints:
        if parts is None:
            world[name] = world[parent]
            continue
        theirs = directions(name, t_pose.joints[0], t_pose.tails[0])
        ours = directions(name, sk.joints, sk.tails)
        # their rest orientation of this bone relative to ours: the rotation taking our rest bones onto theirs
        align = Rotation.align_vectors(np.array(theirs), np.array(ours))[0].as_matrix()
        motion = posed.rotations[:, part[parts[-1]]] if parent is not None else posed.rotations[:, 0]
        world[name] = up_z @ motion @ align.T @ up_z.T
    channels = " ".join(f"{axis}rotation" for axis in order)
    lines, columns = ["HIERARCHY"], []

    def emit(name, depth):
        pad = "  " * depth
        parent = parent_of[name]
        offset = up_z @ (rest_t[name] - (rest_t[parent] if parent else 0.0)) / unit
        lines.extend([f"{pad}{'ROOT' if parent is None else 'JOINT'} {name}", f"{pad}{{",
                      f"{pad}  OFFSET {offset[0]:.6f} {offset[1]:.6f} {offset[2]:.6f}",
                      f"{pad}  CHANNELS {6 if parent is None else 3} "
                      + ("Xposition Yposition Zposition " if parent is None else "") + channels])
        local = world[name] if parent is None else np.swapaxes(world[parent], 1, 2) @ world[name]
        if parent is None:
            columns.append((up_z @ posed.joints[:, 0].T).T / unit)
        columns.append(Rotation.from_matrix(local).as_euler(order.upper(), degrees=True))
        for child in children[name]:
            emit(child, depth + 1)
        leaf = LEAVES.get(name.split(":")[-1])
        if leaf:
            tip = up_z @ (t_pose.tails[0, part[leaf]] - t_pose.joints[0, part[leaf]]) / unit
            lines.extend([f"{pad}  End Site", f"{pad}  {{",
                          f"{pad}    OFFSET {tip[0]:.6f} {tip[1]:.6f} {tip[2]:.6f}", f"{pad}  }}"])
        lines.append(f"{pad}}}")

    emit(joints[0][0], 0)
    values = np.hstack(columns)
    lines += ["MOTION", f"Frames: {n}", "Frame Time: 0.05"] + [" ".join(f"{x:.6f}" for x in row) for row in values]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("order, unit, name, joints, shipped", [("zxy", 0.01, "cm", CMU, "cmu.toml"),
                                                                ("xyz", 0.0254, "in", CMU, "cmu.toml"),
                                                                ("yxz", 1.0, "m", MIXAMO, "mixamo.toml")])
def test_another_tools_bvh_imports_to_the_joint_angles_it_encodes(scene, order, unit, name, joints, shipped):
    poser, clip = scene
    text = other_tool_bvh(poser, clip, order, unit, turn=np.radians(30), walk=0.4, joints=joints)
    bvh = parse_bvh(text, "other_tool.bvh")
    joint_map = choose_joint_map(bvh.names, poser.skeleton)
    assert joint_map.source.endswith(shipped)
    result = retarget(bvh, poser.skeleton, joint_map)
    assert result.unit == name
    limbs = limb_dofs(poser.skeleton)
    error = np.degrees(np.abs(result.clip.angles[:, limbs] - clip.angles[:, limbs]))
    assert error.max() < 0.1
    others = np.setdiff1d(np.arange(poser.skeleton.n_dofs), limbs)
    assert np.degrees(np.abs(result.clip.angles[:, others])).max() < 0.1  # spine, girdles, toes: at rest
    # the root: turned 30° about the vertical and 40 cm forward at the end (same hip height: scale 1)
    turn = Rotation.from_matrix(result.clip.root[-1, :3, :3]).as_rotvec()
    assert np.degrees(turn) == pytest.approx([0, 30, 0], abs=0.01)
    pelvis = poser.skeleton.joints[0]
    moved = result.clip.root[-1, :3, :3] @ pelvis + result.clip.root[-1, :3, 3]
    assert moved == pytest.approx(pelvis + [0, 0, 0.4], abs=1e-4)




@pytest.mark.parametrize("old, new, said", [
    ("CHANNELS 3 Zrotation", "CHANNELS 3 Wrotation", "line 9: Spine: channel 'Wrotation'; allowed each of"),
    ("OFFSET 0 10 0\n    CHANNELS", "OFFSET 0 ten 0\n    CHANNELS",
     "line 8: Spine OFFSET: 'ten'; allowed a finite number"),
    ("0 90 0 0 0 0 0 10 0", "0 90 0 0 0 0 0 1O 0", "line 20: channel value '1O'; allowed a finite number"),
    ("0 90 0 0 0 0 0 10 0", "0 90 0 0 0 0 0 10", "line 20: 17 channel values for 2 frames of 9 channels; allowed 18"),
    ("Frames: 2", "Frames: 0", "line 17: frame count 0; allowed a whole number"),
    ("  JOINT Spine", "  BONE Spine", "line 6: expected JOINT, End Site or '}', found 'BONE'"),
    ("MOTION\n", "", "line 16: expected 'MOTION', found 'Frames:'"),
])
def test_a_malformed_bvh_is_one_line_with_the_line_number(old, new, said):
    assert old in GOOD
    with pytest.raises(HitogataError) as err:
        parse_bvh(GOOD.replace(old, new), "bad.bvh")
    assert str(err.value).startswith("bad.bvh: ") and said in str(err.value) and "\n" not in str(err.value)


def test_frames_split_over_lines_are_refused():
    with pytest.raises(HitogataError, match="line 19: 5 values on this frame line; allowed 9"):
        parse_bvh(GOOD.replace("0 90 0 0 0 0 0 0 0", "0 90 0 0 0\n0 0 0 0"), "split.bvh")


def test_cli_export_import_and_a_scenario_whose_timeline_is_the_bvh(tmp_path, capsys, female, scene):
    from hitogata.motion.scenario import load_scenario

    poser, _ = scene
    (tmp_path / "limbs.toml").write_text(
        '[body]\nsex = "female"\n[time]\nduration = "1s"\nrate = 20\n'
        '[[keyframe]]\ntime = "0s"\n[[keyframe]]\ntime = "0.6s"\nclinical = { "forearm_r.flexion" = 120, '
        '"thigh_l.flexion" = 60, "upper_arm_l.abduction" = 100 }\n')
    assert main(["motion", "export", str(tmp_path / "limbs.toml"), "--out", str(tmp_path / "limbs.bvh")]) == 0
    assert main(["motion", "import", str(tmp_path / "limbs.bvh"), "--out", str(tmp_path / "again.toml")]) == 0
    assert "21 frames at 20 /s" in capsys.readouterr().out
    original = load_scenario(tmp_path / "limbs.toml")
    imported = load_scenario(tmp_path / "again.toml")
    (tmp_path / "from_bvh.toml").write_text('[body]\nsex = "female"\n[timeline]\nbvh = "limbs.bvh"\n')
    direct = load_scenario(tmp_path / "from_bvh.toml")
    want = scenario_clip(original, poser).angles
    for other in (imported, direct):
        got = scenario_clip(other, poser, rate=20).angles
        assert np.degrees(np.abs(got[:len(want)] - want)).max() < 0.01


def test_cli_errors_are_one_line_and_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.bvh"
    bad.write_text(GOOD.replace("0 90 0 0 0 0 0 10 0", "0 90 0 0 0 0 0 x 0"))
    assert main(["motion", "import", str(bad), "--out", str(tmp_path / "x.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "line 20: channel value 'x'" in err
    assert not (tmp_path / "x.toml").exists()
    both = tmp_path / "both.toml"
    both.write_text('[timeline]\nbvh = "bad.bvh"\n[[keyframe]]\ntime = "0s"\n')
    assert main(["motion", "export", str(both), "--out", str(tmp_path / "x.bvh")]) == 2
    assert "give a BVH file or [[keyframe]] entries, not both" in capsys.readouterr().err
    amap = tmp_path / "map.toml"
    amap.write_text('root = "Hips"\n[parts]\nSpine = "backbone"\n')
    good = tmp_path / "good.bvh"
    good.write_text(GOOD)
    assert main(["motion", "import", str(good), "--map", str(amap), "--out", str(tmp_path / "y.toml")]) == 2
    assert "Spine: unknown part 'backbone'" in capsys.readouterr().err


def test_a_bvh_timeline_moves_the_whole_body_with_its_root(tmp_path, female, scene):
    """A walk forward in the BVH's root channels: the scenario keeps it as a root track, the
    skeleton motion and the simulated skin travel with it (the body's own stride scale: the
    file's skeleton is ours, so 1:1)."""
    import dataclasses

    from hitogata.dynamics.motion import simulate
    from hitogata.simulation.run import build_dynamics
    from hitogata.motion.scenario import load_scenario

    poser, clip = scene
    bvh = export_bvh(poser.skeleton, clip)
    position = [i for i, c in enumerate(bvh.joints[0].channels) if c.endswith("position")]
    walked = bvh.values.copy()
    forward = np.linspace(0.0, 40.0, len(walked))  # cm along z: 40 cm over the clip
    walked[:, position[2]] += forward
    (tmp_path / "walk.bvh").write_text(write_bvh(dataclasses.replace(bvh, values=walked)))
    (tmp_path / "walk.toml").write_text('[body]\nsex = "female"\n[model]\nextent = "trunk"\nelement_size = "60mm"\n'
                                        'modes = 4\n[timeline]\nbvh = "walk.bvh"\n')
    scenario = load_scenario(tmp_path / "walk.toml")
    assert scenario.root is not None
    moved = scenario_clip(scenario, poser, rate=20).root[:, :3, 3] - scenario.root.transforms[0, :3, 3]
    assert moved[-1] == pytest.approx([0.0, 0.0, 0.40], abs=1e-6)  # at the clip's end (1 s), and held after
    assert moved[10, 2] == pytest.approx(0.20, abs=1e-6)  # 0.5 s: linear between the frames
    motion = simulate(build_dynamics(female, scenario), scenario.timeline, 1.0, 4.0, 1, True, "clamp",
                      root=scenario.root)
    pelvis = poser.skeleton.names.index("pelvis")
    assert motion.translations[-1, pelvis] - motion.translations[0, pelvis] == pytest.approx([0, 0, 0.40], abs=1e-6)
    assert (motion.skin[-1] - motion.skin[0]).mean(axis=0)[2] == pytest.approx(0.371, abs=1e-3)  # limbs move too
    assert np.abs(motion.skin - motion.skinned_skin).max() < 0.05  # the tissue travels with its skeleton
