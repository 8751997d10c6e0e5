"""The viewer application: one body's posing state, scene and panel on a viser server.

Every person's action goes through one lock, so the state, the scene and the
widgets change together. The fast path — a slider move — poses and skins
with the prepared Poser and updates vertex positions in place; measurements
and strain colours follow on their own threads (`Worker`), and the tissue
model is built on a thread the first time it is shown. A `HitogataError`
from any action is shown in the page; the server keeps running.
"""

from __future__ import annotations

import functools
import socket
import sys
import threading
import time
import traceback
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from hitogata.body.model import Body
from hitogata.errors import HitogataError
from hitogata.export.body_files import body_figures
from hitogata.measure import measure
from hitogata.viewer.colouring import SkinColours, legend
from hitogata.viewer.export import pose_glb, snapshot_html
from hitogata.viewer.frame import Frame, posed_frame, sequence_frame
from hitogata.viewer.keys import keep_arrows_for_widgets
from hitogata.viewer.panels import build_panels
from hitogata.viewer.player import Clock, Sequence, load_sequence
from hitogata.viewer.scene import SceneView
from hitogata.viewer.state import SLIDER_STEP, PoseState
from hitogata.viewer.tissue import tissue_surfaces
from hitogata.viewer.worker import Worker
from hitogata.volume import build_trunk_model

if TYPE_CHECKING:
    import viser

    from hitogata.garment.fabric import Fabric
    from hitogata.garment.pressure import Garment

PLAYBACK_TICK = 1.0 / 30.0  # s between shown frames while playing
MEASURE_DELAY = 0.03  # s: the skin update goes out before the measurements start (see Worker)
F = TypeVar("F", bound=Callable[..., Any])


def reported(action: F) -> F:
    """Show an action's `HitogataError` (or an unexpected failure) in the page instead of raising."""
    @functools.wraps(action)
    def run(self: "ViewerApp", *args: Any, **kwargs: Any) -> Any:
        try:
            return action(self, *args, **kwargs)
        except HitogataError as err:
            self.say(str(err), error=True)
        except Exception as exc:  # a bug must not take the server down: report it and go on
            traceback.print_exc(file=sys.stderr)
            self.say(f"internal error in {action.__name__}: {exc}", error=True)
        return None
    return run  # type: ignore[return-value]


def measurement_markdown(body: Body, frame: Frame) -> str:
    """Markdown table of the frame's measurements in centimetres."""
    values = measure(body, frame.vertices, frame.rig_joints).as_dict()
    rows = [f"| {name.replace('_', ' ')} | {'—' if np.isnan(v) else f'{v * 100:.1f}'} |" for name, v in values.items()]
    return "| measurement | cm |\n|---|---:|\n" + "\n".join(rows)


def figures_text(body: Body) -> str:
    """The body's headline figures on one line."""
    f = body_figures(body)
    return f"stature {f['stature_cm']:.1f} cm · mass {f['mass_kg']:.1f} kg · BMI {f['bmi']:.1f} · volume {f['volume_l']:.1f} L"


