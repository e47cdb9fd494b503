//! The commented case file that `hopperflow init` writes: every key, its unit, its default.

// Each template is one `concat!` of its own text and the sections it shares with the others,
// so that a section common to several kinds is written once. The sections are macros, not
// constants, because `concat!` takes only literals (and macros that expand to them), and the
// templates stay `&'static str` constants. What `hopperflow init` writes is pinned byte for
// byte by the test `every_template_keeps_its_text` (crates/case/tests/suite/shipped.rs).

/// The keys at the top level, then the `[geometry]` header: the same in every template.
macro_rules! globals {
    () => {
        r#"version = 1    # case-file format version
seed = 1       # seed of the random fill, an integer in [0, 2^63 − 1]
gravity = 9.81 # g [m/s²], pointing along −z, in (0, 1000]

[geometry]
"#
    };
}

/// The particle–particle coefficients of the paper's Table 1 under their `[contact]` header
/// (the slab, box and mesh templates).
macro_rules! contact_coefficients {
    () => {
        r#"[contact]
friction = 0.5           # μ_s particle–particle [-], ≥ 0
rolling_friction = 0.01  # μ_r particle–particle [-], ≥ 0
restitution = 0.2        # e particle–particle [-], in (0, 1]
# cohesion = { law = "jkr", work_of_adhesion = 0.05 }  # dry when absent (docs/physics.md
#   §2.4–2.7): "jkr" with work_of_adhesion [J/m²]; "sjkr" with energy_density [J/m³]; or
#   "liquid_bridge" with volume [m³], surface_tension [N/m], contact_angle_deg [0, 90].
#   [wall] and [[pairs]] take the same key.
"#
    };
}

/// The contact laws' keys, briefly explained (the cylinder, box and mesh templates).
macro_rules! contact_laws {
    () => {
        r#"tangential = "mindlin_no_slip"   # "mindlin_no_slip" or "mindlin_deresiewicz"
rolling = "constant_torque"      # "constant_torque" or "epsd"
normal_clamp = false     # clamp the normal force to ≥ 0
"#
    };
}

/// The paper's particle material, the walls of that material and the contact coefficients
/// (the box and mesh templates).
macro_rules! material_wall_contact {
    () => {
        concat!(
            r#"[particles.material]
density = 2500.0         # ρ_p [kg/m³]
shear_modulus = 1.0e8    # G [Pa]; or youngs_modulus = E [Pa], not both
poisson_ratio = 0.25     # ν [-], in (−1, 0.5)

[wall]
material = "same"        # "same", "rigid", or a [wall.material] table
friction = 0.5           # μ_s particle–wall [-], ≥ 0
rolling_friction = 0.01  # μ_r particle–wall [-], ≥ 0
restitution = 0.2        # e particle–wall [-], in (0, 1]

"#,
            contact_coefficients!(),
            contact_laws!(),
        )
    };
}

/// The paper's particle material with the rolling friction of a calibration test, the walls of
/// that material, and the contact laws (the heap and draw-down templates).
macro_rules! calibration_material {
    () => {
        concat!(
            r#"[particles.material]
density = 2500.0         # ρ_p [kg/m³]
shear_modulus = 1.0e8    # G [Pa]; or youngs_modulus = E [Pa], not both
poisson_ratio = 0.25     # ν [-], in (−1, 0.5)

# The rolling friction is what a calibration tunes first, with the sliding friction and the
# cohesion. 0.1 stands a heap of spheres at about 17° here; the paper's 0.01 lets spheres roll
# away over the smooth plate and floor (a heap of about 3°). The walls' own rolling friction
# stands for the roughness of the lab's base: raise it to model a base roughened with glued
# grains.
[wall]
material = "same"        # "same", "rigid", or a [wall.material] table
friction = 0.5           # μ_s particle–wall [-], ≥ 0
rolling_friction = 0.1   # μ_r particle–wall [-], ≥ 0
restitution = 0.2        # e particle–wall [-], in (0, 1]

[contact]
friction = 0.5           # μ_s particle–particle [-], ≥ 0
rolling_friction = 0.1   # μ_r particle–particle [-], ≥ 0
restitution = 0.2        # e particle–particle [-], in (0, 1]
# cohesion = { law = "jkr", work_of_adhesion = 0.05 }  # dry when absent (docs/physics.md
#   §2.4–2.7): "jkr" with work_of_adhesion [J/m²]; "sjkr" with energy_density [J/m³]; or
#   "liquid_bridge" with volume [m³], surface_tension [N/m], contact_angle_deg [0, 90].
#   [wall] and [[pairs]] take the same key.
"#,
            contact_laws!(),
        )
    };
}

