"""The offscreen renderer: real pictures (not blank), views in the body frame, translucency, clear errors."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

pytest.importorskip("pyvista")

from hitogata.errors import HitogataError  # noqa: E402
from hitogata.render import Layer, Lines, Points, Renderer, View, render_views, save_png, side_by_side, titled  # noqa: E402
from hitogata.render.shapes import spheres  # noqa: E402

SIZE = (160, 160)


def sphere(centre=(0.0, 0.0, 0.0), radius=1.0, **style) -> Layer:
    vertices, faces = spheres(np.array([centre], float), np.array([radius]), sides=32, rings=12)
    return Layer(vertices, faces, **style)


def centre_pixel(image: np.ndarray) -> np.ndarray:
    h, w = image.shape[:2]
    return image[h // 2 - 2 : h // 2 + 3, w // 2 - 2 : w // 2 + 3].reshape(-1, 3).mean(axis=0)


def column_of(image: np.ndarray, rgb: tuple[int, int, int]) -> float:
    """Mean column of the pixels nearest a pure colour (red, blue)."""
    channel = int(np.argmax(rgb))
    strong = (image[..., channel].astype(int) - image.astype(int).sum(axis=2) / 3) > 60
    return float(np.nonzero(strong)[1].mean())


def test_png_written_and_not_blank(tmp_path: Path) -> None:
    bones = Lines(np.array([[[0, 0, 0], [0, 1, 0]], [[0, 1, 0], [0.4, 1.3, 0.2]]], float), radius=0.05, color="tan")
    joints = Points(np.array([[0, 1, 0]], float), radius=0.08, color="navy")
    front, side = render_views([bones, joints], size=SIZE, labels=True)
    assert front.shape == side.shape == (SIZE[1], SIZE[0], 3) and front.dtype == np.uint8
    assert front.std() > 10 and side.std() > 10
    assert np.abs(front.astype(int) - side.astype(int)).mean() > 1
    out = save_png(tmp_path / "figure.png", side_by_side([front, side], gap=4))
    back = imread(out)
    assert back.shape[:2] == (SIZE[1], 2 * SIZE[0] + 4) and back.std() > 0.04
    assert [p.name for p in tmp_path.iterdir()] == ["figure.png"]  # no temporary file left


def test_views_follow_the_body_frame() -> None:
    """Front: the body's left (+X) on the picture's right. Side: the body's left side, its front (+Z) on the left."""
    left = sphere((1.0, 0.0, 0.0), 0.4, color=(1.0, 0.0, 0.0))
    front_ball = sphere((0.0, 0.0, 1.0), 0.4, color=(0.0, 0.0, 1.0))
    front, side, top = render_views([left, front_ball], views=("front", "side", "top"), size=SIZE)
    assert column_of(front, (255, 0, 0)) > column_of(front, (0, 0, 255))
    assert column_of(side, (0, 0, 255)) < column_of(side, (255, 0, 0))
    custom = render_views([left, front_ball], views=[View("back", (0, 0, 1), (0, 1, 0))], size=SIZE)[0]
    assert column_of(custom, (255, 0, 0)) < column_of(custom, (0, 0, 255))
    assert top.std() > 10


def test_translucent_inner_surface_shows_through() -> None:
    """Depth peeling with multisampling off: an opaque red sphere inside a translucent one is seen."""
    outer = sphere(radius=1.0, color="white", opacity=0.4)
    inner = sphere(radius=0.5, color=(1.0, 0.0, 0.0))
    alone = centre_pixel(render_views([outer], views=("front",), size=SIZE)[0])
    nested = centre_pixel(render_views([outer, inner], views=("front",), size=SIZE)[0])
    assert nested[0] - nested[1] > 60  # clearly red through the outer surface
    assert np.abs(nested - alone).max() > 60


