//! The validated case: every choice of one hopper run, in SI units, with the paper's
//! defaults (Fan et al. 2023, Table 1 and the base case α = 90°, D = 30 mm, centred).

use dem::MaterialTable;
use serde::{Deserialize, Serialize};

use super::geometry::Geometry;
use super::particles::{MaterialSpec, ParticleSpec};
use super::slab::SlabGeometry;
use files::DEFAULT_GRAVITY;

/// Version of the case-file format this code reads and writes.
pub const CASE_FORMAT_VERSION: i64 = 1;

/// Largest time step allowed, as a fraction of the Rayleigh time.
///
/// EDEM's guidance is 20 % of t_R for dense packings (coordination number ≥ 4), which a
/// filled hopper is; the paper itself uses < 10 % (physics spec §6.1).
pub const MAX_RAYLEIGH_FRACTION: f64 = 0.2;

/// Largest 2D area fraction a monolayer of discs is assumed to reach: the paper's static
/// packing φ_B = 0.59 (3D), which is 0.885 as an area fraction (physics spec §7.3).
pub const MONOLAYER_AREA_FRACTION: f64 = 0.885;

/// Largest volume fraction assumed in a thick slab: random close packing of spheres.
pub const BULK_VOLUME_FRACTION: f64 = 0.64;

/// Slab thickness (in largest diameters) from which two layers of spheres fit side by
/// side, so the fit check switches from disc area to sphere volume.
pub const THICK_SLAB_DIAMETERS: f64 = 2.0;

/// Sliding friction, rolling friction and restitution of one pair type.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct InteractionSpec {
    /// Sliding friction coefficient μ_s [-].
    pub friction: f64,
    /// Rolling friction coefficient μ_r [-].
    pub rolling_friction: f64,
    /// Coefficient of restitution e [-], in (0, 1].
    pub restitution: f64,
    /// How the surfaces stick (docs/physics.md §2.4–2.6); dry by default.
    #[serde(default)]
    pub cohesion: dem::Cohesion,
}

impl InteractionSpec {
    /// Table 1, both particle–particle and particle–wall: the engine's
    /// [`dem::Interaction::fan2023`] (μ = 0.5, μ_r = 0.01, e = 0.2), the one place that
    /// holds these numbers.
    pub fn fan2023() -> Self {
        let table1 = dem::Interaction::fan2023();
        Self {
            friction: table1.friction,
            rolling_friction: table1.rolling_friction,
            restitution: table1.restitution,
            cohesion: table1.cohesion,
        }
    }
}

/// Wall material (the paper does not give it; physics spec §5).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WallMaterialSpec {
    /// Walls of the particle material (default): E*_pw = E*_pp.
    SameAsParticle,
    /// Rigid walls: infinite stiffness, so only the particle's compliance counts.
    Rigid,
    /// Walls of a given material.
    Custom(MaterialSpec),
    /// Walls of the case's `[materials]` entry of this name; each particle material meets
    /// them with its pair's coefficients from `[[pairs]]` (docs/physics.md §1.2), and
    /// [`WallSpec::interaction`] is not used.
    Named(String),
}

/// Walls of the hopper (side walls, bottom plates and the front/back slab walls).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WallSpec {
    /// Wall material.
    pub material: WallMaterialSpec,
    /// Particle–wall friction, rolling friction and restitution (walls not of a named
    /// material).
    pub interaction: InteractionSpec,
}

/// Tangential contact law (physics spec §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TangentialLawSpec {
    /// EDEM/LIGGGHTS Hertz–Mindlin (no slip): linear spring on the accumulated
    /// displacement, Coulomb-capped (default, §3.1).
    MindlinNoSlip,
    /// The paper's Eq. 7 with its typo corrected (§3.3).
    MindlinDeresiewicz,
}

/// Rolling resistance law (physics spec §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RollingLawSpec {
    /// Constant directional torque, the paper's Eq. 8 (EDEM type A, LIGGGHTS cdt).
    ConstantTorque,
    /// Elastic–plastic spring–dashpot (EDEM type C, LIGGGHTS epsd).
    Epsd,
}

/// Contact-law choices and particle–particle coefficients.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactSpec {
    /// Particle–particle friction, rolling friction and restitution (cases without a
    /// `[materials]` table; with one, the pairs come from its `[[pairs]]`).
    pub particle: InteractionSpec,
    /// Tangential law.
    pub tangential: TangentialLawSpec,
    /// Rolling law.
    pub rolling: RollingLawSpec,
    /// Clamp the normal force to F_n ≥ 0 (off: the paper's Eq. 6 has no clamp, §2).
    pub normal_clamp: bool,
}

