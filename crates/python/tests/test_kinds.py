"""Every container kind from Python: runs of a cylindrical silo, a box and a mixture write the
command line's bytes, and `Simulation` builds a case of any kind as a run does (the state
bits of a run's own set-up, read back from the bed it saved), steps it and shows its walls."""

import subprocess

import numpy as np
import pytest

import hopperflow as hf
from conftest import CASES, TINY

# Gravity of the cases [m/s²], along −z.
G = 9.81

# What a finished run of every kind writes besides its plots; a cylindrical silo adds
# wall_pressure.csv, a mixture composition.csv, a slab field.csv.
RUN_FILES = {
    "summary.json",
    "case.toml",
    "flow.csv",
    "crossings.csv",
    "residence.csv",
    "profiles.csv",
    "remaining.csv",
    "wall_forces.csv",
}


def written(folder):
    """The files of a run folder that must be the same bytes from any front end: all but
    timing.json (wall-clock times)."""
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file()} - {"timing.json"}


@pytest.mark.parametrize(
    "name, extra",
    [
        ("tiny-silo.toml", {"wall_pressure.csv"}),
        ("tiny-mixture.toml", {"wall_pressure.csv", "composition.csv"}),
        ("tiny-box.toml", set()),
    ],
)
def test_a_run_from_python_writes_the_command_lines_bytes(cli, tmp_path, name, extra):
    case = CASES / name
    subprocess.run(
        [str(cli), "run", str(case), "--out", str(tmp_path / "cli"), "--threads", "1", "--quiet"],
        check=True,
        capture_output=True,
    )
    # Two threads from Python, one on the command line: the bits depend on neither.
    py = hf.run(str(case), out=tmp_path / "py", threads=2, progress=False)
    files = written(py.path)
    assert files == written(tmp_path / "cli")
    assert RUN_FILES | extra <= files, sorted(files)
    for file in sorted(files):
        assert (py.path / file).read_bytes() == (tmp_path / "cli" / file).read_bytes(), file
    # Not two empty runs: the container discharged through its outlet.
    crossings = py.crossings
    assert len(crossings["time_s"]) > 20
    assert py.summary["discharged_mass"] > 0
    # N(t) starts from the whole fill and never grows: nothing comes back up the outlet.
    remaining = np.asarray(py.remaining["particles"])
    assert remaining[0] == py.case["particles.count"]
    assert np.all(np.diff(remaining) <= 0) and remaining[-1] < remaining[0]
    # Every grain of the bed has a row; those that left have their residence times, each
    # within the discharge (the last crossing after the opening bounds them all).
    residence = np.asarray(py.residence["residence_s"], dtype=float)
    left = residence[np.isfinite(residence)]
    assert len(residence) == py.summary["residence"]["grains"]
    assert len(left) == py.summary["residence"]["left"] > 20
    assert np.all(left > 0)
    if "wall_pressure.csv" in extra:
        # The settled bed presses on the cylinder's wall.
        pressure = py.wall_pressure
        settled = np.asarray(pressure["phase"]) == "settled"
        assert np.asarray(pressure["pressure"])[settled].max() > 0
    if "composition.csv" in extra:
        # Both components left the silo: each column of mass sums to a positive total.
        composition = py.composition
        for component in ["small", "large"]:
            assert np.asarray(composition[f"{component}_mass_kg"]).sum() > 0, component


# ---------------------------------------------------------------------------------------
# The containers of the Simulation tests: a case of each kind and a lattice of spheres at
# rest inside it, 10 % of a diameter apart, clear of every wall.


def stl_text(name, triangles):
    """ASCII STL of `triangles` (three vertices each); the reader computes the normals."""
    lines = [f"solid {name}"]
    for t in triangles:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {v[0]!r} {v[1]!r} {v[2]!r}" for v in t]
        lines += ["endloop", "endfacet"]
    lines.append(f"endsolid {name}")
    return "\n".join(lines) + "\n"


def quad(a, b, c, d):
    """Two triangles of the planar quadrilateral a b c d."""
    return [(a, b, c), (a, c, d)]


# The STL container: a square funnel at 45° from a 16 mm square orifice at z = 0 to 40 mm at
# z = 12 mm, then four vertical sides up to 80 mm.
MESH_HALF, OUTLET_HALF, FUNNEL_TOP, MESH_TOP = 0.02, 0.008, 0.012, 0.08


