"""Run a scenario end to end: body → elastic model → motion → files and a short summary."""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from hitogata.body.model import Body
from hitogata.export import motion_files as files
from hitogata.dynamics.motion import BodyDynamics, Motion, MotionContact
from hitogata.skin.motion_contact import simulate
from hitogata.dynamics.quasistatic import corner_volumes
from hitogata.motion.scenario import Scenario, make_body
from hitogata.export.atomic import write_bytes_atomically
from hitogata.geometry.integrity import surface_integrity
from hitogata.geometry.offset_limit import HELD

# The skin is whole when, beyond what skinning alone does at the same pose, no neighbouring
# triangles fold and none cross, no vertex is below the floor, and the elastic displacement
# changes no faster than JUMP_SPEED: soft tissue wobbling at 3 Hz with 2 cm amplitude moves
# 0.4 m/s against its bone; a tear moves metres per second (240 mm in one 40 ms frame: 6 m/s).
# See docs/scenarios.md.
JUMP_SPEED = 1.0  # m/s


def build_dynamics(body: Body, scenario: Scenario) -> BodyDynamics:
    """The elastic model the scenario asks for, prepared for simulation (read from the disk cache when
    this body's was built before: `dynamics.model_cache`)."""
    from hitogata.dynamics.model_cache import cached_dynamics

    m = scenario.model
    return cached_dynamics(body, m.skinning, extent=m.extent, element_size=m.element_size, element=m.element,
                           n_modes=m.modes, damping_ratios=m.damping_ratios, alpha_beta=m.alpha_beta,
                           materials=m.materials)


@dataclass(frozen=True)
class Summary:
    """The headline figures of a run (SI units) and the files written."""

    title: str
    figures: dict
    files: list[str] = field(default_factory=list)

    def text(self) -> str:
        f = self.figures
        s = f["surface"]
        problems = surface_problems(s)
        lines = [
            f"{self.title}",
            f"  body: {f['body']}",
            f"  model: {f['model']}",
            "  lowest frequencies: " + ", ".join(f"{x:.2f}" for x in f["frequencies_hz"][:6])
            + f" Hz (damping ratios {f['damping_ratios'][0]:.2f}..{max(f['damping_ratios'][:6]):.2f})",
            *([f"  WARNING: the skin is not whole: {'; '.join(problems)} (figures below are not results)"]
              if problems else []),
            f"  largest skin displacement by the elastic body: {f['largest_elastic_mm']:.1f} mm "
            f"at t = {f['largest_elastic_time_s']:.2f} s on the {f['largest_elastic_part']} "
            f"(from rest, skinning included: {f['largest_total_mm']:.0f} mm)",
            (f"  skin surface: {s['folds_beyond_skinning']} folded and {s['self_intersections_beyond_skinning']} "
             f"crossing triangle pairs beyond skinning's (new since rest: {s['new_folds']}, "
             f"{s['new_self_intersections']}); {s['below_floor']} vertices below the floor "
             f"({s['below_floor_beyond_skinning']} beyond skinning's) "
             f"(lowest {s['lowest_m'] * 1e3:.1f} mm); fastest vertex {s['largest_speed_m_s']:.2f} m/s; "
             f"elastic displacement changes at most {s['largest_elastic_jump_m'] * 1e3:.1f} mm a frame "
             f"({s['largest_elastic_jump_speed_m_s']:.2f} m/s)"),
            (f"  elastic displacement held back where it would fold or cross the skin (a 40 mm mesh does "
             f"not resolve a crease): at most {f['held_back_mm']:.1f} mm at t = {f['held_back_time_s']:.2f} s, "
             f"on up to {f['held_back_vertices']} vertices a frame"),
            "  regions moved most (peak mean elastic displacement): "
            + ", ".join(f"{k} {v:.1f} mm" for k, v in f["region_motion_mm"].items()),
            f"  tissue: inverted elements at most {f['inverted_max']}; region volumes within "
            f"{f['volume_change_max_percent']:.2f}% of rest",
            *([_contact_line(f["contact"])] if "contact" in f else []),
            f"  time: model {f['seconds']['model']:.1f} s, simulation {f['seconds']['simulation']:.1f} s, "
            f"files {f['seconds']['files']:.1f} s, checks {f['seconds'].get('checks', 0.0):.1f} s",
        ]
        return "\n".join(lines) + "\n"


