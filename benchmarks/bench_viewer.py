"""Viewer benchmark: the server-side time of one muscle-slider move (issue 7).

Goal: ≤ 30 ms from a slider event to the new skin and skeleton queued for the
browser (posing, skinning, in-place vertex updates, the other sliders' echo).
Each move is also timed until its skin update has arrived at a websocket
client on this machine (viser serialises and sends on its own thread).
Baselines, measured in the same run on the same moves:
  - full re-send: the same pose, but the skin and skeleton re-added as new
    scene nodes (faces and all), as a viewer without in-place updates does;
  - from scratch: the skeleton, muscles and skin prepared anew for every move
    (`Poser.from_body`), then posed and updated in place.
The measurements and strain colours that follow a move on their own threads
are timed separately. With Playwright and Debian's chromium present, the
headline is measured again with a headless browser connected and drawing.

Run:  python benchmarks/bench_viewer.py
"""

from __future__ import annotations

import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import viser
from websockets.sync.client import ClientConnection, connect

from hitogata.body import default_body
from hitogata.posing import Poser
from hitogata.viewer import serve
from hitogata.measure import MEASUREMENT_NAMES
from hitogata.viewer.app import ViewerApp, measurement_markdown
from hitogata.viewer.frame import posed_frame
from hitogata.viewer.scene import BONE_LINE_COLOUR, SKIN_COLOUR

MUSCLE = "biceps_brachii_r"
MOVES = 60
CHROMIUM = "/usr/bin/chromium"


def sweep(app: ViewerApp) -> list[float]:
    """Slider positions (percent) across the muscle's range, there and back (no repeats: each one moves)."""
    k = app.state.muscles.index(MUSCLE)
    lo, hi = app.state.ranges.low[k], app.state.ranges.high[k]
    there = np.round(np.linspace(lo, hi, MOVES // 2 + 1), 1)
    return [float(v) for v in np.concatenate([there[1:], there[-2::-1]])]


def timed_moves(move: Callable[[float], None], values: list[float], client: ClientConnection, payload: int) -> dict:
    """Median and 95th percentile per move: the handler's time, and until the client got `payload` bytes in one frame."""
    handler, delivered = [], []
    for v in values:
        t = time.perf_counter()
        move(v)
        handler.append(time.perf_counter() - t)
        while len(client.recv(timeout=10.0)) < payload:
            pass
        delivered.append(time.perf_counter() - t)
    return {key: (statistics.median(x), float(np.percentile(x, 95))) for key, x in
            (("handler", handler), ("delivered", delivered))}


def report(label: str, result: dict, reference: dict | None = None) -> None:
    cells = []
    for key in ("handler", "delivered"):
        median, p95 = result[key]
        ratio = f" = {median / reference[key][0]:.1f}x" if reference else ""
        cells.append(f"{key} {1e3 * median:5.1f} ms (p95 {1e3 * p95:5.1f}){ratio}")
    print(f"  {label:<44} " + "; ".join(cells))


def drain(client: ClientConnection) -> None:
    """Read whatever the server has sent so far."""
    try:
        while True:
            client.recv(timeout=0.5)
    except TimeoutError:
        pass


def main() -> None:
    body = default_body("female")
    app = serve(body, port=0)
    client = connect(f"ws://127.0.0.1:{app.server.get_port()}", subprotocols=[f"viser-v{viser.__version__}"],
                     max_size=None)
    try:
        drain(client)
        values = sweep(app)
        faces = body.faces
        v_bytes, f_bytes = len(body.vertices) * 12, len(faces) * 12
        print(f"one slider move ({MUSCLE}, {len(values)} moves across its range; one websocket client):")
        handler = timed_moves(lambda v: app.move_muscle(MUSCLE, v), values, client, v_bytes)
        report("the viewer's handler (measurements follow)", handler)
        print(f"  {'':<44} goal <= 30 ms handler: {'met' if handler['handler'][0] <= 0.030 else 'NOT met'}")
        app.wait_idle()
        drain(client)

        def in_place(v: float) -> None:
            app.scene.show(posed_frame(app.state.set_contraction(MUSCLE, v / 100.0)))

        ours = timed_moves(in_place, values, client, v_bytes)
        report(f"ours: prepared, in place ({v_bytes / 1e3:.0f} kB)", ours)

        scene = app.server.scene

        def full_resend(v: float) -> None:
            posed = app.state.set_contraction(MUSCLE, v / 100.0)
            scene.add_mesh_simple("/bench/skin", posed.vertices, faces, color=SKIN_COLOUR)
            scene.add_line_segments("/bench/skeleton", posed.bones, colors=BONE_LINE_COLOUR)

        drain(client)
        report(f"baseline: full re-send ({(v_bytes + f_bytes) / 1e3:.0f} kB)",
               timed_moves(full_resend, values, client, v_bytes + f_bytes), ours)
        scene.remove_by_name("/bench/skin")
        scene.remove_by_name("/bench/skeleton")

        def from_scratch(v: float) -> None:
            posed = Poser.from_body(body).pose(contractions={MUSCLE: v / 100.0})
            app.scene.show(posed_frame(posed))

        drain(client)
        report("baseline: Poser prepared anew each move", timed_moves(from_scratch, values[:20], client, v_bytes), ours)

        print("\nwhat follows a move on the background threads (median of 10):")
        app.wait_idle()
        frame = app.frame
        t_measure = statistics.median(_times(lambda: measurement_markdown(body, frame), 10))
        t_strain = statistics.median(_times(lambda: app.colouring.colours("skin strain", frame.vertices, frame.rig_joints), 10))
        print(f"  measurement table ({len(MEASUREMENT_NAMES)} ISO 8559-1 measurements): {1e3 * t_measure:.0f} ms")
        print(f"  strain colours (per-triangle strain -> vertex colours): {1e3 * t_strain:.0f} ms")
        drain(client)
        _with_browser(app, values, client, v_bytes)
    finally:
        client.close()
        app.stop()


def _times(fn: Callable[[], object], repeat: int) -> list[float]:
    out = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return out


def _with_browser(app: ViewerApp, values: list[float], client: ClientConnection, payload: int) -> None:
    """The headline again with a headless chromium connected, receiving and drawing every update."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        print("\n(playwright missing: the measurement with a browser connected was skipped)")
        return
    if not Path(CHROMIUM).exists():
        print("\n(Debian's chromium missing: the measurement with a browser connected was skipped)")
        return
    args = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync"]
    with sync_playwright() as playwright, tempfile.TemporaryDirectory() as profile:
        context = playwright.chromium.launch_persistent_context(
            profile, executable_path=CHROMIUM, headless=True, args=args)
        page = context.new_page()
        page.goto(app.url)
        page.get_by_text("stature", exact=True).wait_for(timeout=30_000)
        drain(client)
        print("\nwith a headless chromium connected too (software WebGL on the same 2 cores):")
        report("the viewer's handler (measurements follow)", timed_moves(lambda v: app.move_muscle(MUSCLE, v), values, client, payload))
        context.close()


if __name__ == "__main__":
    main()