def mesh_case_file(folder):
    """Writes the STL container's two walls and its case file into `folder`; returns its path."""
    h, o, f, top = MESH_HALF, OUTLET_HALF, FUNNEL_TOP, MESH_TOP
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    funnel, sides = [], []
    for k in range(4):
        (x0, y0), (x1, y1) = corners[k], corners[(k + 1) % 4]
        funnel += quad((o * x0, o * y0, 0.0), (o * x1, o * y1, 0.0), (h * x1, h * y1, f), (h * x0, h * y0, f))
        sides += quad((h * x0, h * y0, f), (h * x1, h * y1, f), (h * x1, h * y1, top), (h * x0, h * y0, top))
    (folder / "funnel.stl").write_text(stl_text("funnel", funnel))
    (folder / "sides.stl").write_text(stl_text("sides", sides))
    text = f"""version = 1
seed = 6

[geometry]
kind = "mesh"
fill_min = [-0.017, -0.017, 0.015]
fill_max = [0.017, 0.017, {top!r}]
outlet = {{ shape = "rectangle", centre = [0.0, 0.0], size = [{2 * o!r}, {2 * o!r}] }}

[[geometry.walls]]
file = "funnel.stl"

[[geometry.walls]]
file = "sides.stl"

[particles]
count = 50
diameter = 0.003

[protocol]
settle_kinetic_energy = 1.0e-8
max_settle_time = 0.15
clog_timeout = 0.1
time_limit = 0.5

[output]
checkpoint_interval = 0.0
vtu_interval = 0.0
plots = false
"""
    path = folder / "tiny-mesh.toml"
    path.write_text(text)
    return path


def grid(counts, spacing, z0, y0=0.0):
    """Centres of a lattice of counts = (nx, ny, nz) points `spacing` apart, centred on
    x = 0 and y = y0, its lowest layer at z0."""
    nx, ny, nz = counts
    xs = (np.arange(nx) - (nx - 1) / 2) * spacing
    ys = y0 + (np.arange(ny) - (ny - 1) / 2) * spacing
    zs = z0 + np.arange(nz) * spacing
    return np.array([[x, y, z] for z in zs for y in ys for x in xs])


class Container:
    """A case of one kind, its walls' names, a lattice inside it and a test of whether a
    sphere lies inside its walls."""

    def __init__(self, case, walls, positions, radius, inside):
        self.case, self.walls, self.positions, self.inside = case, walls, positions, inside
        self.radii = np.full(len(positions), radius)


def container(kind, folder):
    if kind == "slab":
        case = hf.Case.load(str(TINY))
        z = case["geometry.thickness"]
        half = case["geometry.width"] / 2
        return Container(
            case,
            {"left", "right", "front", "back", "plate_left", "plate_right", "gate"},
            grid((10, 1, 4), 0.0033, 0.03, y0=z / 2),
            0.0015,
            lambda p, r: (np.abs(p[:, 0]) <= half - r) & (p[:, 1] >= 0) & (p[:, 1] <= z),
        )
    if kind == "cylinder":
        case = hf.Case.load(str(CASES / "tiny-silo.toml"))
        radius = case["geometry.radius"]
        return Container(
            case,
            {"cylinder", "hopper", "gate"},
            grid((5, 5, 3), 0.0033, 0.03),
            0.0015,
            lambda p, r: np.hypot(p[:, 0], p[:, 1]) <= radius - r,
        )
    if kind == "box":
        case = hf.Case.load(str(CASES / "tiny-box.toml"))
        hw, hd = case["geometry.width"] / 2, case["geometry.depth"] / 2
        return Container(
            case,
            {"left", "right", "front", "back", "plate_left", "plate_right", "gate"},
            grid((9, 5, 2), 0.0044, 0.04),
            0.002,
            lambda p, r: (np.abs(p[:, 0]) <= hw - r) & (np.abs(p[:, 1]) <= hd - r),
        )
    assert kind == "mesh"
    case = hf.Case.load(str(mesh_case_file(folder)))
    return Container(
        case,
        {"funnel", "sides", "gate"},
        grid((5, 5, 2), 0.0033, 0.03),
        0.0015,
        lambda p, r: (np.abs(p[:, 0]) <= MESH_HALF - r) & (np.abs(p[:, 1]) <= MESH_HALF - r),
    )


def test_a_mesh_case_changed_from_python_reads_its_stl_files_from_its_folder(tmp_path, monkeypatch):
    # A change validates the case again; the relative STL paths stay those of the case
    # file's folder, whatever the current folder (as for `hopperflow run FILE --set ...`).
    path = mesh_case_file(tmp_path)
    monkeypatch.chdir(tmp_path.parent)
    case = hf.Case.load(str(path))
    case["particles.count"] = 40
    assert case["particles.count"] == 40
    assert str(tmp_path / "funnel.stl") in case.to_toml()


