"""The engine from Python: stepping gives the engine's bits, arrays are read-only copies,
and misuse raises Python exceptions (never a Rust panic)."""

import numpy as np
import pytest

import hopperflow as hf
from conftest import TINY
from hopperflow._testing import engine_reference

# Gravity of the engine [m/s²], along −z.
G = 9.81


def lattice(case, rows=6, cols=10):
    """Spheres on a square lattice inside the tiny hopper, 10 % apart, at rest."""
    d = case["particles.diameter"]
    xs = (np.arange(cols) - (cols - 1) / 2) * 1.1 * d
    zs = 0.01 + np.arange(rows) * 1.1 * d
    y = case["geometry.thickness"] / 2
    positions = np.array([[x, y, z] for z in zs for x in xs])
    radii = np.full(len(positions), d / 2)
    return positions, radii


def filled(threads=1):
    case = hf.Case.load(str(TINY))
    sim = hf.Simulation.from_case(case, threads=threads)
    positions, radii = lattice(case)
    ids = sim.add_particles(positions, radii)
    return case, sim, positions, radii, ids


def test_stepping_in_pieces_gives_the_engines_bits():
    case, sim, positions, radii, _ = filled()
    sim.open_gate()
    # Steps in uneven pieces from Python, against one uninterrupted run of the engine.
    for n in [1, 99, 400, 2500]:
        sim.step(n)
    ref = engine_reference(case, positions.tolist(), radii.tolist(), np.zeros_like(positions).tolist(), 3000)
    assert sim.steps == 3000
    # Bit for bit, not within a tolerance: the same operations in the same order.
    assert sim.positions.tobytes() == ref[0].tobytes()
    assert sim.velocities.tobytes() == ref[1].tobytes()
    assert sim.angular_velocities.tobytes() == ref[2].tobytes()
    # The spheres fell: every one moved down.
    assert np.all(sim.positions[:, 2] < positions[:, 2])


def test_two_threads_give_the_same_bits():
    _, one, *_ = filled(threads=1)
    _, two, *_ = filled(threads=2)
    for sim in (one, two):
        sim.open_gate()
        sim.step(2000)
    assert one.positions.tobytes() == two.positions.tobytes()
    assert one.velocities.tobytes() == two.velocities.tobytes()


def test_arrays_are_read_only_copies():
    _, sim, *_ = filled()
    before = sim.positions
    with pytest.raises(ValueError):
        before[0, 0] = 1.0
    sim.step(100)
    # A copy: stepping does not change an array read before.
    assert not np.array_equal(before, sim.positions)
    assert sim.positions.shape == (60, 3) and sim.radii.shape == (60,)
    assert sim.ids.dtype == np.uint64 and sim.materials.dtype == np.uint16
    assert len(sim) == 60


def test_add_and_remove_particles_and_walls():
    case, sim, _, _, ids = filled()
    assert sim.remove_particles([int(ids[0]), int(ids[1]), 10**9]) == 2
    assert len(sim) == 58 and int(ids[0]) not in sim.ids
    new = sim.add_particle([0.0, 0.0015, 0.08], 0.0015, velocity=[0.0, 0.0, -1.0])
    assert new in sim.ids
    walls = sim.walls
    assert {"left", "right", "front", "back", "gate"} <= set(walls)
    sim.open_gate()
    assert "gate" not in sim.walls
    # A lid above the fill, removed again.
    lid = sim.add_plane([0.0, 0.0, 0.09], [0.0, 0.0, -1.0])
    sim.translate_wall(lid, [0.0, 0.0, 0.001])
    sim.remove_wall(lid)
    sim.step(500)
    removed = sim.remove_below(-0.001)
    assert all(r not in sim.ids for r in removed)
    energy = sim.energy()
    assert energy["translational"] > 0
    assert set(sim.contacts()) == {"particle_particle", "particle_wall"}