/// The `[protocol]` header and the settling keys (every template).
macro_rules! settling {
    () => {
        r#"[protocol]
settle_kinetic_energy = 1.0e-9  # [J], mean kinetic energy per particle below which the fill is settled
max_settle_time = 3.0    # [s], longest simulated settling time
"#
    };
}

/// The outlet-crossing check and the start of the steady window (every template).
macro_rules! steady_window {
    () => {
        r#"crossing_check_interval = 10  # [steps] between outlet-crossing checks, in [1, 100]
steady_start_fraction = 0.15  # [-], steady window starts when this fraction of the fill has left
"#
    };
}

/// The end of `[measure]` and the start of `[output]`, without VTU snapshots (the cylinder,
/// box and mesh templates).
macro_rules! measure_end_3d {
    () => {
        concat!(
            steady_window!(),
            r#"steady_end_fraction = 0.7     # [-], and ends at this fraction

[output]
vtu_interval = 0.0       # [s], time between VTU particle snapshots; 0 writes none
"#,
        )
    };
}

/// A case file holding the paper's base case with every key explained.
///
/// Keys whose default depends on another key (on the particle diameter or the hopper
/// height) and keys that are alternatives to another key are shown commented out, so
/// that the template reads back to exactly [`super::Case::paper_base`] and stays right
/// when the user changes the diameter.
pub const CASE_TEMPLATE: &str = concat!(
    r#"# hopperflow case file.
#
# Every value is in SI units (m, kg, s, Pa, J), except angles, which are in degrees and
# carry `_deg` in their key. The values below are the defaults: the base case of
# Fan et al. (2023), Powder Technology 429, 118964, Table 1 (flat bottom, D = 30 mm,
# centred outlet, 3000 spheres of 3 mm). Delete any key to use its default.
# Check a file with `hopperflow check FILE`; override a key on the command line with
# `hopperflow run FILE --set geometry.outlet_width=0.045`.

"#,
    globals!(),
    r#"# kind = "slab"          # "slab" (this hopper, the default), "cylinder" (a silo), "box" (a
#                        # rectangular silo) or "mesh" (your STL walls); `hopperflow init
#                        # --kind cylinder|box|mesh` writes a commented template of each
# Coordinates: x from the hopper axis, z up from the outlet plane, y across the slab.
width = 0.1              # L [m], distance between the side walls
height = 0.4             # H [m], height of the side walls above the outlet plane
thickness = 0.00303      # Z [m], slab thickness; 1.01 d is quasi-2D, several d is a 3D hopper
outlet_width = 0.03      # D [m], must be < L and ≥ 3 particle diameters
hopper_angle_deg = 90.0  # α [°], bottom plates from the vertical, in (0, 90]; 90 = flat bottom
# Outlet position: give at most one of the two; without either the outlet is centred.
# With e + s = (L − D)/2 the outlet centre is at x_c = −e (toward the left wall for e > 0).
# outlet_gap = 0.035     # s [m], gap between the left wall and the outlet's left edge, 0 ≤ s ≤ L − D
# outlet_offset = 0.0    # e [m], offset of the outlet centre from the axis, |e| ≤ (L − D)/2

# Several materials, and the contact coefficients of each pair (docs/physics.md §1.2), in
# place of [particles.material] and the coefficients of [contact] and [wall]: particles,
# components and walls then name their material. A pair not listed is mixed from the two
# self-pairs (e = √(e_aa e_bb); μ_s and μ_r harmonic means). cases/README.md has the
# benchmark's table (Dosta et al. 2024).
# [materials.M1]         # one table per material; names are letters, digits, _ or -
# density = 2500.0       # ρ [kg/m³], > 0
# youngs_modulus = 1.0e9 # E [Pa], > 0; or shear_modulus = G [Pa]
# poisson_ratio = 0.2    # ν [-], in (−1, 0.5)
# [[pairs]]              # one entry per pair, each pair once
# materials = ["M1", "M1"]  # the two materials, either order; a name twice is a material with itself
# restitution = 0.5      # e [-], in (0, 1]
# friction = 0.3         # μ_s [-], ≥ 0
# rolling_friction = 0.0 # μ_r [-], ≥ 0; default 0
# cohesion = { law = "sjkr", energy_density = 3.0e5 }  # optional, as in [contact]

[particles]
count = 3000             # N, number of particles; they must fit below H (area fraction ≤ 0.885)
diameter = 0.003         # d [m], monodisperse diameter
# coarse_graining = 1.0 # κ [-] in [1, 20]: parcels of κ d, each for κ³ grains (docs/physics.md §2.8)
# shape = { kind = "rod", aspect_ratio = 2.0 } # grains as rigid clumps of spheres, in 3D silos only: "rod" (aspect_ratio, beads), "spheres" (spheres = [{ centre, radius }]) or "stl" (file, cells, shortfall); `diameter` is then the equal-volume diameter (docs/physics.md §11.7)
# Instead of `diameter`, a size distribution (number-weighted), one of:
# [particles.size_distribution]
# kind = "uniform"       # min [m], max [m]
# min = 0.0027
# max = 0.0033
# kind = "normal"        # mean [m], std_dev [m], optional min/max [m] (default mean ± 3 std_dev)
# kind = "discrete"      # diameters = [m, ...], fractions = [number fractions summing to 1]
# material = "M1"        # instead of [particles.material]: a [materials] entry
# Instead of `diameter`, a mixture: components, each with its size, material and fraction.
# fraction_by = "number" # what the fractions count: "number" (default) or "mass"
# [[particles.components]]
# name = "small"         # heads its columns of composition.csv; default c1, c2, ...
# diameter = 0.002       # [m], or a [particles.components.size_distribution] table
# material = "M1"        # a [materials] entry; default: particles.material
# fraction = 0.5         # [-], in [0, 1]; the components' fractions sum to 1

[particles.material]
density = 2500.0         # ρ_p [kg/m³]
shear_modulus = 1.0e8    # G [Pa]
poisson_ratio = 0.25     # ν [-], in (−1, 0.5)

[wall]
material = "same"        # "same" (particle material), "rigid", a [materials] entry (its
                         # [[pairs]] then give the coefficients below), or a [wall.material]
                         # table with density [kg/m³], shear_modulus [Pa], poisson_ratio [-]
friction = 0.5           # μ_s particle–wall [-], ≥ 0 (applies to front and back walls too)
rolling_friction = 0.01  # μ_r particle–wall [-], ≥ 0
restitution = 0.2        # e particle–wall [-], in (0, 1]

"#,
    contact_coefficients!(),
    r#"tangential = "mindlin_no_slip"   # "mindlin_no_slip" (EDEM/LIGGGHTS) or "mindlin_deresiewicz" (paper Eq. 7, corrected)
rolling = "constant_torque"      # "constant_torque" (paper Eq. 8) or "epsd"
normal_clamp = false     # clamp the normal force to ≥ 0 (the paper's Eq. 6 does not)

[time]
time_step = 2.5e-6       # Δt [s], at most 0.2 Rayleigh times; 2.5e-6 s = 0.097 t_R for Table 1
# rayleigh_fraction = 0.097  # alternative to time_step: Δt as a fraction of the Rayleigh time, in (0, 0.2]

"#,
    settling!(),
    r#"fill_bottom = 0.0        # [m], bottom of the insertion region above the outlet plane
# fill_top = 0.4         # [m], top of the insertion region; default H
fill_speed = 1.0         # [m/s], downward speed of inserted particles, ≥ 0
# deletion_depth = 0.015 # [m], particles this far below the outlet are removed; default 5 d, ≥ d
clog_timeout = 0.3       # [s], no particle leaving for this long means the flow stopped
time_limit = 20.0        # [s], longest simulated discharge after the gate opens
stop_fraction = 1.0      # [-], stop once this fraction of the fill's mass has left and the steady window is complete, in [steady_end_fraction, 1]

[measure]
rate_bin_width = 0.02    # [s], time bins of the discharge rate W(t), ≥ Δt
# x_bin_width = 0.0015   # [m], x-bins of v(x) and φ(x); default d/2, ≤ D
# strip_height = 0.003   # [m], height h of the outlet strip for φ(x); default d
frame_interval = 0.001   # [s], time between snapshot frames, ≥ Δt
"#,
    steady_window!(),
    r#"steady_end_fraction = 0.7     # [-], and ends at this fraction; 0 ≤ start < end ≤ stop_fraction ≤ 1

[output]
vtu_interval = 0.1       # [s], time between VTU particle snapshots (particles.pvd); 0 writes none
checkpoint_interval = 1.0  # [s], simulated time between checkpoints; 0 writes none
plots = true             # draw the per-case plots
"#,
);