def in_added_order(sim, ids, values):
    """Rows of `values` (as `sim` holds its particles) in the order the particles were added
    with `ids`: the engine keeps them sorted by cell."""
    row = {int(i): k for k, i in enumerate(sim.ids)}
    return values[[row[int(i)] for i in ids]]


@pytest.mark.parametrize("kind", ["slab", "cylinder", "box", "mesh"])
def test_spheres_fall_into_a_container_of_each_kind_and_out_of_its_outlet(kind, tmp_path):
    c = container(kind, tmp_path)
    sim = hf.Simulation.from_case(c.case)
    assert sim.kind == kind
    assert set(sim.walls) == c.walls
    ids = sim.add_particles(c.positions, c.radii)
    # 50 ms of free fall: no sphere reaches a wall (the lowest falls 12 mm, 20 mm short of
    # the nearest) or a neighbour (all fall alike). Velocity Verlet is exact for a constant
    # acceleration, so only round-off separates z from z0 − g t²/2: 1 nm is far above it and
    # far below the 12 mm fallen; x and y do not change by a bit.
    steps = round(0.05 / sim.time_step)
    sim.step(steps)
    t = steps * sim.time_step
    p = in_added_order(sim, ids, sim.positions)
    assert np.all(p[:, :2] == c.positions[:, :2])
    assert np.allclose(p[:, 2], c.positions[:, 2] - 0.5 * G * t * t, rtol=0, atol=1e-9)
    # 0.35 s more: the spheres have landed in the container, held by its closed gate, every
    # one inside its walls (up to the overlaps of contact, below 10 % of r: the engine's
    # guard) and lower than it started.
    sim.step(round(0.35 / sim.time_step))
    p = in_added_order(sim, ids, sim.positions)
    assert np.all(c.inside(p, 0.9 * c.radii)), p[~c.inside(p, 0.9 * c.radii)]
    assert np.all(p[:, 2] > 0.9 * c.radii)
    assert np.all(p[:, 2] < c.positions[:, 2])
    assert sim.contacts()["particle_wall"] > 0
    # The gate carries the spheres over the outlet: the force on it points down.
    force, _ = sim.wall_load(sim.walls["gate"])
    assert force[2] < 0
    # Opened, the outlet lets spheres fall through the orifice plane z = 0.
    sim.open_gate()
    assert "gate" not in sim.walls
    sim.step(round(0.2 / sim.time_step))
    assert np.count_nonzero(sim.positions[:, 2] < 0) > 5


def packing_csv(path, positions, radii, names=None):
    """A packing file: x, y, z, radius and, for a mixture, each particle's component."""
    lines = ["x,y,z,radius" + (",material" if names is not None else "")]
    for k, (p, r) in enumerate(zip(positions, radii)):
        row = [repr(float(v)) for v in (*p, r)]
        if names is not None:
            row.append(names[k])
        lines.append(",".join(row))
    path.write_text("\n".join(lines) + "\n")
    return path


def staggered(positions, spacing):
    """`positions` (a `grid`) with each vertical column raised by 0 to 2 mm: spheres dropped
    from one height all rebound in step, and a lattice can look calm at the top of its first
    rebound, in the air; staggered, they land one after another."""
    column = np.round(positions[:, :2] / spacing).astype(int)
    lift = 0.0005 * ((column[:, 0] + 2 * column[:, 1]) % 5)
    return positions + np.column_stack([np.zeros((len(positions), 2)), lift])


def packing_of(kind, folder):
    """The case file of a container of `kind` and a packing inside it: positions, radii and
    the components' indices (None for one component)."""
    if kind == "mixture":
        path = CASES / "tiny-mixture.toml"
        positions = staggered(grid((5, 5, 3), 0.0044, 0.012), 0.0044)
        # Large (r = 2 mm) and small (r = 1 mm) spheres alternate through the lattice.
        components = np.arange(len(positions)) % 2
        radii = np.where(components == 1, 0.002, 0.001)
        return path, positions, radii, components
    if kind == "box":
        positions = staggered(grid((9, 5, 2), 0.0044, 0.04), 0.0044)
        return CASES / "tiny-box.toml", positions, np.full(len(positions), 0.002), None
    assert kind == "mesh"
    positions = staggered(grid((5, 5, 2), 0.0033, 0.02), 0.0033)
    return mesh_case_file(folder), positions, np.full(len(positions), 0.0015), None