/// Filling, discharge and stopping rules of a run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Protocol {
    /// The fill counts as settled when the mean kinetic energy per particle is below
    /// this [J].
    pub settle_kinetic_energy: f64,
    /// Longest simulated time allowed for the fill to settle [s].
    pub max_settle_time: f64,
    /// Bottom of the region particles are inserted in, above the outlet plane [m].
    pub fill_bottom: f64,
    /// Top of the region particles are inserted in, above the outlet plane [m].
    pub fill_top: f64,
    /// Downward speed of particles when inserted [m/s]: faster fills sooner, slower pours
    /// more gently.
    pub fill_speed: f64,
    /// Particles this far below the outlet plane are deleted [m] (physics spec §5: 5 d).
    pub deletion_depth: f64,
    /// The outlet counts as clogged when no particle leaves for this long [s].
    pub clog_timeout: f64,
    /// Longest simulated discharge time after the gate opens [s].
    pub time_limit: f64,
    /// Stop once this fraction of the fill's mass has left through the outlet [-], in
    /// (0, 1], and at least `measure.steady_end_fraction`; the run goes on until the
    /// steady window is complete (its last rate bin closed) if that comes later. 1 runs
    /// until the hopper is empty, drained or clogged; the studies stop at 0.7, as soon as
    /// the steady window (15–70 % of the fill discharged) is complete.
    pub stop_fraction: f64,
    /// How far a silo's side walls slip up past the settled bed before the opening [m]
    /// (docs/physics.md §7.7): the bed then settles again with its wall friction mobilised
    /// upward, Janssen's filling state. 0 (the default) leaves the fill's bed as it is.
    #[serde(default)]
    pub wall_slip: f64,
    /// Breaking each arch and going on (`[protocol.unclog]`, docs/physics.md §5.11); `None`,
    /// the default, stops the run at its first clog.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unclog: Option<UnclogSpec>,
}

/// How a clogged run breaks its arch and goes on (`[protocol.unclog]`, docs/physics.md
/// §5.11): at each clog an upward force pulse on the grains above the orifice, the model of
/// the air jet blown up through the outlet in experiments, then the next avalanche; until
/// `avalanches` avalanches have ended in a clog, `protocol.time_limit`, or the container
/// empties (it is not refilled).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnclogSpec {
    /// The mechanism.
    pub method: UnclogMethod,
    /// The pulse's upward force on a grain of the mean diameter over that grain's weight
    /// [-]; a grain of diameter d gets it times (d/d̄)², its cross-section's share.
    pub force_ratio: f64,
    /// Each further pulse of one clog is this many times stronger than the last, up to
    /// [`MAX_UNCLOG_FORCE_RATIO`] weights [-]: an arch that held against one pulse gets a
    /// stronger one, as an experimenter opens the air valve further.
    pub growth: f64,
    /// How long each pulse lasts [s].
    pub duration: f64,
    /// Height above the outlet line of the region the pulse acts in [m] (its footprint is
    /// the orifice's).
    pub height: f64,
    /// Avalanches ended by a clog after which the run stops [-].
    pub avalanches: u32,
    /// Pulses in a row that may fail to restart the flow before the run stops as clogged
    /// [-].
    pub max_pulses: u32,
}

/// The arch-breaking mechanism of `[protocol.unclog]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UnclogMethod {
    /// An upward force on the grains in a region over the orifice, proportional to each
    /// grain's cross-section, for a set duration: an air jet through the outlet.
    AirJet,
}

/// Largest `protocol.unclog.force_ratio`: a jet far stronger than the grains' weight would
/// blow the region's grains up into the bed rather than loosen the arch.
pub const MAX_UNCLOG_FORCE_RATIO: f64 = 50.0;

impl UnclogSpec {
    /// The force ratio of pulse `k` (1 for the first) of one clog [-]: `force_ratio` times
    /// `growth`^(k − 1), at most [`MAX_UNCLOG_FORCE_RATIO`].
    pub fn force_ratio_of_pulse(&self, k: u32) -> f64 {
        let grown = self.force_ratio * self.growth.powi(k.saturating_sub(1).min(1000) as i32);
        grown.min(MAX_UNCLOG_FORCE_RATIO)
    }
}
/// Largest `protocol.unclog.avalanches`.
pub const MAX_AVALANCHES: i64 = 100_000;