/// A case file of a cylindrical silo with every key explained (`hopperflow init --kind
/// cylinder`): the benchmark silo of Dosta et al. (2024) with its large orifice, reduced to
/// 20 000 spheres of its material M1 in steel walls.
pub const CYLINDER_TEMPLATE: &str = concat!(
    r#"# hopperflow case file: a cylindrical silo.
#
# Every value is in SI units (m, kg, s, Pa, J), except angles, which are in degrees and
# carry `_deg` in their key. The values below are the open DEM benchmark silo of Dosta et al.
# (2024), Computer Physics Communications 296, 109066, with its large orifice and material M1,
# reduced to 20 000 spheres (the benchmark fills 100 000). Check a file with
# `hopperflow check FILE`; override a key with `--set geometry.outlet_diameter=0.04`.

"#,
    globals!(),
    r#"kind = "cylinder"
# Coordinates: z up from the orifice plane z = 0, the silo's axis on z (x = y = 0).
radius = 0.1             # R [m], inner radius of the cylinder
height = 0.2354          # H [m], top of the cylinder above the orifice plane
outlet_diameter = 0.06   # D [m], the circular orifice; ≥ 3 particle diameters, |e| + D/2 < R
hopper_angle_deg = 45.0  # θ [°], the cone's half-angle from the vertical, in (0, 90]; 90 = flat bottom
outlet_offset = 0.0      # e [m], the orifice centre's offset along x; flat bottom only
walls = "smooth"         # "smooth" (exact cylinder and cone) or "meshed" (triangle meshes)
mesh_segments = 96       # segments around the axis of meshed walls and of the orifice's polygon, in [12, 4096]

[particles]
count = 20000            # N; they must fit below H at volume fraction 0.64
diameter = 0.004         # d [m], or a [particles.size_distribution] as in `hopperflow init`
# coarse_graining = 1.0 # κ [-] in [1, 20]: parcels of κ d, each for κ³ grains (docs/physics.md §2.8)
# shape = { kind = "rod", aspect_ratio = 2.0 } # grains as rigid clumps of spheres: "rod" (aspect_ratio, beads), "spheres" (spheres = [{ centre, radius }]) or "stl" (file, cells, shortfall); `diameter` is then the equal-volume diameter (docs/physics.md §11.7)
# A mixture instead of `diameter`: [[particles.components]], each with a diameter, a
# material and a fraction, and particles.fraction_by = "number" or "mass"; named materials
# and their pairs in [materials.NAME] and [[pairs]]. `hopperflow init` lists the keys, and
# cases/README.md gives this benchmark's table of M1, M2 and steel.

[particles.material]     # M1
density = 2500.0         # ρ_p [kg/m³]
youngs_modulus = 1.0e9   # E [Pa]; or shear_modulus = G [Pa], not both
poisson_ratio = 0.2      # ν [-], in (−1, 0.5)

[wall]                   # steel walls and the M1–steel pair
friction = 0.2           # μ_s particle–wall [-], ≥ 0
rolling_friction = 0.0   # μ_r particle–wall [-], ≥ 0
restitution = 0.4        # e particle–wall [-], in (0, 1]

[wall.material]          # or material = "same" / "rigid" / a [materials] name instead of this table
density = 7200.0         # [kg/m³]
youngs_modulus = 210.0e9 # E [Pa]
poisson_ratio = 0.2      # ν [-]

[contact]                # the M1–M1 pair
friction = 0.3           # μ_s particle–particle [-], ≥ 0
rolling_friction = 0.0   # μ_r particle–particle [-], ≥ 0
restitution = 0.5        # e particle–particle [-], in (0, 1]
# cohesion = { law = "jkr", work_of_adhesion = 0.05 }  # dry when absent: "jkr", "sjkr" or
#   "liquid_bridge", as `hopperflow init` explains (docs/physics.md §2.4–2.7); [wall] too
"#,
    contact_laws!(),
    r#"
[time]
time_step = 1.5e-6       # Δt [s], at most 0.2 Rayleigh times (the benchmark's for M1)

"#,
    settling!(),
    r#"fill_bottom = 0.0        # [m], bottom of the insertion region above the orifice plane
# fill_top = 0.2354      # [m], top of the insertion region; default H
fill_speed = 1.0         # [m/s], downward speed of inserted particles, ≥ 0
deletion_depth = 0.02    # [m], particles this far below the orifice are removed (the benchmark's)
clog_timeout = 0.3       # [s], no particle leaving for this long means the flow stopped
time_limit = 5.0         # [s], longest simulated discharge after the gate opens
stop_fraction = 1.0      # [-], stop once this fraction of the fill has left and the steady window is complete
wall_slip = 0.0          # [m], after settling the side walls slip up past the bed by this much, then it settles again: wall friction mobilised upward (Janssen's filling state, docs/physics.md §7.7); in [0, d_min/2], 0 = off

[measure]
rate_bin_width = 0.01    # [s], time bins of W(t) and the samples of N(t) (remaining.csv)
# x_bin_width = 0.002    # [m], width of the annuli of v(r) and φ(r); default d/2, ≤ D
# strip_height = 0.004   # [m], height h of the slab at the orifice for φ(r); default d
frame_interval = 0.001   # [s], time between the frames that measure φ(r), ≥ Δt
"#,
    measure_end_3d!(),
    r#"checkpoint_interval = 0.25  # [s], simulated time between checkpoints; 0 writes none
plots = true             # draw the plots and the frames of a vertical cut through the axis
"#,
);