@pytest.mark.parametrize("kind", ["mixture", "box", "mesh"])
def test_a_simulation_from_a_case_steps_to_the_bits_of_the_bed_a_run_saved(cli, tmp_path, kind):
    path, positions, radii, components = packing_of(kind, tmp_path)
    names = None
    if components is not None:
        names = [["small", "large"][k] for k in components]
    packing = packing_csv(tmp_path / "packing.csv", positions, radii, names)
    # The command line's run from the packing, its bed saved when the gate opens: the
    # library's own set-up of the case (walls, materials, laws, skin), stepped by the run
    # while the spheres fall 9 to 14 mm onto the closed gate, the cone or the plates and
    # settle there (until calm, at most 0.1 s), then a short discharge.
    sets = {
        "particles.count": len(positions),
        "protocol.max_settle_time": 0.1,
        "protocol.time_limit": 0.02,
    }
    subprocess.run(
        [str(cli), "run", str(path), "--packing", str(packing), "--save-bed", str(tmp_path / "bed"),
         "--out", str(tmp_path / "run"), "--quiet"]
        + [arg for key, value in sets.items() for arg in ("--set", f"{key}={value!r}")],
        check=True,
        capture_output=True,
    )
    bed = hf.Simulation.from_bed(tmp_path / "bed")
    # Python's simulation of the same case: the packing's spheres added in file order, at
    # rest, each of its component's material, stepped as many steps as the run settled.
    case = hf.Case.load(str(path))
    case.update(sets)
    sim = hf.Simulation.from_case(case, threads=2)
    ids = sim.add_particles(positions, radii, components=components)
    # The settling is judged from 0.05 s on.
    assert bed.steps >= 0.05 / bed.time_step
    sim.step(bed.steps)
    # The same state to the bit: positions, velocities and spins, in the same order.
    assert np.array_equal(sim.ids, bed.ids)
    for name in ["positions", "velocities", "angular_velocities", "forces", "radii", "masses"]:
        assert getattr(sim, name).tobytes() == getattr(bed, name).tobytes(), name
    assert np.array_equal(sim.components, bed.components)
    assert np.array_equal(sim.materials, bed.materials)
    assert sim.time == bed.time and set(sim.walls) == set(bed.walls)
    # Not a state that any set-up would share: the spheres fell and touch the walls.
    z = in_added_order(sim, ids, sim.positions)[:, 2]
    assert np.all(z < positions[:, 2] - 0.001)
    assert sim.contacts()["particle_wall"] > 0
    if components is not None:
        assert sim.component_names == ["small", "large"]
        assert np.array_equal(in_added_order(sim, ids, sim.components), components)
        # Each component has its own material, and so its own density: a large sphere
        # weighs 8 small ones of the same material, 16 of this lighter one.
        masses = in_added_order(sim, ids, sim.masses)
        assert masses[1] / masses[0] == pytest.approx(16.0, rel=1e-12)
    # The bed goes on from Python: opened, it discharges.
    bed.open_gate()
    bed.step(round(0.1 / bed.time_step))
    assert np.count_nonzero(bed.positions[:, 2] < 0) > 0
    if kind == "mesh":
        # The bed's case names its STL files; with one gone, the bed cannot be rebuilt.
        (tmp_path / "funnel.stl").unlink()
        with pytest.raises(hf.CaseError, match="funnel.stl"):
            hf.Simulation.from_bed(tmp_path / "bed")


@pytest.mark.parametrize(
    "call, error, words",
    [
        (lambda s: s.add_particle([0, 0, 0.03], 0.001, component=2), ValueError, r"component = 2: .*0\.\.2.*small, large"),
        (lambda s: s.add_particle([0, 0, 0.03], 0.001, component=-1), ValueError, "component = -1"),
        (lambda s: s.add_particle([0, 0, 0.03], 0.001, component="large"), TypeError, None),
        (lambda s: s.add_particles([[0, 0, 0.03]], [0.001], components=[0, 1]), ValueError, "components has 2 entries"),
        (lambda s: s.add_particles([[0, 0, 0.03], [0, 0, 0.04]], [0.001, 0.001], components=[0, 5]), ValueError, "particle 1: .*component = 5"),
    ],
)
def test_bad_components_raise_value_errors_and_add_nothing(call, error, words):
    sim = hf.Simulation.from_case(hf.Case.load(str(CASES / "tiny-mixture.toml")))
    with pytest.raises(error, match=words):
        call(sim)
    assert len(sim) == 0