/// Measurement settings (physics spec §7).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeasureSpec {
    /// Width of the time bins of the discharge rate W(t) [s] (§7: 0.02–0.05 s).
    pub rate_bin_width: f64,
    /// Width of the x-bins of the outlet profiles [m] (§7.2: d/2).
    pub x_bin_width: f64,
    /// Height h of the strip around the outlet line for φ(x) [m] (§7.3: h = d).
    pub strip_height: f64,
    /// Simulated time between snapshot frames for φ(x) and the flux check [s].
    pub frame_interval: f64,
    /// Steps between checks for particles crossing the outlet line (§7.2: ≤ 100).
    pub crossing_check_interval: u32,
    /// Start of the steady window, as a fraction of the particles discharged (§7).
    pub steady_start_fraction: f64,
    /// End of the steady window, as a fraction of the particles discharged (§7).
    pub steady_end_fraction: f64,
}

/// What a run writes besides its measurements.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OutputSpec {
    /// Simulated time between VTU particle snapshots [s]; 0 writes none.
    pub vtu_interval: f64,
    /// Simulated time between checkpoints [s]; 0 writes none.
    pub checkpoint_interval: f64,
    /// Whether to draw the per-case plots.
    pub plots: bool,
}

/// The coarse-graining kernel of `[output.fields]` (docs/physics.md §7.13).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldKernel {
    /// Lucy's compact polynomial (the default).
    Lucy,
    /// A Gaussian cut at 3 widths.
    Gaussian,
}

/// Coarse-grained continuum fields (`[output.fields]`, docs/physics.md §7.13): density,
/// volume fraction, velocity and stress on an (x, z) grid for a slab or a box, (r, z) for a
/// cylinder; off unless the section is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FieldsSpec {
    /// The kernel.
    pub kernel: FieldKernel,
    /// Kernel width w [m] of the fields written.
    pub width: f64,
    /// Side h of the grid's square cells [m].
    pub cell_size: f64,
    /// Averaging window [s]: the frames are summed in blocks of this length, and the fields
    /// written average the blocks of the discharge's steady window (all, where it has none).
    pub window: f64,
    /// Simulated time between the frames coarse-grained [s].
    pub interval: f64,
    /// Further widths [m] at which the fields are computed for the check of the width.
    pub widths: Vec<f64>,
}

/// Smallest kernel width, in largest particle diameters: the branch quadrature is sized
/// for w ≥ d/4 (docs/physics.md §7.13).
pub const MIN_FIELD_WIDTH_DIAMETERS: f64 = 0.25;
/// Largest kernel width, in largest particle diameters: beyond it the fields are the
/// container's averages, not a field.
pub const MAX_FIELD_WIDTH_DIAMETERS: f64 = 20.0;
/// Most widths in `[output.fields] widths`.
pub const MAX_FIELD_WIDTHS: usize = 8;

/// Largest g [m/s²] a case may give: about 100 times the Earth's, the range of geotechnical
/// centrifuges; beyond it the default time-step guidance no longer holds.
pub const MAX_GRAVITY: f64 = 1000.0;

fn default_gravity() -> f64 {
    DEFAULT_GRAVITY
}

/// One validated hopper case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Case {
    /// Seed of the random fill (≤ i64::MAX so that it can be written as a TOML integer).
    pub seed: u64,
    /// The container: the paper's slab hopper or a silo.
    pub geometry: Geometry,
    /// Named materials and the coefficients of their pairs (`[materials.NAME]` and
    /// `[[pairs]]`, docs/physics.md §1.2); `None` for a case of one particle material given
    /// by `particles.material` and coefficients given by `[contact]` and `[wall]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub materials: Option<MaterialTable>,
    /// The particles: count, sizes, material or components (`[particles]`).
    pub particles: ParticleSpec,
    /// The walls' material and friction (`[wall]`).
    pub wall: WallSpec,
    /// The contact laws and their coefficients (`[contact]`).
    pub contact: ContactSpec,
    /// Integration time step Δt [s] (physics spec §6.1: 2.5e-6 s = 0.097 t_R).
    pub time_step: f64,
    /// Gravitational acceleration g [m/s²], along −z (the top-level key `gravity`).
    #[serde(default = "default_gravity")]
    pub gravity: f64,
    /// The run's phases: fill, settle, discharge and their limits (`[protocol]`).
    pub protocol: Protocol,
    /// What the run measures and where (`[measure]`).
    pub measure: MeasureSpec,
    /// What the run writes (`[output]`).
    pub output: OutputSpec,
    /// Coarse-grained fields (`[output.fields]`); `None`, the default, writes none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fields: Option<FieldsSpec>,
}