/// A case file of a rectangular silo with every key explained (`hopperflow init --kind box`):
/// a box 100 mm × 50 mm with a 60° wedge over a 20 mm slot, 4000 spheres of the paper's
/// material.
pub const BOX_TEMPLATE: &str = concat!(
    r#"# hopperflow case file: a rectangular silo.
#
# Every value is in SI units (m, kg, s, Pa, J), except angles, which are in degrees and
# carry `_deg` in their key. A box W × B above a wedge of two plates meeting a slot that spans
# the depth, a pyramid of four plates narrowing to a square orifice, or a flat bottom; the
# spheres are those of Fan et al. (2023), Table 1, 3 mm. Check a file with
# `hopperflow check FILE`; override a key with `--set geometry.outlet_width=0.025`.

"#,
    globals!(),
    r#"kind = "box"
# Coordinates: z up from the orifice plane z = 0, the box centred on the z axis:
# x in [−W/2, W/2], y in [−B/2, B/2]. Frames show the vertical cut through y = 0.
width = 0.1              # W [m], along x
depth = 0.05             # B [m], along y; ≥ the largest particle diameter
height = 0.2             # H [m], top of the walls above the orifice plane
outlet = "slot"          # "slot" (D wide in x, across the whole depth; a wedge of two plates) or
                         # "square" (side D; a pyramid of four plates)
outlet_width = 0.02      # D [m]; ≥ 3 particle diameters, |e| + D/2 < W/2, and D < B for a square
hopper_angle_deg = 60.0  # α [°], the plates from the vertical, in (0, 90]; 90 = flat bottom
outlet_offset = 0.0      # e [m], x of the orifice centre; flat bottom only
walls = "smooth"         # "smooth" (exact planar polygons) or "meshed" (each wall as triangles)

[particles]
count = 4000             # N; they must fit below H at volume fraction 0.64
diameter = 0.003         # d [m], or a [particles.size_distribution] as in `hopperflow init`

"#,
    material_wall_contact!(),
    r#"
[time]
time_step = 2.5e-6       # Δt [s], at most 0.2 Rayleigh times; or rayleigh_fraction = 0.097

"#,
    settling!(),
    r#"fill_bottom = 0.0        # [m], bottom of the insertion region above the orifice plane
# fill_top = 0.2         # [m], top of the insertion region; default H
fill_speed = 1.0         # [m/s], downward speed of inserted particles, ≥ 0
# deletion_depth = 0.015 # [m], particles this far below the orifice are removed; default 5 d
clog_timeout = 0.3       # [s], no particle leaving for this long means the flow stopped
time_limit = 10.0        # [s], longest simulated discharge after the gate opens
stop_fraction = 1.0      # [-], stop once this fraction of the fill has left and the steady window is complete
wall_slip = 0.0          # [m], after settling the side walls slip up past the bed by this much, then it settles again: wall friction mobilised upward (Janssen's filling state, docs/physics.md §7.7); in [0, d_min/2], 0 = off

[measure]
rate_bin_width = 0.02    # [s], time bins of W(t) and the samples of N(t) (remaining.csv)
# x_bin_width = 0.0015   # [m], x-bins of the profiles v(x) and φ(x) across the orifice; default d/2, ≤ D
# strip_height = 0.003   # [m], not used by a box (its φ(x) comes from the crossings)
frame_interval = 0.001   # [s], time between snapshot frames, ≥ Δt
"#,
    measure_end_3d!(),
    r#"checkpoint_interval = 0.5  # [s], simulated time between checkpoints; 0 writes none
plots = true             # draw the plots and the frames of a vertical cut through y = 0
"#,
);

