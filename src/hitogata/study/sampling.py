"""Statures and masses drawn from a population's published statistics (pure numpy).

Per sex, stature and mass are jointly normal with the given means, standard
deviations and correlation: x = μ + L z with L the Cholesky factor of the
covariance and z standard normal. Each sex draws from its own stream spawned
from the study's seed, so changing the number of men leaves the women alone.
Bodies are grouped into clusters of similar stature and mass (k-means on the
standardised pair, per sex) for the percentile tables.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.cluster.vq import kmeans2

SEXES = ("female", "male")


@dataclass(frozen=True)
class Joint:
    """A sex's joint normal distribution of stature (m) and mass (kg), with its published source."""

    stature_mean: float
    stature_sd: float
    mass_mean: float
    mass_sd: float
    correlation: float
    source: str

    @property
    def mean(self) -> np.ndarray:
        return np.array([self.stature_mean, self.mass_mean])

    @property
    def covariance(self) -> np.ndarray:
        s, m, r = self.stature_sd, self.mass_sd, self.correlation
        return np.array([[s * s, r * s * m], [r * s * m, m * m]])


def sex_counts(count: int, female_share: float) -> dict[str, int]:
    """Women and men in a sample of `count`: the share rounded, the rest men."""
    women = int(round(count * female_share))
    return {"female": women, "male": count - women}


def sample_stature_mass(joint: Joint, count: int, seed: int, sex: str) -> np.ndarray:
    """(count, 2) statures (m) and masses (kg) of one sex, reproducible from the seed."""
    stream = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(SEXES.index(sex),)))
    z = stream.standard_normal((count, 2))
    return joint.mean + z @ np.linalg.cholesky(joint.covariance).T


def clusters(values: np.ndarray, k: int, seed: int) -> np.ndarray:
    """(N,) cluster index 0..k−1 of each (stature, mass) row, ordered by the clusters' mean mass.

    k-means on the standardised columns; a cluster count above N is cut to N.
    """
    n = len(values)
    k = max(1, min(k, n))
    if k == 1:
        return np.zeros(n, dtype=int)
    scale = values.std(axis=0)
    scaled = (values - values.mean(axis=0)) / np.where(scale > 0, scale, 1.0)
    _, labels = kmeans2(scaled, k, seed=np.random.default_rng(seed), minit="++")
    present = np.unique(labels)
    order = present[np.argsort([values[labels == c, 1].mean() for c in present])]
    rank = {int(c): i for i, c in enumerate(order)}
    return np.array([rank[int(c)] for c in labels])