@pytest.mark.parametrize(
    "call, error, words",
    [
        (lambda s: s.step(-1), ValueError, "n = -1"),
        (lambda s: s.step(10**12), ValueError, "n = "),
        (lambda s: s.step(1.5), TypeError, None),
        (lambda s: s.add_particle([0, 0, 0.05], -0.001), ValueError, "radius"),
        (lambda s: s.add_particle([0, 0, 0.05], float("nan")), ValueError, "radius"),
        (lambda s: s.add_particle([0, float("nan"), 0.05], 0.001), ValueError, "position"),
        (lambda s: s.add_particle([0, 0], 0.001), (TypeError, ValueError), None),
        (lambda s: s.add_particle("abc", 0.001), (TypeError, ValueError), None),
        (lambda s: s.add_particles([[0, 0, 0.05]], [0.001, 0.001]), ValueError, "radii"),
        (lambda s: s.remove_wall(999), KeyError, "wall 999"),
        (lambda s: s.remove_wall(-1), KeyError, "wall -1"),
        (lambda s: s.translate_wall(999, [0, 0, 0]), KeyError, "wall 999"),
        (lambda s: s.wall_load(999), KeyError, "wall 999"),
        (lambda s: s.wall_load(-1), KeyError, "wall -1"),
        (lambda s: s.wall_load("gate"), TypeError, None),
        (lambda s: s.add_plane([0, 0, 0], [0, 0, 0]), ValueError, "plane"),
        (lambda s: s.add_polygon([[0, 0, 0], [1, 0, 0]]), ValueError, "polygon"),
        (lambda s: s.remove_below(float("nan")), ValueError, "z"),
        (lambda s: hf.Simulation.from_case(hf.Case.paper(), threads=0), ValueError, "threads"),
        (lambda s: hf.Simulation.from_case("case.toml"), TypeError, None),  # type: ignore[arg-type]
    ],
)
def test_misuse_raises_python_exceptions(call, error, words):
    _, sim, *_ = filled()
    with pytest.raises(error, match=words):
        call(sim)


def test_removing_the_gate_twice_raises_key_error():
    _, sim, *_ = filled()
    gate = sim.walls["gate"]
    sim.open_gate()
    with pytest.raises(KeyError):
        sim.open_gate()
    # A removed wall has no load either.
    with pytest.raises(KeyError, match=f"wall {gate}"):
        sim.wall_load(gate)


def test_a_resting_sphere_presses_a_plane_with_its_weight():
    case = hf.Case.load(str(TINY))
    sim = hf.Simulation.from_case(case)
    # A shelf across the hopper, well above its floor, and one sphere just touching it,
    # midway between the faces (it touches neither: the slab is 1.01 d thick).
    shelf_z = 0.05
    shelf = sim.add_plane([0.0, 0.0, shelf_z], [0.0, 0.0, 1.0])
    r = case["particles.diameter"] / 2
    x, y = 0.01, case["geometry.thickness"] / 2
    sim.add_particle([x, y, shelf_z + r], r)
    before = sim.wall_load(shelf)
    # Before any step no load has been evaluated.
    assert np.all(before[0] == 0) and np.all(before[1] == 0)
    # 20 ms: the contact (restitution 0.2, some 10 µs long) has long damped out.
    sim.step(round(0.02 / sim.time_step))
    force, torque = sim.wall_load(shelf)
    assert force.shape == (3,) and torque.shape == (3,)
    m = sim.masses[0]
    weight = np.array([0.0, 0.0, -G * m])
    # The plane's load is the reaction of the contact force on the sphere: its total force
    # (`forces` holds the weight too) less its weight. The loads are summed in quanta of
    # 2^-32 of the weight, so they agree to that.
    contact = sim.forces[0] - weight
    assert np.allclose(force, -contact, rtol=0, atol=1e-9 * G * m)
    # At rest the sphere weighs on the plane, downward: F = m g. The residual
    # acceleration after 20 ms is far below 10^-6 g.
    assert np.allclose(force, weight, rtol=0, atol=1e-6 * G * m), (force, weight)
    # Torque about the origin [N m] of a force at the contact point (x, y, shelf_z):
    # (y F_z, −x F_z, 0), up to the sphere's rolling resistance torque at rest (none).
    expected = np.array([y * force[2], -x * force[2], 0.0])
    assert np.allclose(torque, expected, rtol=0, atol=1e-6 * G * m * r), (torque, expected)
    # The faces are not summed and read zero; the side walls, untouched, too.
    walls = sim.walls
    for name in ["front", "left"]:
        f, t = sim.wall_load(walls[name])
        assert np.all(f == 0) and np.all(t == 0), name


def test_overlapping_particles_stop_the_engine_with_run_error():
    _, sim, *_ = filled()
    # Two spheres nearly on top of each other: the engine refuses the overlap.
    sim.add_particle([0.0, 0.0015, 0.09], 0.0015)
    sim.add_particle([0.0001, 0.0015, 0.09], 0.0015)
    with pytest.raises(hf.RunError, match="overlap"):
        sim.step(10)


def test_a_particle_too_small_for_the_time_step_stops_with_run_error():
    _, sim, *_ = filled()
    # Δt = 2.5 µs is far above the Rayleigh time of a 1 µm sphere.
    sim.add_particle([0.0, 0.0015, 0.09], 1e-6)
    with pytest.raises(hf.RunError, match="Rayleigh"):
        sim.step(1)
