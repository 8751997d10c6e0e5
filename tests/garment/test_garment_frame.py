"""Newton stopped on what a user reads (the levels' pressures and indentations), and a motion frame's garment
started on the tissue's own surface: the same answers as Newton run to its decrement."""

from __future__ import annotations

import numpy as np
import pytest

from hitogata.garment.contact.equilibrium import settle
from hitogata.garment.contact.readings import PRINTED, LevelReader
from hitogata.garment.contact.spec import load_garment
from samples import LENGTH, SHORT_GARMENT, soft_cylinder


def test_a_reading_that_settles_stops_newton_at_the_answer_read_to_its_tolerance(monkeypatch):
    """The soft thick-walled cylinder: Newton stopped where the ring's pressure no longer changes by 0.05
    mmHg reads the pressure of Newton run on to round-off within that, in a quarter of its steps."""
    from hitogata.garment.contact import equilibrium

    body, stations, tube, start = soft_cylinder()
    arc = stations.origins[:, 2]
    reader = LevelReader.build(tube, arc, np.array([0.5 * LENGTH]), None)
    read = settle(tube, start, body, reader=reader)
    monkeypatch.setattr(equilibrium, "DECREMENT", 1e-12)
    converged = settle(tube, start, body, tolerance=1e-10)
    assert read.converged and converged.converged and 4 * read.iterations <= converged.iterations
    pressure = reader.pressures(read.garment, read.garment_force)
    assert np.abs(pressure - reader.pressures(converged.garment, converged.garment_force)).max() < PRINTED.pressure
    # the ring's balance: its tension over its radius (Laplace's law on the garment's own circle)
    tension = float(tube.membrane.tensions(read.garment)[0].mean())
    radius = float(np.linalg.norm(read.garment[:, :2], axis=1).mean())
    assert pressure[0] == pytest.approx(tension / radius, rel=0.01)
    # the rigid body's readings have no indentation: NaN, never compared
    assert np.isnan(reader.read(read.garment, read.body, read.garment_force)[1:]).all()
    assert not reader.changed(np.array([1.0, np.nan, np.nan]), np.array([1.0 + 0.5 * PRINTED.pressure, 1.0, 2.0]))
    assert reader.changed(np.array([1.0, np.nan, np.nan]), np.array([1.0 + 2 * PRINTED.pressure, np.nan, np.nan]))


@pytest.fixture(scope="module")
def sleeve(female, tmp_path_factory):
    """The short sleeve dressed on the default female's soft leg (standing)."""
    from hitogata.garment.contact.dressing import dress

    path = tmp_path_factory.mktemp("sleeve") / "sleeve.toml"
    path.write_text(SHORT_GARMENT, encoding="utf-8")
    return dress(female, load_garment(path))