def _contact_line(c: dict) -> str:
    return (f"  self-contact resolved (IPC barrier frame to frame) in {c['frames_meeting']} of {c['frames']} frames "
            f"where skin meets: up to {c['free_vertices_max']} free vertices, {c['newton_iterations']} Newton "
            f"iterations in all, smallest gap {c['min_gap_mm']:.2f} mm, {c['seconds']:.1f} s "
            f"({c['seconds_per_frame_meeting']:.2f} s a frame where skin meets"
            + (f"; frames reached from rest again, their start crossing itself: {c['restarts_from_rest']}"
               if c["restarts_from_rest"] else "") + ")")


def contact_figures(c: MotionContact) -> dict:
    """What resolving a motion's self-contact took (`Motion.contact`), for the summary."""
    meeting = c.free > 0
    return {
        "frames": len(c.free),
        "frames_meeting": int(meeting.sum()),
        "free_vertices_max": int(c.free.max()),
        "newton_iterations": int(c.iterations.sum()),
        "min_gap_mm": float(c.min_distance.min() * 1e3),
        "restarts_from_rest": int(c.from_rest[1:].sum()),
        "seconds": float(c.seconds.sum()),
        "seconds_per_frame_meeting": float(c.seconds[meeting].mean()) if meeting.any() else 0.0,
    }


def figures(motion: Motion, scenario: Scenario) -> dict:
    """Largest displacements, regions that moved most, frequencies, tissue checks."""
    dyn = motion.dynamics
    model = dyn.model
    elastic_skin = np.linalg.norm(motion.skin - motion.skinned_skin, axis=2)
    frame, vertex = np.unravel_index(np.argmax(elastic_skin), elastic_skin.shape)
    total = np.linalg.norm(motion.skin - dyn.poser.body.vertices[None].astype(np.float32), axis=2)
    magnitude = np.linalg.norm(motion.elastic, axis=2)  # (F, N)
    region_motion = {}
    for k, name in enumerate(model.region_names):
        nodes = np.unique(model.elements[model.region == k])
        if len(nodes):
            region_motion[name] = float(magnitude[:, nodes].mean(axis=1).max() * 1e3)
    v0 = corner_volumes(model.points, model.elements)
    worst_change, inverted = 0.0, 0
    for x in motion.nodes:
        v = corner_volumes(x.astype(np.float64), model.elements)
        inverted = max(inverted, int((v <= 0).sum()))
        for k in range(len(model.region_names)):
            mine = model.region == k
            if mine.any():
                worst_change = max(worst_change, abs(v[mine].sum() / v0[mine].sum() - 1.0))
    body = dyn.poser.body
    surface = surface_integrity(body.vertices, body.faces, motion.skin, motion.times, motion.skinned_skin)
    return {
        "body": f"{scenario.body.sex}, stature {body.stature * 100:.1f} cm, mass {body.mass:.1f} kg",
        "model": (f"{scenario.model.extent}, {model.element}, {len(model.elements)} elements, "
                  f"{len(model.points)} nodes, {len(model.modes.eigenvalues)} modes, "
                  f"alpha {model.alpha:.3g}/s beta {model.beta:.3g} s"),
        "frequencies_hz": [float(x) for x in model.modes.frequencies],
        "damping_ratios": [float(x) for x in model.damping_ratios],
        "largest_elastic_mm": float(elastic_skin.max() * 1e3),
        "largest_elastic_time_s": float(motion.times[frame]),
        "largest_elastic_vertex": int(vertex),
        "largest_elastic_part": dyn.poser.skeleton.names[int(dyn.poser.skin.weights[vertex].toarray().argmax())],
        "largest_total_mm": float(total.max() * 1e3),
        "region_motion_mm": dict(sorted(region_motion.items(), key=lambda kv: -kv[1])),
        "inverted_max": inverted,
        "volume_change_max_percent": worst_change * 100.0,
        "frames": len(motion.times),
        "surface": surface.worst(),
        "held_back_mm": float(motion.held_back.max() * 1e3),
        "held_back_vertices": int((motion.held_back > HELD).sum(axis=1).max()),
        "held_back_time_s": float(motion.times[int(np.argmax(motion.held_back.max(axis=1)))]),
        **({"contact": contact_figures(motion.contact)} if motion.contact is not None else {}),
    }