def test_bad_kinds_and_beds_raise_value_errors(tmp_path):
    case = hf.Case.load(str(CASES / "tiny-silo.toml"))
    # An unknown kind is refused by the case, naming the key and the kinds there are.
    with pytest.raises(ValueError, match=r"geometry\.kind.*slab.*cylinder.*box.*mesh"):
        case["geometry.kind"] = "sphere"
    with pytest.raises(ValueError, match="no saved bed there"):
        hf.Simulation.from_bed(tmp_path)
    with pytest.raises(ValueError, match="threads"):
        hf.Simulation.from_bed(tmp_path, threads=0)
    with pytest.raises(TypeError):
        hf.Simulation.from_bed(42)  # type: ignore[arg-type]  # the misuse tested
    # A file that is not a bed.
    (tmp_path / "bed.bin").write_bytes(b"not a bed")
    with pytest.raises(ValueError, match="bed.bin"):
        hf.Simulation.from_bed(tmp_path)
    # A one-component case takes component 0 only.
    sim = hf.Simulation.from_case(case)
    assert len(sim.component_names) == 1
    with pytest.raises(ValueError, match="component = 1"):
        sim.add_particle([0, 0, 0.03], 0.0015, component=1)


def test_walls_added_to_a_mixture_meet_each_material_as_the_containers_walls_do():
    # A sphere of each component dropped from rest 5 mm onto the closed gate, and a twin of
    # each dropped 5 mm onto a shelf added from Python. The container's walls are of the
    # table's steel and meet each material with its own pair; the shelf must too. The dense
    # spheres tell it: a shelf with only the wall's own interaction (the first material's
    # pair, restitution 0.3) would send its dense sphere back up at 0.094 m/s, the
    # dense-steel pair (0.4) at 0.125 m/s.
    case = hf.Case.load(str(CASES / "tiny-mixture.toml"))
    sim = hf.Simulation.from_case(case)
    shelf_z = 0.02
    sim.add_polygon([[0.006, -0.004, shelf_z], [0.014, -0.004, shelf_z], [0.014, 0.004, shelf_z], [0.006, 0.004, shelf_z]])
    radii, drop = [0.001, 0.002], 0.005
    ids = []
    for component in (0, 1):
        y, r = (-0.003, 0.003)[component], radii[component]
        # Over the gate (it closes the orifice of radius 8 mm, clear of the cone) and over
        # the shelf.
        ids.append(sim.add_particle([-0.004, y, r + drop], r, component=component))
        ids.append(sim.add_particle([0.01, y, shelf_z + r + drop], r, component=component))
    # 40 ms: each sphere has hit its floor (after 32 ms) and flies back up.
    sim.step(round(0.04 / sim.time_step))
    p = in_added_order(sim, ids, sim.positions)
    v = in_added_order(sim, ids, sim.velocities)
    for gate_row, shelf_row in [(0, 1), (2, 3)]:
        assert v[gate_row, 2] > 0.01, "rebounding"
        # Equal heights above their floors and equal velocities, but for the round-off of
        # positions 20 mm higher (ulp(0.02 m) = 3.5e-18 m a step over 16 000 steps, and the
        # Hertz force's response to it): 1e-12 m and 1e-9 m/s are far above that and far
        # below the 0.03 m/s between the two pairs.
        assert p[shelf_row, 2] - shelf_z == pytest.approx(p[gate_row, 2], rel=0, abs=1e-12)
        assert v[shelf_row, 2] == pytest.approx(v[gate_row, 2], rel=0, abs=1e-9)


def test_the_calibration_tests_load_and_refuse_bad_values_naming_the_key():
    # The two lab tests as case kinds (docs/physics.md §5.9–5.10): loaded from the shipped
    # example cases, edited like any case, and refused with the key on a bad value.
    from conftest import REPO

    heap = hf.Case.load(str(REPO / "cases" / "repose.toml"))
    assert heap["geometry.kind"] == "heap" and heap["geometry.lift_speed"] > 0
    box = hf.Case.load(str(REPO / "cases" / "draw-down.toml"))
    assert box["geometry.kind"] == "draw_down"
    assert box["geometry.slot_width"] < box["geometry.width"]
    with pytest.raises(hf.CaseError) as error:
        heap["geometry.lift_speed"] = -0.01
    assert error.value.key == "geometry.lift_speed"