class ViewerApp:
    """The viewer of one body on a running viser server."""

    def __init__(self, server: "viser.ViserServer", body: Body,
                 garment: "tuple[Garment, Fabric] | None" = None) -> None:
        self.server = server
        server.gui.configure_theme(control_width="large", show_share_button=False)  # no tunnel off this machine
        keep_arrows_for_widgets(server)
        self.lock = threading.RLock()
        self.state = PoseState(body)
        self.frame = posed_frame(self.state.posed)
        self.garment = garment
        self.colouring = SkinColours(body, garment)
        self.colour_map = "skin strain"
        self.sequence: Sequence | None = None
        self.clock: Clock | None = None
        self.showing_sequence = False
        self._playback: threading.Thread | None = None
        self._tissue_for: Body | None = None  # the body whose tissue model is built or being built
        self.scene = SceneView(server.scene, body.faces, self.frame, skin_opacity=1.0)
        self.scene.fit_bones(self.state.poser.skeleton, body.vertices)
        self._aim_camera(body)
        inputs = {"sex": "male" if body.params.sex >= 0.5 else "female", "age": body.params.age,
                  "stature_cm": round(body.stature * 100, 1), "mass_kg": round(body.mass, 1)}
        self.panels = build_panels(server.gui, self.state, inputs, self, self.colouring.maps)
        self.panels.figures.content = figures_text(body)
        self.measurer = Worker(self._measure, "measurements", self._fail, delay=MEASURE_DELAY)
        self.painter = Worker(self._paint_strain, "strain colours", self._fail)
        self.measurer.request()

    # ------------------------------------------------------------------ showing

    def _aim_camera(self, body: Body) -> None:
        height = body.stature
        self.server.initial_camera.position = (0.45 * height, 0.6 * height, 0.85 * height)
        self.server.initial_camera.look_at = (0.0, 0.5 * height, 0.0)

    def say(self, text: str, error: bool = False) -> None:
        """Show a one-line message at the top of the panel (an error in bold)."""
        self.panels.message.content = f"**Error:** {text}" if error else text
        if error:
            print(f"hitogata view: {text}", file=sys.stderr)

    def _fail(self, text: str) -> None:
        self.say(text, error=True)

    def show(self, frame: Frame) -> None:
        """Show a frame now; measurements and strain colours follow."""
        self.frame = frame
        self.scene.show(frame)
        self.measurer.request()
        if self.scene.layers["strain"]:
            self.painter.request()

    def _measure(self) -> None:
        with self.lock:
            body, frame = self.state.body, self.frame
        self.panels.measurements.content = measurement_markdown(body, frame)

    def _paint_strain(self) -> None:
        with self.lock:
            frame, colouring, name = self.frame, self.colouring, self.colour_map
        colours = colouring.colours(name, frame.vertices, frame.rig_joints)
        with self.lock:  # a newer frame or map has requested its own run meanwhile (`show`, `set_colour_map`)
            self.scene.show_strain(frame.vertices, colours)

    def _echo_sliders(self, moved: str | None = None) -> None:
        """Set every slider but the one being moved to its muscle's contraction in the current pose."""
        for name, value in self.state.slider_values().items():
            slider = self.panels.sliders[name]
            if name != moved and abs(slider.value - value) > 0.5 * SLIDER_STEP:
                slider.value = value

    # ------------------------------------------------------------------ actions (panels.Actions)

    @reported
    def move_muscle(self, name: str, percent: float) -> None:
        with self.lock:
            driven = self.state.drivers.get(name)
            if driven is not None and abs(driven * 100.0 - percent) < 1e-9 and not self.showing_sequence:
                return  # a queued event for a value already shown
            self._stop_sequence()
            posed = self.state.set_contraction(name, percent / 100.0)
            self.show(posed_frame(posed))
            self._echo_sliders(moved=name)

    @reported
    def reset_pose(self) -> None:
        with self.lock:
            self._stop_sequence()
            self.show(posed_frame(self.state.reset()))
            self._echo_sliders()
            self.say("pose reset to rest")

    @reported
    def rebuild_body(self, sex: str, age: float, stature_cm: float, mass_kg: float) -> None:
        self.panels.rebuild.disabled = True
        try:
            for label, value in (("age", age), ("stature", stature_cm), ("mass", mass_kg)):
                if not isinstance(value, (int, float)):
                    raise HitogataError(f"{label} {value!r}: allowed a number")
            self.say(f"building a body of {stature_cm:g} cm, {mass_kg:g} kg…")
            body = Body.from_measurements(sex, float(age), float(stature_cm) / 100.0, float(mass_kg))
            colouring = SkinColours(body, self.garment)
            with self.lock:
                self._drop_sequence()
                posed = self.state.set_body(body)
                self.scene.fit_bones(self.state.poser.skeleton, body.vertices)
                self.colouring = colouring
                self._update_slider_ranges()
                self.scene.clear_tissue()
                self._tissue_for = None
                self.show(posed_frame(posed))
                self._echo_sliders()
                self.panels.figures.content = figures_text(body)
                if self.scene.layers["tissue"]:
                    self._build_tissue()
            self.say(f"body rebuilt: {figures_text(body)}")
        finally:
            self.panels.rebuild.disabled = False

    def _update_slider_ranges(self) -> None:
        ranges = self.state.ranges
        for k, name in enumerate(self.state.muscles.names):
            slider = self.panels.sliders[name]
            slider.min, slider.max = float(ranges.low[k]), float(ranges.high[k])

    @reported
    def set_layer(self, layer: str, on: bool) -> None:
        with self.lock:
            self.scene.set_layer(layer, on)
            if layer == "strain" and on:
                self.painter.request()
            if layer == "tissue" and on and self._tissue_for is not self.state.body:
                self._build_tissue()

    @reported
    def set_colour_map(self, name: str) -> None:
        """Colour the skin by map `name` (`viewer.colouring.MAPS`); the colour layer is turned on."""
        with self.lock:
            if name not in self.colouring.maps:
                self.colouring.values(name, self.frame.vertices, self.frame.rig_joints)  # its one-line error
            self.colour_map = name
            self.panels.legend.content = legend(name)
            self.panels.colour_map.value = name
            self.panels.colours.value = True
            self.scene.set_layer("strain", True)
            self.painter.request()

    @reported
    def set_skin_opacity(self, opacity: float) -> None:
        with self.lock:
            self.scene.set_skin_opacity(opacity)

    def _build_tissue(self) -> None:
        """Build the trunk's tissue model on a thread; show it if the body is still the same."""
        body, skin = self.state.body, self.state.poser.skin
        self._tissue_for = body
        self.say("building the tissue regions (a few seconds)…")

        @reported
        def build(app: "ViewerApp") -> None:
            try:
                surfaces = tissue_surfaces(build_trunk_model(body), skin)
            except Exception:
                with app.lock:
                    app._tissue_for = None  # let the next switch-on try again
                raise
            with app.lock:
                if app.state.body is body:
                    app.scene.set_tissue(surfaces)
                    app.scene.show(app.frame)
                    app.say("tissue regions ready: bone, viscera, muscle")

        threading.Thread(target=build, args=(self,), name="tissue", daemon=True).start()

    def open_sequence(self, path: str) -> None:
        """Load a sequence for the player; a `HitogataError` if it cannot be (the page's action reports it)."""
        if not path.strip():
            raise HitogataError("sequence path: empty; allowed a .npz or .toml file or a results folder")
        with self.lock:
            poser = self.state.poser
        seq = load_sequence(path, poser)
        with self.lock:
            if self.state.poser is not poser:
                raise HitogataError(f"{path}: the body changed while loading; load it again")
            self._stop_sequence()
            self.sequence, self.clock = seq, Clock(seq.start, seq.end)
            slider = self.panels.time
            slider.min, slider.max = seq.start, max(seq.end, seq.start + 0.01)
            slider.value, slider.disabled = seq.start, False
            self.panels.sequence_info.content = (
                f"{len(seq.times)} frames, {seq.start:g}–{seq.end:g} s"
                f"{'' if seq.angles is not None else ' (no joint angles: skeleton hidden)'}"
            )
            self._show_time(seq.start)
            self.say(f"loaded {seq.source}")

    load_sequence = reported(open_sequence)

    def _show_time(self, t: float) -> None:
        seq = self.sequence
        if seq is None:
            return
        self.showing_sequence = True
        self.show(sequence_frame(self.state.poser, seq, seq.frame_at(t)))

    @reported
    def play(self) -> None:
        with self.lock:
            if self.clock is None:
                raise HitogataError("play: no sequence loaded; load one first")
            self.clock.play()
            if self._playback is None or not self._playback.is_alive():
                self._playback = threading.Thread(target=self._play_loop, name="playback", daemon=True)
                self._playback.start()

    def _play_loop(self) -> None:
        last = time.perf_counter()
        while True:
            time.sleep(PLAYBACK_TICK)
            now = time.perf_counter()
            with self.lock:
                if self.clock is None or not self.clock.playing:
                    return
                t = self.clock.advance(now - last)
                self._show_time(t)
                self.panels.time.value = round(t, 2)
            last = now

    def wait_playback(self, timeout: float = 30.0) -> bool:
        """Block until playback has reached its end (or paused) and its last frame is shown."""
        thread = self._playback
        if thread is not None:
            thread.join(timeout)
        return thread is None or not thread.is_alive()

    @reported
    def pause(self) -> None:
        with self.lock:
            if self.clock is not None:
                self.clock.pause()

    @reported
    def scrub(self, t: float) -> None:
        with self.lock:
            if self.clock is not None:
                self.clock.scrub(t)
                self._show_time(self.clock.time)

    @reported
    def back_to_muscles(self) -> None:
        with self.lock:
            self._stop_sequence()
            self.show(posed_frame(self.state.posed))

    def _stop_sequence(self) -> None:
        """Leave the sequence (posing by muscles again); it stays loaded for scrubbing."""
        self.showing_sequence = False
        if self.clock is not None:
            self.clock.pause()

    def _drop_sequence(self) -> None:
        """Forget the loaded sequence (it belongs to the body being replaced)."""
        self._stop_sequence()
        self.sequence, self.clock = None, None
        self.panels.time.disabled = True
        self.panels.sequence_info.content = "no sequence loaded"

    @reported
    def download_glb(self, client: "viser.ClientHandle") -> None:
        with self.lock:
            data = pose_glb(self.state.body, self.frame)
        client.send_file_download("hitogata-pose.glb", data, save_immediately=True)

    @reported
    def download_html(self, client: "viser.ClientHandle") -> None:
        with self.lock:
            html = snapshot_html(self.server)
        client.send_file_download("hitogata-snapshot.html", html.encode("utf-8"), save_immediately=True)

    # ------------------------------------------------------------------ lifetime

    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def wait_idle(self, timeout: float = 30.0) -> bool:
        """Block until the measurements and strain colours have caught up (tests, benchmarks)."""
        return self.measurer.wait_idle(timeout) and self.painter.wait_idle(timeout)

    def stop(self) -> None:
        with self.lock:
            self._stop_sequence()
        self.measurer.stop()
        self.painter.stop()
        self.server.stop()


def check_host(host: str) -> None:
    """A one-line error unless this machine can listen on `host` (viser would retry forever)."""
    try:
        with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET) as probe:
            probe.bind((host, 0))
    except OSError as exc:
        raise HitogataError(f"host {host!r}: cannot listen there ({exc.strerror or exc}); e.g. 127.0.0.1") from None


def serve(body: Body, host: str = "127.0.0.1", port: int = 8080,
          garment: "tuple[Garment, Fabric] | None" = None) -> ViewerApp:
    """Start a viewer of `body` on host:port (the next free port if taken); returns the running app.
    `garment`: a stretch garment and its fabric, for the pressure colour map."""
    try:
        import viser
    except ImportError:
        raise HitogataError("the viewer needs viser: pip install viser") from None
    from viser.infra import _infra

    from hitogata.viewer.origin import guard

    check_host(host)
    guard(_infra)  # only the viewer's own page may connect
    server = viser.ViserServer(host=host, port=port, label="hitogata", verbose=False)
    return ViewerApp(server, body, garment)