@pytest.mark.slow
def test_a_garment_laid_on_the_tissue_starts_clear_of_it_and_settles_to_the_same_answer(sleeve):
    """The standing garment laid on its own tissue's surface (a motion frame's start, `onto_tissue`): every
    point where it lay or half a barrier's reach out from the tissue along its ray, no triangle through the
    tissue; a ring pushed into the tissue is found crossing; solved from the laid start, the levels read the
    standing answer to their tolerance."""
    from hitogata.garment.contact.dressing import Posture, solve
    from hitogata.garment.contact.equilibrium import DHAT
    from hitogata.garment.contact.motion import (
        ON_TISSUE_LIFT,
        ON_TISSUE_MOST,
        crossing_rings,
        onto_tissue,
        tissue_reach,
    )

    tube, tissue, nodes = sleeve.tube, sleeve.tissue, sleeve.tissue_nodes
    assert tissue is not None and nodes is not None
    coords = tube.stations.coordinates(sleeve.garment.reshape(tube.n_rings, tube.per_ring, 3))
    laid = onto_tissue(coords, tube, tissue, nodes, coords)
    reach = tissue_reach(coords, tube.stations, tissue, nodes)
    assert np.isfinite(reach).mean() > 0.95  # rays leave the surface near their station (an end ring's may not)
    hit = np.isfinite(reach)
    # the garment lay outside the tissue, about the barrier's reach along its rays (more where it bridges hollows)
    lay = np.linalg.norm(coords, axis=2)[hit] - reach[hit]
    assert 0 < lay.min() and lay.max() < 3 * DHAT
    # kept where it lay, or moved out to half a barrier's reach beyond the tissue along its ray (twice, four
    # times … that where its ring's chords still cut the tissue's ridges: one lift a ring)
    radius, out = np.linalg.norm(coords, axis=2), np.linalg.norm(laid, axis=2)
    assert (out >= radius - 1e-12).all() and (out[hit] >= reach[hit] + ON_TISSUE_LIFT - 1e-9).all()
    moved = hit & (out > radius + 1e-12)
    for ring in range(tube.n_rings):
        lift = out[ring, moved[ring]] - reach[ring, moved[ring]]
        if lift.size:
            assert lift.max() - lift.min() < 1e-9 and ON_TISSUE_LIFT - 1e-9 < lift.max() <= ON_TISSUE_MOST
            assert np.log2(lift.max() / ON_TISSUE_LIFT) == pytest.approx(round(np.log2(lift.max() / ON_TISSUE_LIFT)),
                                                                         abs=1e-6)
    placed = tube.stations.place(laid).reshape(-1, 3)
    assert crossing_rings(tube, placed, nodes, tissue.body.faces).size == 0
    pushed = laid.copy()
    middle = tube.n_rings // 2
    pushed[middle] *= 0.9  # some 4 mm into the leg
    found = crossing_rings(tube, tube.stations.place(pushed).reshape(-1, 3), nodes, tissue.body.faces)
    assert middle in found and set(found) <= {middle - 1, middle, middle + 1}
    body = sleeve.body
    again = solve(body, sleeve.spec, Posture.standing(body), sleeve.levels, sleeve.arc, sleeve.level_arc,
                  sleeve.hull_radii, tube, tissue, placed, stiffness=sleeve.barrier_stiffness, tissue_start=nodes)
    assert again.converged and again.tissue_nodes is not None
    reader = LevelReader.build(tube, sleeve.arc, sleeve.level_arc, tissue)
    before = reader.read(sleeve.garment, nodes, sleeve.garment_force)
    after = reader.read(again.garment, again.tissue_nodes, again.garment_force)
    n = len(sleeve.levels)
    # Newton's path differs; what is read agrees to twice the step's tolerance (each solve stops within one)
    assert np.abs(after[:n] - before[:n]).max() < 2 * PRINTED.pressure
    assert np.abs(after[n:] - before[n:]).max() < 2 * PRINTED.indentation



def test_a_barrier_too_weak_for_its_contacts_is_raised_and_the_ring_balances_its_tension():
    """A warm frame's κ is carried from the last frame, whose contacts may have pressed less. The soft
    thick-walled cylinder solved with a thousandth of the κ its own start sets: at that κ the ring's contacts
    close to CCD's 10 µm gap, where Newton can no longer move them (a step cut there to under its tolerance
    counted as convergence: the ring read 445 Pa against its tension's 1058 Pa over its radius; where the
    cut was to nothing, a motion's frame started cold). κ is raised where contacts keep closing and where
    CCD blocks a step (IPC's adaptive stiffness): Newton goes on to an equilibrium,
    clear of the gap, whose pressure is the ring's tension over its radius (Laplace's law) within 2 %: the ring,
    its contacts from 0.09 to 0.9 mm out, is round to 0.7 % of its radius (at the start's κ, to 0.2 %)."""
    from hitogata.garment.contact.equilibrium import CCD_GAP, STIFFEST

    body, stations, tube, start = soft_cylinder()
    reader = LevelReader.build(tube, stations.origins[:, 2], np.array([0.5 * LENGTH]), None)
    weak = 1e-3 * settle(tube, start, body, iterations=0).barrier_stiffness
    eq = settle(tube, start, body, stiffness=weak, reader=reader)
    assert eq.converged and eq.start_stiffness == weak and weak < eq.barrier_stiffness <= STIFFEST * weak
    assert eq.min_distance > 2 * CCD_GAP
    pressure = reader.pressures(eq.garment, eq.garment_force)[0]
    tension = float(tube.membrane.tensions(eq.garment)[0].mean())
    radius = float(np.linalg.norm(eq.garment[:, :2], axis=1).mean())
    assert pressure == pytest.approx(tension / radius, rel=0.02)