/// A case file of STL walls with every key explained (`hopperflow init --kind mesh`): a
/// conical silo given as two STL files in millimetres, which `hopperflow init FILE --kind mesh`
/// writes beside FILE ([`template_files`]).
pub const MESH_TEMPLATE: &str = concat!(
    r#"# hopperflow case file: a container of your own STL walls.
#
# Every value is in SI units (m, kg, s, Pa, J), except angles, which are in degrees and
# carry `_deg` in their key. The walls are STL files (ASCII or binary), each mapped to metres
# by scale, then rotation, then translation. `hopperflow init FILE --kind mesh` writes the two
# files named below beside FILE: a silo of radius 50 mm with a 45° cone to a 20 mm orifice,
# in millimetres. Check a file with `hopperflow check FILE`.
#
# Conventions: z is vertical (gravity along −z) and z = 0 is the orifice plane. The outlet
# below lies in that plane: the crossings are counted there, and a gate (the outlet's shape as
# a polygon at z = 0) closes it until the fill has settled; the walls must leave it open and
# stand above it. Particles are poured into the fill box, which must lie inside the walls:
# nothing can tell the inside of an open mesh, so only a box that cuts a triangle is refused.

"#,
    globals!(),
    r#"kind = "mesh"
fill_min = [-0.03, -0.03, 0.05]  # [m], lower corner of the fill box; z ≥ 0
fill_max = [0.03, 0.03, 0.2]     # [m], upper corner; its z is the case's H (the default fill_top)
outlet = { shape = "disc", centre = [0.0, 0.0], radius = 0.01, segments = 96 }
# outlet = { shape = "rectangle", centre = [0.0, 0.0], size = [0.02, 0.03] }  # sides along x, y [m]
# A disc's gate is the regular polygon of `segments` sides (in [12, 4096]) circumscribing it.
# The orifice must be ≥ 3 particle diameters across (a disc's diameter, a rectangle's sides).

[[geometry.walls]]       # one table per STL file, at most 64
name = "cylinder"        # the wall's name in wall_forces.csv; default: the file's stem
file = "silo_wall.stl"   # relative to this file's folder; the resolved case holds it absolute
# sha256 = "…"           # the file's SHA-256; when given, a changed file is refused
scale = 0.001            # [m per file unit]: 0.001 for millimetres
rotate_axis = [0.0, 0.0, 1.0]  # rotation axis (any length, not zero), applied after the scale
rotate_deg = 0.0         # [°], rotation about the axis (right-hand rule)
translate = [0.0, 0.0, 0.0]    # [m], applied last

[[geometry.walls]]
name = "cone"
file = "silo_cone.stl"
scale = 0.001

[particles]
count = 2000             # N
diameter = 0.004         # d [m], or a [particles.size_distribution] as in `hopperflow init`

"#,
    material_wall_contact!(),
    r#"
[time]
time_step = 2.5e-6       # Δt [s], at most 0.2 Rayleigh times; or rayleigh_fraction

"#,
    settling!(),
    r#"fill_bottom = 0.0        # [m], bottom of the insertion band (inside the fill box)
# fill_top = 0.2         # [m], top of the insertion band; default H, the fill box's top
fill_speed = 1.0         # [m/s], downward speed of inserted particles, ≥ 0
# deletion_depth = 0.02  # [m], particles this far below the orifice plane are removed; default 5 d
clog_timeout = 0.3       # [s], no particle leaving for this long means the flow stopped
time_limit = 10.0        # [s], longest simulated discharge after the gate opens
stop_fraction = 1.0      # [-], stop once this fraction of the fill has left and the steady window is complete

[measure]
rate_bin_width = 0.02    # [s], time bins of W(t) and the samples of N(t) (remaining.csv)
# x_bin_width = 0.002    # [m], annuli of v(r), φ(r) (disc) or x-bins of v(x), φ(x) (rectangle); default d/2
# strip_height = 0.004   # [m], height of the slab at the orifice for a disc's φ(r); default d
frame_interval = 0.001   # [s], time between the frames that measure φ(r), ≥ Δt
"#,
    measure_end_3d!(),
    r#"checkpoint_interval = 0.5  # [s], simulated time between checkpoints; 0 writes none
plots = true             # draw the plots and the frames of a vertical cut through the outlet's centre
"#,
);

