"""The GUI panel: muscle sliders by region, body shape, layers, measurements, player, export.

Widgets only: each handler passes a person's input on to an `Actions` object
(the app) and nothing else. viser calls a handler also when the server itself
sets a value (client None); those calls are the app echoing its own state
onto the widgets and are ignored here.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Any, Protocol

from hitogata.body.model import STATURE_RANGE
from hitogata.options import SEXES
from hitogata.viewer.colouring import legend
from hitogata.viewer.groups import muscle_groups, slider_label
from hitogata.viewer.state import SLIDER_STEP, PoseState

if TYPE_CHECKING:
    import viser



class Actions(Protocol):
    """What a person can ask of the viewer; `client` is who asked (for downloads and notices)."""

    def move_muscle(self, name: str, percent: float) -> None: ...
    def reset_pose(self) -> None: ...
    def rebuild_body(self, sex: str, age: float, stature_cm: float, mass_kg: float) -> None: ...
    def set_layer(self, layer: str, on: bool) -> None: ...
    def set_colour_map(self, name: str) -> None: ...
    def set_skin_opacity(self, opacity: float) -> None: ...
    def load_sequence(self, path: str) -> None: ...
    def play(self) -> None: ...
    def pause(self) -> None: ...
    def scrub(self, time: float) -> None: ...
    def back_to_muscles(self) -> None: ...
    def download_glb(self, client: "viser.ClientHandle") -> None: ...
    def download_html(self, client: "viser.ClientHandle") -> None: ...


@dataclass
class Panels:
    """The widgets the app updates."""

    message: "viser.GuiMarkdownHandle"
    measurements: "viser.GuiMarkdownHandle"
    sliders: dict[str, "viser.GuiSliderHandle"]
    sex: "viser.GuiDropdownHandle"
    age: "viser.GuiNumberHandle"
    stature: "viser.GuiNumberHandle"
    mass: "viser.GuiNumberHandle"
    rebuild: "viser.GuiButtonHandle"
    figures: "viser.GuiMarkdownHandle"
    tissue: "viser.GuiCheckboxHandle"
    colours: "viser.GuiCheckboxHandle"
    colour_map: "viser.GuiDropdownHandle"
    legend: "viser.GuiMarkdownHandle"
    sequence_path: "viser.GuiTextHandle"
    sequence_info: "viser.GuiMarkdownHandle"
    time: "viser.GuiSliderHandle"


def _move_muscle(actions: Actions, name: str, event: Any) -> None:
    actions.move_muscle(name, event.target.value)


def _set_layer(actions: Actions, layer: str, event: Any) -> None:
    actions.set_layer(layer, event.target.value)


def by_person(handler: Callable[[Any], None]) -> Callable[[Any], None]:
    """Wrap an on_update handler so that it runs only for a person's input, not server echoes."""
    def run(event: Any) -> None:
        if event.client is not None:
            handler(event)
    return run


def build_panels(gui: "viser.GuiApi", state: PoseState, body_inputs: dict[str, Any], actions: Actions,
                 colour_maps: tuple[str, ...]) -> Panels:
    """Make every widget and wire it to `actions`; body_inputs: sex, age, stature_cm, mass_kg to show;
    colour_maps: the skin's colour maps to offer (`viewer.colouring.SkinColours.maps`)."""
    message = gui.add_markdown("")
    with gui.add_folder("Measurements"):
        measurements = gui.add_markdown("measuring…")
    tabs = gui.add_tab_group()
    with tabs.add_tab("Muscles"):
        sliders = _muscle_tab(gui, state, actions)
    with tabs.add_tab("Body"):
        body_widgets = _body_tab(gui, body_inputs, actions)
    with tabs.add_tab("Layers"):
        layer_widgets = _layers_tab(gui, actions, colour_maps)
    with tabs.add_tab("Player"):
        player_widgets = _player_tab(gui, actions)
    with tabs.add_tab("Export"):
        _export_tab(gui, actions)
    return Panels(message, measurements, sliders, *body_widgets, *layer_widgets, *player_widgets)


