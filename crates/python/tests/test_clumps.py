"""Grains that are not round from Python (docs/physics.md §11): a shaped case runs and writes
its grains' orientations; a clump added to a simulation falls as one body and shows its
orientation and long axis as arrays; bad members are refused with the argument's name."""

import json

import numpy as np
import pytest

import hopperflow as hf
from conftest import CASES

SILO = CASES / "tiny-silo.toml"
G = 9.81


def rods():
    """The tiny silo filled with 120 rods of aspect ratio 2 at the 3 mm sphere's volume (the
    beads are 0.75 d across, so the step is taken at 0.15 of their Rayleigh time)."""
    case = hf.Case.load(str(SILO))
    case["particles.count"] = 120
    case["particles.shape"] = {"kind": "rod", "aspect_ratio": 2.0}
    case["time.time_step"] = 2.5e-6
    return case


def test_a_run_of_rods_counts_grains_and_writes_their_orientations(tmp_path):
    run = hf.run(rods(), out=tmp_path / "rods", progress=False)
    summary = json.loads((run.path / "summary.json").read_text())
    orientation = summary["orientation"]
    # Every grain of the bed has a row with a unit long axis; the outlet counts grains.
    table = np.loadtxt(run.path / "orientations.csv", delimiter=",", skiprows=1)
    assert table.shape == (120, 7)
    assert np.allclose(np.linalg.norm(table[:, 4:7], axis=1), 1.0, atol=1e-12)
    assert orientation["bed"]["grains"] == 120
    crossings = np.loadtxt(run.path / "crossings.csv", delimiter=",", skiprows=1, ndmin=2)
    assert orientation["outlet"]["grains"] == len(crossings)
    # Each crossing weighs one grain: ρ (π/6) d³ of the 3 mm sphere, to the union's rounding.
    grain = 2500.0 * np.pi / 6 * 0.003**3
    assert np.allclose(crossings[:, 5], grain, rtol=1e-9)


def test_a_clump_falls_as_one_body_with_its_axes_as_arrays():
    sim = hf.Simulation.from_case(hf.Case.load(str(SILO)))
    r = 0.0015
    # A dumbbell of touching spheres, its axis turned 90° about y to stand upright.
    s = np.sqrt(0.5)
    first = sim.add_clump([[-r, 0, 0, r], [r, 0, 0, r]], [0.0, 0.0, 0.04], orientation=[0.0, s, 0.0, s])
    assert len(sim) == 2
    assert list(sim.clump_indices) == [0, 0]
    clumps = sim.clumps
    assert list(clumps["ids"]) == [first]
    assert clumps["orientations"].shape == (1, 4) and clumps["members"][0] == 2
    # Its long axis stands upright (sign arbitrary); its mass is two spheres' (touching).
    assert abs(abs(clumps["axes"][0][2]) - 1.0) < 1e-12
    assert clumps["masses"][0] == pytest.approx(2 * 2500.0 * 4 / 3 * np.pi * r**3, rel=1e-12)
    # Free fall for 400 steps: the centre of mass drops g t²/2, the members keep their
    # distance (a rigid body), to round-off.
    sim.step(400)
    t = sim.time
    z = sim.clumps["positions"][0][2]
    assert z == pytest.approx(0.04 - 0.5 * G * t * t, abs=1e-12)
    p = sim.positions
    assert np.linalg.norm(p[0] - p[1]) == pytest.approx(2 * r, rel=1e-12)
    # Removed by its centre of mass, whole, under one id.
    assert sim.remove_below(1.0) == [first]
    assert len(sim) == 0


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"members": []}, "members: a clump needs at least one member"),
        ({"members": [[0, 0, 0, 0.0]]}, "members: member 0: radius 0"),
        ({"members": [[0, 0, 0, 0.001]], "orientation": [0, 0, 0, 2.0]}, "unit quaternion"),
        ({"members": [[0, 0, 0, 0.001]], "component": 3}, "component = 3"),
    ],
)
def test_bad_clumps_are_refused_with_the_argument(kwargs, words):
    sim = hf.Simulation.from_case(hf.Case.load(str(SILO)))
    with pytest.raises(ValueError, match=words):
        sim.add_clump(position=[0.0, 0.0, 0.03], **kwargs)
    assert len(sim) == 0
