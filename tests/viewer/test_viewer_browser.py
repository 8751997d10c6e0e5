"""End to end in a real headless browser: Debian's chromium driven by Playwright.

The page loads; a muscle slider moved with the keyboard changes the server's
pose, the picture on the canvas and a measurement shown; bad input typed into
the page is a message there and the server goes on; the pose downloads as GLB
and the static HTML snapshot opens from a file. GUI state is shared by every
client of a server, so each test resets what it moves first.

Steady on a busy machine: every step waits on the page's or the server's
state (a selector, a value, a canvas that stopped changing), never a fixed
pause; clicks do not wait for navigations (the page never navigates), and the
timeouts are `PATIENCE`, a bound reached only when the state never comes.
"""

import io
import shutil
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("viser", reason="the viewer needs viser (pip install viser)")
sync_api = pytest.importorskip("playwright.sync_api", reason="the browser test needs playwright (pip install playwright)")
CHROMIUM = "/usr/bin/chromium"
if not Path(CHROMIUM).exists():
    pytest.skip("the browser test needs Debian's chromium (apt-get install chromium)", allow_module_level=True)

from PIL import Image  # noqa: E402

from hitogata.viewer import serve  # noqa: E402
from hitogata.viewer.export import snapshot_html  # noqa: E402
from waiting import PATIENCE, wait_for  # noqa: E402

CHROMIUM_ARGS = [
    "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]
TIMEOUT_MS = PATIENCE * 1000
SETTLED = 8  # a canvas whose pixels moved by at most this much between two screenshots has settled


@pytest.fixture(scope="module")
def app(female):
    viewer = serve(female, port=0)
    yield viewer
    viewer.stop()


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    profile = tmp_path_factory.mktemp("chromium-profile")
    with sync_api.sync_playwright() as playwright:
        context = playwright.chromium.launch_persistent_context(
            str(profile), executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS,
            viewport={"width": 1280, "height": 800}, accept_downloads=True,
        )
        yield context
        context.close()
    shutil.rmtree(profile, ignore_errors=True)


@pytest.fixture(scope="module")
def page(app, browser):
    page = browser.new_page()
    page.set_default_timeout(TIMEOUT_MS)
    page.goto(app.url)
    page.locator("canvas").first.wait_for()
    page.get_by_text("stature", exact=True).wait_for()
    return page


def canvas_pixels(page) -> np.ndarray:
    png = page.locator("canvas").first.screenshot()
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)


def settled_canvas(page) -> np.ndarray:
    """The canvas's pixels once two screenshots in a row agree (the renderer has drawn the last update)."""
    shots = [canvas_pixels(page)]

    def same_as_before() -> bool:
        shots.append(canvas_pixels(page))
        return np.abs(shots[-1] - shots[-2]).max() <= SETTLED

    assert wait_for(same_as_before), "the canvas never settled"
    return shots[-1]


def click(locator) -> None:
    """Click without waiting for a navigation: the viewer is one page, a wait for one stalls under load."""
    locator.click(no_wait_after=True)


def slider_thumb(page, label: str):
    """The visible slider whose label reads `label` (the same name may sit in a closed folder)."""
    target = page.locator("label").filter(has_text=label).locator("visible=true").first
    return page.locator(f'[id="{target.get_attribute("for")}"] [role=slider]')


def field(page, label: str):
    """The visible input beside a label."""
    row = page.locator("label", has_text=label).locator("visible=true").first
    return row.locator("xpath=ancestor::div[contains(@class, 'mantine-Flex-root')][1]//input").first


def open_trunk(page) -> None:
    """Open the muscles' Trunk folder unless it is open (the page is shared: another test may have)."""
    trunk = page.get_by_text("Trunk", exact=True)
    trunk.wait_for()
    if not page.locator("label").filter(has_text="rectus abdominis (left)").locator("visible=true").count():
        click(trunk)


def stature_shown(page) -> str:
    return page.locator("tr", has_text="stature").first.inner_text()


def test_a_muscle_slider_moves_the_pose_the_picture_and_a_measurement(app, page):
    click(page.get_by_role("tab", name="Muscles"))
    click(page.get_by_role("button", name="Reset pose"))  # shared state: start from rest
    assert wait_for(lambda: app.state.drivers == {} and not app.showing_sequence)
    open_trunk(page)
    thumb = slider_thumb(page, "rectus abdominis (left)")
    assert thumb.get_attribute("aria-valuenow") == "0"
    assert app.wait_idle(PATIENCE)
    before_pixels, before_stature = settled_canvas(page), stature_shown(page)

    thumb.focus()
    page.keyboard.press("End")
    k = app.state.muscles.index("rectus_abdominis_l")
    assert wait_for(lambda: app.state.drivers.get("rectus_abdominis_l", 0.0) * 100 == pytest.approx(app.state.ranges.high[k]))
    assert app.state.posed.angle("lumbar_3.flexion") > 0.05  # the server's pose bent the spine
    assert wait_for(lambda: stature_shown(page) != before_stature), "the stature shown did not change"
    assert app.wait_idle(PATIENCE)

    def bent_on_canvas() -> bool:
        changed = np.abs(settled_canvas(page) - before_pixels).max(axis=2) > 24
        return changed.mean() > 0.01

    assert wait_for(bent_on_canvas), "the canvas did not show the bent spine"


def test_a_stature_outside_the_range_is_a_message_and_the_server_goes_on(app, page):
    click(page.get_by_role("tab", name="Body"))
    stature = page.get_by_label("stature (cm)")
    stature.fill("250")
    stature.press("Tab")
    assert wait_for(lambda: app.panels.stature.value == 250)
    click(page.get_by_role("button", name="Rebuild body"))
    page.get_by_text("stature 250.0 cm: allowed 140–210 cm").wait_for()
    stature.fill("165")  # shared state: put it back
    stature.press("Tab")
    page.reload()  # the server still serves and poses
    page.get_by_text("stature", exact=True).wait_for()
    click(page.get_by_role("tab", name="Muscles"))
    click(page.get_by_role("button", name="Reset pose"))
    assert wait_for(lambda: app.state.drivers == {})