/// A case file of the angle-of-repose test with every key explained (`hopperflow init --kind
/// heap`): a cylinder of 40 mm inner diameter filled with 2000 spheres of the paper's material
/// with a rolling friction of 0.1, lifted off a plate at 50 mm/s.
pub const HEAP_TEMPLATE: &str = concat!(
    r#"# hopperflow case file: the angle of repose of a heap from a lifted cylinder.
#
# Every value is in SI units (m, kg, s, Pa, J), except angles, which are in degrees and
# carry `_deg` in their key. A cylinder open at both ends stands on a round plate; it is
# filled, the fill settles, and the cylinder is lifted at lift_speed: the material flows out
# under its edge and forms a heap (Roessler & Katterfeld 2018, 2019). Once its lower edge has
# cleared the material the cylinder is removed; grains rolling off the plate fall and are
# removed. The run ends when the heap is at rest (settle_kinetic_energy) or at time_limit.
# summary.json's `repose` holds the angle fitted to the heap's flanks with its error
# (docs/physics.md §7.10); heap_surface.csv the surface it was fitted to.
# Check a file with `hopperflow check FILE`; override a key with
# `--set contact.rolling_friction=0.1`.

"#,
    globals!(),
    r#"kind = "heap"
# Coordinates: z up from the plate's top face z = 0, the cylinder and the plate on the z axis.
cylinder_radius = 0.02   # R_c [m], inner radius of the cylinder; 2 R_c ≥ 5 particle diameters
height = 0.08            # H [m], height of the cylinder; the fill is poured below it
plate_radius = 0.06      # R_p [m], radius of the base plate, ≥ R_c + d; the heap of 2000 spheres
                         # of 3 mm fits on it down to about 17°: a smaller plate makes a
                         # fixed-base heap, whose toe spills over the edge
lift_speed = 0.05        # [m/s], the cylinder's lifting speed, in (0, 1]

[particles]
count = 2000             # N; they must fit in the cylinder below H at volume fraction 0.64
diameter = 0.003         # d [m], or a [particles.size_distribution] as in `hopperflow init`

"#,
    calibration_material!(),
    r#"
[time]
time_step = 4.0e-6       # Δt [s], at most 0.2 Rayleigh times: 0.155 t_R for these spheres, a
                         # larger step than the paper's 2.5e-6 s (0.097 t_R), for a cheap test

"#,
    settling!(),
    r#"fill_bottom = 0.0        # [m], bottom of the insertion region above the plate
# fill_top = 0.08        # [m], top of the insertion region; default H
fill_speed = 1.0         # [m/s], downward speed of inserted particles, ≥ 0
# deletion_depth = 0.015 # [m], grains this far below the plate are removed; default 5 d, ≥ d
time_limit = 5.0         # [s], longest simulated time from the start of the lift
# Not used by the heap, which has no outlet (accepted, and written back, at their defaults):
# clog_timeout = 0.3     # [s]
# stop_fraction = 1.0    # [-]
# wall_slip = 0.0        # [m], must stay 0: the heap's cylinder is lifted, not slipped

# [measure]              # not used by the heap either: the surface is binned one mean
# rate_bin_width = 0.02  # diameter wide (docs/physics.md §7.10)
# x_bin_width = 0.0015
# strip_height = 0.003
# frame_interval = 0.001
# crossing_check_interval = 10
# steady_start_fraction = 0.15
# steady_end_fraction = 0.7

[output]
vtu_interval = 0.0       # [s], time between VTU particle snapshots; 0 writes none
checkpoint_interval = 0.0  # [s], simulated time between checkpoints; 0 writes none
plots = true             # draw the plots and the frames of a vertical cut through the axis
"#,
);

