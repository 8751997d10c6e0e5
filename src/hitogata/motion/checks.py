"""A scenario checked against its body before any elastic model is built.

The file's body is made (seconds, not the half minute of the model), then every
keyframe value is checked against the skeleton and muscles: names resolved
with the command line's shorthands (`knee_r.flexion`, side-less = both sides)
or refused with the closest names, angles within the joint's range and
contractions within the muscle's reach. Every message blames the user's file,
keyframe and value as written.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from hitogata.body.model import Body
from hitogata.motion.scenario import KeyframeValue, Scenario, make_body
from hitogata.dynamics.timeline import Timeline
from hitogata.errors import HitogataError
from hitogata.posing.names import resolve_dofs, resolve_muscles
from hitogata.posing.pose import Poser, poser_for

KINDS = {"contractions": "contraction", "angles": "angle", "clinical": "clinical"}


def scenario_body(scenario: Scenario) -> Body:
    """The scenario's body; a body outside the supported range blames the file's [body]."""
    try:
        return make_body(scenario.body)
    except HitogataError as err:
        raise HitogataError(f"{scenario.source}: [body]: {err}") from None


def checked_scenario(scenario: Scenario, body: Body | None = None) -> tuple[Scenario, Body]:
    """The scenario with its names resolved to the list names, and its body (`body` if given, instead
    of the scenario's [body]); or a one-line error."""
    body = scenario_body(scenario) if body is None else body
    poser = poser_for(body)
    renamed: dict[tuple[str, str], list[str]] = {}
    owner: dict[tuple[str, str], str] = {}
    for entry in scenario.entries:
        kind = KINDS[entry.table]
        names = _resolve(poser, entry, scenario.source)
        for name in names:
            first = owner.setdefault((kind, name), entry.name)
            if first != entry.name:
                raise HitogataError(f"{entry.where(scenario.source)}: {name} is also given as {first!r}; give it once")
        renamed[(kind, entry.name)] = names
        if scenario.on_limit == "raise":
            _check_value(poser, entry, names, scenario.source)
    channels = tuple(dataclasses.replace(c, name=name) for c in scenario.timeline.channels
                     for name in renamed.get((c.kind, c.name), [c.name]))
    return dataclasses.replace(scenario, timeline=Timeline(channels)), body


def _resolve(poser: Poser, entry: KeyframeValue, source: str) -> list[str]:
    where = entry.where(source)
    if entry.table != "contractions":
        return resolve_dofs(entry.name, poser.skeleton.dof_names, where)
    ms = poser.muscles
    names = resolve_muscles(entry.name, ms.names, where)
    if len(names) == 1:
        return names
    # side-less: both sides, but a midline DOF moved by both is driven by the left one (as on the command line)
    first = set(ms.dofs(ms.index(names[0])).tolist())
    return names[:1] + [n for n in names[1:] if not first & set(ms.dofs(ms.index(n)).tolist())]


def _check_value(poser: Poser, entry: KeyframeValue, names: list[str], source: str) -> None:
    sk = poser.skeleton
    if entry.table == "contractions":
        for name in names:
            try:
                poser.angles(contractions={name: entry.value}, on_limit="raise")
            except HitogataError as err:
                raise HitogataError(f"{entry.where(source)}: {err}") from None
        return
    for name in names:
        k = sk.dof_index(name)
        offset = sk.rest[k] if entry.table == "clinical" else 0.0
        low, high = offset + sk.lower[k], offset + sk.upper[k]
        if not low - 1e-9 <= entry.value <= high + 1e-9:
            frame = "clinical, 0 = anatomical position" if entry.table == "clinical" else "from the rest pose"
            side = f" ({name})" if name != entry.name else ""
            raise HitogataError(
                f"{entry.where(source)}: beyond the joint's range{side}; allowed {np.degrees(low):.1f}deg"
                f" … {np.degrees(high):.1f}deg ({frame}), or on_limit = \"clamp\" in [timeline]"
            )