def _muscle_tab(gui: "viser.GuiApi", state: PoseState, actions: Actions) -> dict[str, "viser.GuiSliderHandle"]:
    gui.add_markdown("Contraction, % of the muscle's rest length (+ shorter, − stretched). "
                     "A muscle moved takes over its joints; the others follow.")
    reset = gui.add_button("Reset pose")
    reset.on_click(by_person(lambda _: actions.reset_pose()))
    sliders = {}
    ms, ranges = state.muscles, state.ranges
    for title, names in muscle_groups(ms).items():
        with gui.add_folder(title, expand_by_default=False):
            for name in names:
                k = ms.index(name)
                dofs = ", ".join(ms.skeleton.dof_names[d] for d in ms.dofs(k)[:2])
                slider = gui.add_slider(
                    slider_label(name, title), min=float(ranges.low[k]), max=float(ranges.high[k]),
                    step=SLIDER_STEP, initial_value=0.0, hint=f"{name}: moves {dofs}{'…' if len(ms.dofs(k)) > 2 else ''}",
                )
                slider.on_update(by_person(partial(_move_muscle, actions, name)))
                sliders[name] = slider
    return sliders


def _body_tab(gui: "viser.GuiApi", inputs: dict[str, Any], actions: Actions) -> tuple[Any, Any, Any, Any, Any, Any]:
    lo, hi = STATURE_RANGE
    sex = gui.add_dropdown("sex", SEXES, initial_value=inputs["sex"])
    age = gui.add_number("age (years)", float(inputs["age"]), step=1.0)
    stature = gui.add_number("stature (cm)", float(inputs["stature_cm"]), step=0.5,
                             hint=f"{lo * 100:.0f}–{hi * 100:.0f} cm")
    mass = gui.add_number("mass (kg)", float(inputs["mass_kg"]), step=0.5, hint="BMI about 18–35")
    rebuild = gui.add_button("Rebuild body")
    rebuild.on_click(by_person(lambda _: actions.rebuild_body(sex.value, age.value, stature.value, mass.value)))
    figures = gui.add_markdown("")
    return sex, age, stature, mass, rebuild, figures


def _layers_tab(gui: "viser.GuiApi", actions: Actions, colour_maps: tuple[str, ...]) -> tuple[Any, Any, Any, Any]:
    checks = {
        "skin": gui.add_checkbox("skin", True),
        "skeleton": gui.add_checkbox("skeleton (65 parts)", True, hint="inside the skin: lower the skin opacity"),
        "tissue": gui.add_checkbox("tissue regions (trunk)", False,
                                   hint="nested shells: bone, viscera, muscle; built on first use (a few seconds); "
                                        "inside the skin: lower the skin opacity"),
        "strain": gui.add_checkbox("skin colours", False, hint="the colour map below, on the skin"),
    }
    colour_map = gui.add_dropdown("colour map", colour_maps, initial_value=colour_maps[0],
                                  hint="zone stretch: the fit report's zones and scale; pressure: the garment's "
                                       "(hitogata view --garment-ease … --fabric …)")
    colour_map.on_update(by_person(lambda event: actions.set_colour_map(event.target.value)))
    for layer, check in checks.items():
        check.on_update(by_person(partial(_set_layer, actions, layer)))
    opacity = gui.add_slider("skin opacity", min=0.1, max=1.0, step=0.05, initial_value=1.0)
    opacity.on_update(by_person(lambda event: actions.set_skin_opacity(event.target.value)))
    key = gui.add_markdown(legend(colour_maps[0]))
    return checks["tissue"], checks["strain"], colour_map, key


def _player_tab(gui: "viser.GuiApi", actions: Actions) -> tuple[Any, Any, Any]:
    gui.add_markdown("A sequence file (.npz: times, vertices), pose keyframes (.toml) or a results folder.")
    path = gui.add_text("path", "")
    load = gui.add_button("Load")
    load.on_click(by_person(lambda _: actions.load_sequence(path.value)))
    info = gui.add_markdown("no sequence loaded")
    time = gui.add_slider("time (s)", min=0.0, max=1.0, step=0.01, initial_value=0.0, disabled=True)
    time.on_update(by_person(lambda event: actions.scrub(event.target.value)))
    buttons = gui.add_button_group("playback", ("Play", "Pause", "Back to muscles"))
    choices = {"Play": actions.play, "Pause": actions.pause, "Back to muscles": actions.back_to_muscles}
    buttons.on_click(by_person(lambda event: choices[event.target.value]()))
    return path, info, time


def _export_tab(gui: "viser.GuiApi", actions: Actions) -> None:
    glb = gui.add_button("Download pose (GLB)", hint="the shown surface, skinned to the rig in this pose")
    glb.on_click(by_person(lambda event: actions.download_glb(event.client)))
    html = gui.add_button("Download snapshot (HTML)", hint="the 3-D scene as one file that opens without a server")
    html.on_click(by_person(lambda event: actions.download_html(event.client)))