impl Case {
    /// The paper's base case: Table 1, α = 90°, D = 30 mm, centred outlet, 3000 spheres.
    pub fn paper_base() -> Self {
        let d = 3.0e-3;
        let slab = SlabGeometry::paper();
        Self {
            seed: 1,
            protocol: Protocol {
                settle_kinetic_energy: 1.0e-9,
                max_settle_time: 3.0,
                fill_bottom: 0.0,
                fill_top: slab.height,
                fill_speed: 1.0,
                deletion_depth: 5.0 * d,
                // At the smallest outlet (D = 6 d) some 700 particles leave per second:
                // 0.3 s without any is a stopped flow, not a fluctuation.
                clog_timeout: 0.3,
                time_limit: 20.0,
                stop_fraction: 1.0,
                wall_slip: 0.0,
                unclog: None,
            },
            geometry: Geometry::Slab(slab),
            materials: None,
            particles: ParticleSpec::paper(),
            wall: WallSpec {
                material: WallMaterialSpec::SameAsParticle,
                interaction: InteractionSpec::fan2023(),
            },
            contact: ContactSpec {
                particle: InteractionSpec::fan2023(),
                tangential: TangentialLawSpec::MindlinNoSlip,
                rolling: RollingLawSpec::ConstantTorque,
                normal_clamp: false,
            },
            time_step: 2.5e-6,
            gravity: DEFAULT_GRAVITY,
            measure: MeasureSpec {
                rate_bin_width: 0.02,
                x_bin_width: 0.5 * d,
                strip_height: d,
                frame_interval: 1.0e-3,
                crossing_check_interval: 10,
                steady_start_fraction: 0.15,
                steady_end_fraction: 0.70,
            },
            output: OutputSpec {
                // A ParaView series of a base-case run: about 45 snapshots of 1 MB.
                vtu_interval: 0.1,
                checkpoint_interval: 1.0,
                plots: true,
            },
            fields: None,
        }
    }

    /// Time step as a fraction of the Rayleigh time of the smallest particle [-].
    pub fn rayleigh_fraction(&self) -> f64 {
        self.time_step / self.particles.rayleigh_time()
    }

    /// The slab hopper of a slab case.
    pub fn slab(&self) -> Option<&SlabGeometry> {
        self.geometry.slab()
    }

    /// Whether the slab is thick enough for two layers of spheres (then the case is a 3D
    /// rectangular hopper and packing is judged by volume); false for a silo.
    pub fn is_thick_slab(&self) -> bool {
        self.slab()
            .is_some_and(|g| g.thickness >= THICK_SLAB_DIAMETERS * self.particles.max_diameter())
    }

    /// In-plane container area the particles need at the densest assumed packing [m²]
    /// (slab cases; NaN for a silo).
    ///
    /// Quasi-2D slab: disc area / `MONOLAYER_AREA_FRACTION`. Thick slab: sphere volume /
    /// (`BULK_VOLUME_FRACTION` · Z).
    pub fn packed_area(&self) -> f64 {
        match self.slab() {
            Some(g) if self.is_thick_slab() => {
                self.particles.total_volume() / (BULK_VOLUME_FRACTION * g.thickness)
            }
            Some(_) => self.particles.total_disc_area() / MONOLAYER_AREA_FRACTION,
            None => f64::NAN,
        }
    }

    /// Container volume the particles need at the densest assumed packing, sphere volume /
    /// `BULK_VOLUME_FRACTION` [m³] (silo cases).
    pub fn packed_volume(&self) -> f64 {
        self.particles.total_volume() / BULK_VOLUME_FRACTION
    }

    /// Estimated height of the settled fill above the outlet plane [m], or `None` when
    /// the particles cannot fit below H at the densest assumed packing, and for STL walls,
    /// whose inside volume is not known.
    pub fn fill_height(&self) -> Option<f64> {
        match &self.geometry {
            Geometry::Slab(g) => g.height_holding(self.packed_area()),
            Geometry::Cylinder(g) => g.height_holding(self.packed_volume()),
            Geometry::Cuboid(g) => g.height_holding(self.packed_volume()),
            Geometry::DrawDown(g) => g.container.height_holding(self.packed_volume()),
            Geometry::Heap(g) => g.height_holding(self.packed_volume()),
            Geometry::Mesh(_) => None,
        }
    }

    /// Whether N particles fit in the container below H (see [`Case::packed_area`] and
    /// [`Case::packed_volume`]). Always true for STL walls: an open mesh has no inside
    /// volume to compare with, and a fill that cannot be placed stops the run instead.
    pub fn particles_fit(&self) -> bool {
        matches!(self.geometry, Geometry::Mesh(_)) || self.fill_height().is_some()
    }
}