/// A case file of the draw-down test with every key explained (`hopperflow init --kind
/// draw-down`): a box 100 mm × 30 mm over a 20 mm slot, 3000 spheres of the paper's material
/// with a rolling friction of 0.1.
pub const DRAW_DOWN_TEMPLATE: &str = concat!(
    r#"# hopperflow case file: the draw-down test.
#
# Every value is in SI units (m, kg, s, Pa, J), except angles, which are in degrees and
# carry `_deg` in their key. A box W × B with a flat floor and a slot D wide across its whole
# depth in the middle; the fill settles, the slot opens, and the material discharges until the
# flow stops: what stays on the two shelves beside the slot slopes at the drained angle of
# repose (Grima & Wypych 2011; Coetzee 2017). summary.json holds the discharge rate W and,
# in `draw_down`, the left and right shelf angles fitted to the surface left behind, their
# mean and its error (docs/physics.md §7.11); shelf_surface.csv the surface they were fitted
# to. Check a file with `hopperflow check FILE`; override a key with
# `--set geometry.slot_width=0.025`.

"#,
    globals!(),
    r#"kind = "draw_down"
# Coordinates: z up from the floor z = 0, the box centred on the z axis: x in [−W/2, W/2],
# y in [−B/2, B/2], the slot x in [−D/2, D/2]. Frames show the vertical cut through y = 0.
width = 0.1              # W [m], along x
depth = 0.03             # B [m], along y; ≥ the largest particle diameter
height = 0.1             # H [m], top of the walls above the floor
slot_width = 0.02        # D [m], along x; ≥ 3 particle diameters, and each shelf (W − D)/2
                         # ≥ 3 particle diameters
walls = "smooth"         # "smooth" (exact planar polygons) or "meshed" (each wall as triangles)

[particles]
count = 3000             # N; they must fit below H at volume fraction 0.64
diameter = 0.003         # d [m], or a [particles.size_distribution] as in `hopperflow init`

"#,
    calibration_material!(),
    r#"
[time]
time_step = 4.0e-6       # Δt [s], at most 0.2 Rayleigh times: 0.155 t_R for these spheres, a
                         # larger step than the paper's 2.5e-6 s (0.097 t_R), for a cheap test

"#,
    settling!(),
    r#"fill_bottom = 0.0        # [m], bottom of the insertion region above the floor
# fill_top = 0.1         # [m], top of the insertion region; default H
fill_speed = 1.0         # [m/s], downward speed of inserted particles, ≥ 0
# deletion_depth = 0.015 # [m], particles this far below the slot are removed; default 5 d
clog_timeout = 0.3       # [s], no particle leaving for this long means the flow stopped: the
                         # test ends `drained`, or `clogged` when an arch spans the slot
time_limit = 10.0        # [s], longest simulated discharge after the slot opens
stop_fraction = 1.0      # [-], keep 1: the test runs until the flow stops by itself

[measure]
rate_bin_width = 0.02    # [s], time bins of W(t) and the samples of N(t) (remaining.csv)
# x_bin_width = 0.0015   # [m], x-bins of the profiles v(x) and φ(x) across the slot; default d/2, ≤ D
# strip_height = 0.003   # [m], not used by a draw-down box (its φ(x) comes from the crossings)
frame_interval = 0.001   # [s], time between snapshot frames, ≥ Δt
"#,
    measure_end_3d!(),
    r#"checkpoint_interval = 0.0  # [s], simulated time between checkpoints; 0 writes none
plots = true             # draw the plots and the frames of a vertical cut through y = 0
"#,
);

