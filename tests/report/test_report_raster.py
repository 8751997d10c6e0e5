"""The pictures' depth buffer: each pixel shows the nearest triangle over its centre, as a direct test finds it."""

import numpy as np

from hitogata.report.raster import rasterise

PIXEL = 0.01


def nearest_by_brute_force(screen: np.ndarray, depth: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Index of the nearest triangle over each point (-1: none), one triangle at a time."""
    best, found = np.full(len(centres), np.inf), np.full(len(centres), -1)
    for k, (a, b, c) in enumerate(screen):
        area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        if area == 0.0:
            continue
        wa = ((b[0] - centres[:, 0]) * (c[1] - centres[:, 1]) - (b[1] - centres[:, 1]) * (c[0] - centres[:, 0])) / area
        wb = ((c[0] - centres[:, 0]) * (a[1] - centres[:, 1]) - (c[1] - centres[:, 1]) * (a[0] - centres[:, 0])) / area
        wc = 1.0 - wa - wb
        z = wa * depth[k, 0] + wb * depth[k, 1] + wc * depth[k, 2]
        wins = (wa >= 0) & (wb >= 0) & (wc >= 0) & (z < best)
        best[wins], found[wins] = z[wins], k
    return found


def test_each_pixel_shows_the_nearest_triangle_over_its_centre() -> None:
    rng = np.random.default_rng(7)
    screen, depth = rng.uniform(0.0, 1.0, (60, 3, 2)), rng.uniform(0.0, 1.0, (60, 3))
    screen[0, 2] = screen[0, 1]  # a degenerate triangle covers nothing
    colours = np.column_stack([rng.uniform(0.0, 1.0, (60, 3)), np.ones(60)])
    image = rasterise(screen, depth, colours, PIXEL)
    height, width, _ = image.rgba.shape
    left, right, bottom, top = image.extent
    np.testing.assert_allclose([right - left, top - bottom], [width * PIXEL, height * PIXEL], rtol=1e-12)
    columns, rows = np.meshgrid(left + (np.arange(width) + 0.5) * PIXEL, bottom + (np.arange(height) + 0.5) * PIXEL)
    found = nearest_by_brute_force(screen, depth, np.column_stack([columns.ravel(), rows.ravel()]))
    expected = np.zeros((height * width, 4))
    expected[found >= 0] = colours[found[found >= 0]]
    np.testing.assert_allclose(image.rgba.reshape(-1, 4), expected, atol=1e-6)  # float32 colours
    assert 0 < (found >= 0).sum() < len(found)  # covered and bare pixels both tested