def surface_problems(surface: dict) -> list[str]:
    """What is wrong with the skin in a run's surface figures (`SurfaceIntegrity.worst`), one phrase each."""
    out = []
    if surface["folds_beyond_skinning"]:
        out.append(f"{surface['folds_beyond_skinning']} folded triangle pairs at t = {surface['new_folds_time_s']:.2f} s")
    if surface["self_intersections_beyond_skinning"]:
        out.append(f"{surface['self_intersections_beyond_skinning']} crossing triangle pairs at "
                   f"t = {surface['new_self_intersections_time_s']:.2f} s")
    if surface["below_floor_beyond_skinning"]:
        out.append(f"{surface['below_floor_beyond_skinning']} vertices below the floor where skinning has them above")
    if surface["largest_elastic_jump_speed_m_s"] > JUMP_SPEED:
        out.append(f"a jump of {surface['largest_elastic_jump_m'] * 1e3:.0f} mm in one frame at "
                   f"t = {surface['largest_elastic_jump_time_s']:.2f} s")
    return out


def snapshot_times(motion: Motion, scenario: Scenario) -> list[float]:
    """The scenario's snapshot times, or start, the frame of largest elastic motion, and end."""
    if scenario.output.snapshots is not None:
        return list(scenario.output.snapshots)
    peak = int(np.argmax(np.linalg.norm(motion.elastic, axis=2).max(axis=1)))
    return sorted({float(motion.times[0]), float(motion.times[peak]), float(motion.times[-1])})


def _bar(label: str, enabled: bool) -> Callable[[int, int], None] | None:
    """A tqdm progress callback (done, total), or None when disabled or tqdm is missing."""
    if not enabled:
        return None
    from tqdm import tqdm

    state: dict = {}

    def update(done: int, total: int) -> None:
        bar = state.setdefault("bar", tqdm(total=total, desc=label, unit="step", leave=False, disable=None))  # None: off unless a terminal
        bar.update(done - bar.n)
        if done >= total:
            bar.close()

    return update


def run_scenario(scenario: Scenario, out: str | Path, progress: bool = False, body: Body | None = None,
                 dynamics: BodyDynamics | None = None, name: str = "motion", contact: bool = False) -> Summary:
    """Simulate a scenario and write what its [output] asks for into `out` (created if needed);
    contact: every frame's skin with its self-contact resolved (`simulate`'s)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    clock = {}
    start = time.perf_counter()
    if dynamics is None:
        dynamics = build_dynamics(body or make_body(scenario.body), scenario)
    clock["model"] = time.perf_counter() - start
    start = time.perf_counter()
    motion = simulate(dynamics, scenario.timeline, scenario.duration, scenario.rate, scenario.substeps,
                      scenario.model.gravity, scenario.on_limit, progress=_bar("simulate", progress),
                      root=scenario.root, contact=contact)
    clock["simulation"] = time.perf_counter() - start
    start = time.perf_counter()
    o = scenario.output
    written = [files.write_sequence(out / f"{name}{files.SEQUENCE_SUFFIX}", motion)]
    if "glb" in o.files:
        written.append(files.write_motion_glb(out / f"{name}.glb", motion))
    if "pvd" in o.files:
        written.append(files.write_pvd(out, motion, name))
    if "png" in o.files or "gif" in o.files:
        with files.MotionPictures(motion, o.views, o.size, scenario.title) as pictures:  # one window, frames shared
            if "png" in o.files:
                written += files.write_pictures(out, motion, snapshot_times(motion, scenario), o.views, o.size,
                                                name, pictures=pictures)
            if "gif" in o.files:
                size = (o.size[0] * 2 // 3, o.size[1] * 2 // 3)
                written.append(files.write_gif(out / f"{name}.gif", motion, o.views, size, o.gif_rate,
                                               progress=_bar("gif", progress), pictures=pictures))
    clock["files"] = time.perf_counter() - start
    start = time.perf_counter()
    figs = figures(motion, scenario)
    clock["checks"] = time.perf_counter() - start
    figs["seconds"] = clock
    summary = Summary(scenario.title, figs, [str(Path(p).relative_to(out)) for p in written])  # relative: the folder may move
    write_bytes_atomically(out / f"{name}_summary.txt", summary.text().encode())
    document = {"title": summary.title, **figs, "files": summary.files}
    write_bytes_atomically(out / f"{name}_summary.json", json.dumps(document, indent=2).encode())
    return summary