def test_a_broken_scenario_file_is_a_message(app, page, tmp_path):
    broken = tmp_path / "broken.npz"
    broken.write_bytes(b"this is not a sequence")
    click(page.get_by_role("tab", name="Player"))
    path = field(page, "path")
    path.fill(str(broken))
    path.press("Tab")
    assert wait_for(lambda: app.panels.sequence_path.value == str(broken))
    click(page.get_by_role("button", name="Load"))
    page.get_by_text("not a readable .npz file").wait_for()
    assert app.sequence is None


def test_the_pose_downloads_as_glb_and_the_snapshot_opens_from_a_file(app, page, browser, tmp_path):
    click(page.get_by_role("tab", name="Export"))
    with page.expect_download() as download:
        click(page.get_by_role("button", name="Download pose (GLB)"))
    assert download.value.suggested_filename == "hitogata-pose.glb"
    assert Path(download.value.path()).read_bytes()[:4] == b"glTF"
    snapshot = tmp_path / "snapshot.html"
    snapshot.write_text(snapshot_html(app.server), encoding="utf-8")
    offline = browser.new_page()
    offline.set_default_timeout(TIMEOUT_MS)
    requests = []
    offline.on("request", lambda request: requests.append(request.url))
    offline.goto(snapshot.as_uri())
    offline.locator("canvas").first.wait_for()
    offline.close()
    assert all(url.startswith(("file:", "data:", "blob:")) for url in requests), requests


def frames_drawn(page, count: int) -> None:
    """Return once the page has drawn `count` more animation frames (its own clock, not ours)."""
    page.evaluate("""count => new Promise(done => {
        let n = 0;
        const step = () => (++n >= count ? done() : requestAnimationFrame(step));
        requestAnimationFrame(step);
    })""", count)


def test_a_held_arrow_key_moves_a_focused_slider_and_not_the_camera(app, page):
    """The camera turns with a held arrow key only when no slider has the focus."""
    click(page.get_by_role("tab", name="Muscles"))
    click(page.get_by_role("button", name="Reset pose"))
    assert wait_for(lambda: app.state.drivers == {} and not app.showing_sequence)
    open_trunk(page)
    client = max(app.server.get_clients().items())[1]  # this page's (a reloaded page's old one may linger)
    thumb = slider_thumb(page, "rectus abdominis (left)")
    thumb.focus()

    k = app.state.muscles.index("rectus_abdominis_l")
    ends = {"Home": app.state.ranges.low[k], "End": app.state.ranges.high[k]}  # percent

    def camera_reported(key: str) -> np.ndarray:
        """The camera as the server last heard of it, after every report the page has sent so far."""
        frames_drawn(page, 30)  # longer than the camera's 20 ms report throttle
        page.keyboard.press(key)  # a slider message after them: one socket keeps their order
        assert wait_for(lambda: app.state.drivers.get("rectus_abdominis_l", 0.0) * 100 == pytest.approx(ends[key]))
        return np.array(client.camera.wxyz)

    before = camera_reported("Home")
    page.keyboard.down("ArrowRight")
    assert wait_for(lambda: app.state.drivers["rectus_abdominis_l"] * 100 > ends["Home"] + 1e-6)
    frames_drawn(page, 30)  # a held key would turn the camera a little every frame
    page.keyboard.up("ArrowRight")
    assert np.allclose(camera_reported("End"), before, atol=1e-9), "the camera turned with the slider's key"

    page.evaluate("document.activeElement.blur()")  # no widget has the focus: the key is the camera's
    page.keyboard.down("ArrowRight")
    assert wait_for(lambda: not np.allclose(client.camera.wxyz, before, atol=1e-6)), "the camera never turned"
    page.keyboard.up("ArrowRight")
    click(page.get_by_role("button", name="Reset pose"))
    assert wait_for(lambda: app.state.drivers == {})


TRY_SOCKET = ('const socket = new WebSocket("URL"); socket.onopen = () => { document.title = "opened"; }; '
              'socket.onerror = () => { document.title = "refused"; };')


def test_a_page_from_another_origin_cannot_open_the_viewers_websocket(app, page, browser, tmp_path):
    """A site the user visits tries ws://127.0.0.1:PORT: Chromium reports the refusal; the viewer's own page works."""
    import http.server
    import threading

    script = TRY_SOCKET.replace("URL", app.url.replace("http://", "ws://"))
    (tmp_path / "index.html").write_text(f"<!doctype html><title>waiting</title><script>{script}</script>")
    handler = lambda *a, **k: http.server.SimpleHTTPRequestHandler(*a, directory=str(tmp_path), **k)  # noqa: E731
    foreign = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=foreign.serve_forever, daemon=True).start()
    visited = browser.new_page()
    try:
        visited.goto(f"http://127.0.0.1:{foreign.server_address[1]}/index.html")
        visited.wait_for_function("document.title !== 'waiting'", timeout=TIMEOUT_MS)
        assert visited.title() == "refused"
        visited.goto(app.url)  # the same script on the viewer's own page connects
        visited.evaluate(f"document.title = 'waiting'; {script}")
        visited.wait_for_function("document.title !== 'waiting'", timeout=TIMEOUT_MS)
        assert visited.title() == "opened"
    finally:
        visited.close()
        foreign.shutdown()
    assert page.get_by_text("stature", exact=True).is_visible()  # the viewer's page is still served
