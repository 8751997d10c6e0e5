"""Posing benchmark: muscles → joint angles (eq. 1, 2) → kinematics → skinning of the whole skin.

Goal (issue 3): ≤ 2 ms per pose for the whole chain, and a batch of 1,000 poses.
Baselines, measured in the same run on the same poses: linear blend skinning
with dense (V, 65) weights (every vertex blends all 65 transforms, the plain
numpy way), and a per-vertex Python loop over the sparse weights for one pose.

Run:  python benchmarks/bench_pose.py
"""

from __future__ import annotations

import statistics
import time
from functools import partial

import numpy as np

from hitogata.body import default_body
from hitogata.muscles.activation import Drive, muscle_lengths
from hitogata.posing import Poser
from hitogata.posing.skinning import skin_vertices

DRIVERS = [
    "rectus_abdominis_l", "external_oblique_r", "sternocleidomastoid_l", "deltoid_l", "pectoralis_major_r",
    "biceps_brachii_l", "triceps_brachii_r", "pronator_teres_l", "flexor_digitorum_superficialis_r",
    "iliopsoas_l", "gluteus_maximus_r", "hamstrings_l", "quadriceps_r", "tibialis_anterior_l", "gastrocnemius_r",
]  # fmt: skip
N_BATCH = 1000


def timed(fn, repeat: int) -> float:
    """Median seconds of `repeat` calls."""
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return statistics.median(out)


def random_lengths(poser: Poser, n: int, seed: int = 0) -> np.ndarray:
    """(n, k) driver lengths for random angles inside each driver's joint ranges and reach."""
    ms, rng = poser.muscles, np.random.default_rng(seed)
    idx = [ms.index(n) for n in DRIVERS]
    lo = np.maximum(ms.low, ms.reach_low)[idx]
    hi = np.minimum(ms.high, ms.reach_high)[idx]
    theta = lo + (hi - lo) * rng.uniform(0.05, 0.95, (n, len(idx)))
    q = np.zeros((n, ms.skeleton.n_dofs))
    for j, m in enumerate(idx):
        q += np.where(
            theta[:, j : j + 1] >= 0, theta[:, j : j + 1] * ms.share_pos[m], theta[:, j : j + 1] * ms.share_neg[m]
        )
    return muscle_lengths(ms, q)[:, idx]


def dense_lbs(weights: np.ndarray, rest: np.ndarray, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """Baseline: blend all 65 transforms per vertex with dense weights."""
    r = np.einsum("vk,pkij->pvij", weights, rotations)
    t = np.einsum("vk,pki->pvi", weights, translations)
    return np.einsum("pvij,vj->pvi", r, rest) + t


def loop_lbs(weights, rest: np.ndarray, rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """Baseline: one pose, a Python loop over vertices and their influences."""
    out = np.zeros_like(rest)
    for v in range(len(rest)):
        for ptr in range(weights.indptr[v], weights.indptr[v + 1]):
            k, w = weights.indices[ptr], weights.data[ptr]
            out[v] += w * (rotations[k] @ rest[v] + translations[k])
    return out


def chain(poser: Poser, drive: Drive, lengths: np.ndarray, method: str) -> np.ndarray:
    """Muscle lengths (P, k) → angles → kinematics → skinned surfaces (P, V, 3)."""
    pose = poser.kinematics.pose(drive.angles(lengths))
    return skin_vertices(poser.skin, pose.rotations, pose.translations, method)


def main() -> None:
    body = default_body("female")
    t0 = time.perf_counter()
    poser = Poser.from_body(body)
    print(
        f"prepare skeleton, {len(poser.muscles.names)} muscles and skin on a body: "
        f"{1e3 * (time.perf_counter() - t0):.0f} ms ({len(body.vertices)} skin vertices, "
        f"{len(poser.skeleton.names)} parts, {poser.skeleton.n_dofs} DOFs)"
    )
    drive = Drive(poser.muscles, DRIVERS, mode="length")
    lengths = random_lengths(poser, N_BATCH)
    skin, rest = poser.skin, poser.skin.rest

    print(f"\none pose, {len(DRIVERS)} muscles set (median of 300):")
    one = lengths[:1]
    pose = poser.kinematics.pose(drive.angles(one))
    t_drive = timed(lambda: drive.angles(one), 300)
    t_fk = timed(lambda: poser.kinematics.pose(drive.angles(one)), 300) - t_drive
    print(f"  muscles -> angles {1e3 * t_drive:.3f} ms, kinematics {1e3 * t_fk:.3f} ms")
    skin_time = {}
    for method in ("lbs", "dqs"):
        skin_time[method] = timed(partial(skin_vertices, skin, pose.rotations, pose.translations, method), 300)
        whole = timed(partial(chain, poser, drive, one, method), 300)
        print(f"  skinning {method}: {1e3 * skin_time[method]:.3f} ms; whole chain {1e3 * whole:.3f} ms (goal <= 2 ms)")

    dense = skin.weights.toarray()
    t_dense = timed(lambda: dense_lbs(dense, rest, pose.rotations, pose.translations), 20)
    t_loop = timed(lambda: loop_lbs(skin.weights, rest, pose.rotations[0], pose.translations[0]), 1)
    ratio = t_dense / skin_time["lbs"]
    print(f"  baseline dense-weight LBS {1e3 * t_dense:.2f} ms: {ratio:.0f}x our LBS skinning")
    print(f"  baseline per-vertex loop LBS {1e3 * t_loop:.0f} ms: {t_loop / skin_time['lbs']:.0f}x")
    gap = np.abs(
        skin_vertices(skin, pose.rotations, pose.translations, "lbs")
        - dense_lbs(dense, rest, pose.rotations, pose.translations)
    )
    print(f"  (largest difference to the dense baseline: {gap.max():.1e} m)")

    print(f"\nbatch of {N_BATCH} poses (muscles -> angles -> kinematics -> skin, all at once):")
    out = {}
    for method in ("lbs", "dqs"):
        out[method] = chain(poser, drive, lengths, method)  # first touch of the (P, V, 3) output's memory
        t_batch = timed(partial(chain, poser, drive, lengths, method), 3)
        print(f"  {method}: {t_batch:.2f} s, {1e3 * t_batch / N_BATCH:.3f} ms per pose")
    p = poser.kinematics.pose(drive.angles(lengths[:100]))
    t_dense_b = timed(lambda: dense_lbs(dense, rest, p.rotations, p.translations), 1) / 100
    t_lbs_b = timed(lambda: skin_vertices(skin, p.rotations, p.translations, "lbs"), 3) / 100
    print(
        f"  baseline dense-weight LBS on 100 of them: {1e3 * t_dense_b:.2f} ms per pose, "
        f"{t_dense_b / t_lbs_b:.0f}x our batched LBS skinning ({1e3 * t_lbs_b:.3f} ms per pose)"
    )
    spread = np.linalg.norm(out["lbs"] - out["dqs"], axis=2)
    print(
        f"  LBS vs DQS over the batch: 99th percentile vertex gap {1e3 * np.percentile(spread, 99):.1f} mm, "
        f"max {1e3 * spread.max():.1f} mm"
    )


if __name__ == "__main__":
    main()