/// The commented template of a geometry kind, by its `geometry.kind` name (the draw-down
/// test also by the command line's spelling, `draw-down`).
pub fn template(kind: &str) -> Option<&'static str> {
    match kind {
        "slab" => Some(CASE_TEMPLATE),
        "cylinder" => Some(CYLINDER_TEMPLATE),
        "box" => Some(BOX_TEMPLATE),
        "mesh" => Some(MESH_TEMPLATE),
        "heap" => Some(HEAP_TEMPLATE),
        "draw_down" | "draw-down" => Some(DRAW_DOWN_TEMPLATE),
        _ => None,
    }
}

/// Segments around the axis of the mesh template's STL files.
const TEMPLATE_SEGMENTS: usize = 48;

/// The files a kind's template names, as (file name, ASCII STL text): for `mesh`, the silo's
/// cylinder (radius 50 mm from the cone's top at 40 mm up to 200 mm) and its 45° cone from
/// the 20 mm orifice, in millimetres; nothing for the other kinds.
pub fn template_files(kind: &str) -> Vec<(&'static str, String)> {
    if kind != "mesh" {
        return Vec::new();
    }
    use glam::DVec3;
    let (radius, orifice, cone_top, top) = (50.0, 10.0, 40.0, 200.0);
    let cylinder = stl::shapes::cylinder_side(
        DVec3::new(0.0, 0.0, cone_top),
        DVec3::new(0.0, 0.0, top - cone_top),
        radius,
        TEMPLATE_SEGMENTS,
    );
    let cone = stl::shapes::frustum_side(
        DVec3::ZERO,
        DVec3::new(0.0, 0.0, cone_top),
        orifice,
        radius,
        TEMPLATE_SEGMENTS,
    );
    let ascii = |triangles: Vec<stl::Triangle>, name: &str| {
        let mut bytes = Vec::new();
        stl::write_ascii(&mut bytes, &triangles, name)
            .expect("the builders' triangles are writable");
        String::from_utf8(bytes).expect("ASCII STL is text")
    };
    vec![
        (
            "silo_wall.stl",
            ascii(cylinder.expect("valid cylinder arguments"), "silo wall"),
        ),
        (
            "silo_cone.stl",
            ascii(cone.expect("valid cone arguments"), "silo cone"),
        ),
    ]
}