def test_views_share_one_scale() -> None:
    """Front and side: the same scale; with no width given, each image is as wide as its view."""
    ball = sphere(radius=0.5, color=(1.0, 0.0, 0.0))
    bar = Lines(np.array([[[-3.0, -1.0, 0], [3.0, -1.0, 0]]]), radius=0.05, color=(0.0, 0.0, 1.0))
    front, side = render_views([ball, bar], size=(None, 200))
    assert front.shape[0] == side.shape[0] == 200
    assert front.shape[1] > 3 * side.shape[1]  # 6 m wide from the front, 1 m from the side

    def red(line: np.ndarray) -> np.ndarray:
        return line[:, 0].astype(int) - line[:, 1:].astype(int).mean(axis=1) > 60

    tall = [np.count_nonzero(red(im[:, im.shape[1] // 2])) for im in (front, side)]  # the ball's height, pixels
    assert tall[0] > 40 and abs(tall[0] - tall[1]) <= 2
    middle = int(np.nonzero(red(side[:, side.shape[1] // 2]))[0].mean())
    assert abs(np.count_nonzero(red(side[middle])) - tall[1]) <= 3  # as wide as tall: not squashed


def test_scalars_colour_a_layer() -> None:
    ball = sphere(radius=1.0)
    values = ball.vertices[:, 0]  # left-right gradient
    image = render_views(
        [Layer(ball.vertices, ball.faces, scalars=values, colormap="coolwarm")], views=("front",), size=SIZE
    )[0]
    row = image[SIZE[1] // 2]
    assert row[30, 2] > row[30, 0] and row[-30, 0] > row[-30, 2]  # blue at −X (left of picture), red at +X
    barred = render_views(
        [Layer(ball.vertices, ball.faces, scalars=values, colormap="coolwarm", scalar_title="mm")],
        views=("front",), size=(160, 240),
    )[0]
    strip = barred[-64:].astype(int)  # the colour bar, under the ball: blue to red
    assert (strip[..., 2] - strip[..., 0] > 80).any() and (strip[..., 0] - strip[..., 2] > 80).any()
    assert (barred[:8] == 255).all()  # the ball is kept clear of the bar, not pushed off the top


@pytest.mark.parametrize(
    "make,message",
    [
        (lambda: Layer(np.zeros((3, 3)), np.array([[0, 1, 5]])), "indices must lie in [0, 3)"),
        (lambda: Layer(np.zeros((3, 3)), np.array([[0, 1, 2]]), color="skin"), "Layer color = 'skin'"),
        (lambda: Layer(np.zeros((3, 3)), np.array([[0, 1, 2]]), opacity=1.5), "Layer opacity = 1.5: allowed 0..1"),
        (lambda: Lines(np.zeros((2, 3))), "Lines segments: shape (2, 3) given, expected (N, 2, 3)"),
        (lambda: Points(np.array([[0, np.nan, 0]])), "contains NaN"),
        (lambda: Points(np.zeros((2, 3)), radius=[1.0, -1.0]), "Points radius"),
        (lambda: render_views([], size=SIZE), "nothing to draw"),
        (lambda: render_views([Points(np.zeros((1, 3)))], views=("above",)), "view 'above': allowed front, side"),
        (lambda: render_views([Points(np.zeros((1, 3)))], size=(10, 10)), "size = (10, 10)"),
        (lambda: save_png("picture.jpg", np.zeros((4, 4, 3), np.uint8)), "writes .png files only"),
        (lambda: save_png("picture.png", np.zeros((4, 4))), "expected (height, width, 3 or 4) uint8"),
    ],
)
def test_bad_input_is_one_line(make, message: str) -> None:
    with pytest.raises(HitogataError) as err:
        make()
    assert message in str(err.value) and "\n" not in str(err.value)


RENDER_ONE = """
import numpy as np
from hitogata.errors import HitogataError
from hitogata.render import Points, render_views
try:
    render_views([Points(np.zeros((1, 3)), radius=0.1)], size=(64, 64))
except HitogataError as err:
    print(err)
    raise SystemExit(3)
"""


@pytest.mark.parametrize(
    "broken",
    [{"LIBGL_DRIVERS_PATH": "/nonexistent"}, {"__EGL_VENDOR_LIBRARY_FILENAMES": "/nonexistent.json"}],
    ids=["no-software-renderer", "no-mesa-egl-driver"],
)
def test_missing_gl_libraries_give_the_apt_command_not_a_crash(broken: dict) -> None:
    """Without these VTK segfaults (exit 139); we check first and name the packages."""
    env = {**os.environ, **broken}
    env.pop("VTK_DEFAULT_OPENGL_WINDOW", None)
    result = subprocess.run([sys.executable, "-c", RENDER_ONE], env=env, capture_output=True, text=True, timeout=60)
    assert result.returncode == 3, (result.returncode, result.stderr[-500:])
    assert "apt-get install -y libegl1 libegl-mesa0 libgl1-mesa-dri" in result.stdout


def test_pixel_lines_and_dots() -> None:
    """Lines without a radius are drawn `width` pixels wide, Points without one as dots."""
    lines = Lines(np.array([[[-1.0, -1.0, 0], [1.0, 1.0, 0]], [[-1.0, 1.0, 0], [1.0, -1.0, 0]]]), width=3)
    dots = Points(np.array([[0.0, -1.0, 0], [0.0, 1.0, 0]]), size=12, color="red")
    image = render_views([lines, dots], views=("front",), size=SIZE)[0]
    dark = (image < 100).all(axis=2)
    assert dark[SIZE[1] // 2, SIZE[0] // 2] and dark.sum() > 300  # the cross, through the centre
    assert column_of(image, (255, 0, 0)) == pytest.approx(SIZE[0] / 2, abs=3)


def test_a_live_renderer_draws_what_a_fresh_window_draws() -> None:
    """An animation reuses one window: after other pictures (another size, a colour bar) the same
    items give the same pixels as in a window of their own (lights, bars and actors not carried over)."""
    scene = [sphere(opacity=0.4, color="#b5473a"), Lines(np.array([[[0, -1.5, 0], [0, 1.5, 0]]]), radius=0.05)]
    other = [sphere((0.3, 0.0, 0.0), scalars=sphere().vertices[:, 1], scalar_title="height (m)")]
    fresh = render_views(scene, size=(120, 180))
    with Renderer() as renderer:
        renderer.render(other, size=(120, 180))
        renderer.render(scene, size=(100, 150))
        renderer.render(other, size=(120, 180))
        live = renderer.render(scene, size=(120, 180))
    for a, b in zip(fresh, live):
        np.testing.assert_array_equal(a, b)


def test_a_title_band_goes_on_top() -> None:
    image = np.full((50, 300, 3), 200, dtype=np.uint8)
    out = titled(image, "trunk flexion with the arms raised, t = 1.20 s")
    assert out.shape == (50 + 22, 300, 3) and np.array_equal(out[22:], image)
    assert (out[:22] < 128).any() and (out[:22] == 255).mean() > 0.5  # dark text on white
