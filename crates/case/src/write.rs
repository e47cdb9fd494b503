//! Writes a resolved case back as a TOML case file that reads back to the same case.

use std::fmt::{Display, Write};

use dem::MaterialTable;

use super::case::{
    Case, FieldKernel, RollingLawSpec, TangentialLawSpec, UnclogMethod, WallMaterialSpec,
    CASE_FORMAT_VERSION,
};
use super::error::rounded;
use super::geometry::Geometry;
use super::grain_shape::{GrainShape, ShapeGiven};
use super::mesh::MeshOutlet;
use super::particles::{FractionBasis, MaterialSpec, SizeDistribution};
use super::wall_surface::WallSurface;
use files::DEFAULT_GRAVITY;

/// A float in TOML syntax that parses back to the same bits: Rust prints the shortest
/// representation that round-trips, `{:?}` always with a `.` or an exponent; large
/// moduli are written with an exponent (`1e8`) for readability.
fn float(x: f64) -> String {
    if x.abs() >= 1e6 {
        format!("{x:e}")
    } else {
        format!("{x:?}")
    }
}

/// A cohesion as the inline table a case file gives it (`crate::resolve_cohesion`), in the
/// syntax that reads back to the same bits; `None` for a dry contact, which writes nothing.
fn cohesion(c: &dem::Cohesion) -> Option<String> {
    match *c {
        dem::Cohesion::None => None,
        dem::Cohesion::Jkr { work_of_adhesion } => Some(format!(
            "{{ law = \"jkr\", work_of_adhesion = {} }}",
            float(work_of_adhesion)
        )),
        dem::Cohesion::SimplifiedJkr { energy_density } => Some(format!(
            "{{ law = \"sjkr\", energy_density = {} }}",
            float(energy_density)
        )),
        dem::Cohesion::LiquidBridge {
            volume,
            surface_tension,
            contact_angle,
        } => Some(format!(
            "{{ law = \"liquid_bridge\", volume = {}, surface_tension = {}, contact_angle = {} }}",
            float(volume),
            float(surface_tension),
            float(contact_angle)
        )),
    }
}

/// A case file being written, a line at a time: every key as `key = value`, then its note
/// (a unit, a symbol, a derived value) as a comment, two spaces before the `#`.
struct Lines(String);

impl Lines {
    /// A line as it is.
    fn line(&mut self, text: &str) {
        let _ = writeln!(self.0, "{text}");
    }

    /// A table's header after an empty line, given with its brackets (`[name]`, `[[name]]`).
    fn table(&mut self, header: &str) {
        let _ = writeln!(self.0, "\n{header}");
    }

    /// `key = value`, then `  # note` unless the note is empty.
    fn key(&mut self, key: &str, value: impl Display, note: &str) {
        if note.is_empty() {
            let _ = writeln!(self.0, "{key} = {value}");
        } else {
            let _ = writeln!(self.0, "{key} = {value}  # {note}");
        }
    }

    /// A float key, in the syntax that reads back to the same bits ([`float`]).
    fn float(&mut self, key: &str, x: f64, note: &str) {
        self.key(key, float(x), note);
    }

    /// A word in quotes, as it is: the writer's own words and names the case validated,
    /// which need no escape (a free text goes through [`string`]).
    fn word(&mut self, key: &str, word: &str, note: &str) {
        self.key(key, format_args!("\"{word}\""), note);
    }
}

/// A TOML basic string that reads back to `text` exactly: quotes, backslashes and control
/// characters escaped.
fn string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn walls_word(walls: WallSurface) -> &'static str {
    match walls {
        WallSurface::Smooth => "smooth",
        WallSurface::Meshed => "meshed",
    }
}

fn floats(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|x| float(*x)).collect();
    format!("[{}]", items.join(", "))
}

fn material_lines(out: &mut Lines, material: &MaterialSpec) {
    out.float("density", material.density, "[kg/m³]");
    out.float("shear_modulus", material.shear_modulus, "[Pa]");
    out.float("poisson_ratio", material.poisson_ratio, "[-]");
}

/// The size of the particles or of the last `[[particles.components]]` (`table` names the
/// table the size distribution's header continues): `diameter`, or a size distribution.
fn size_lines(out: &mut Lines, size: &SizeDistribution, table: &str) {
    match size {
        SizeDistribution::Monodisperse { diameter } => {
            out.float("diameter", *diameter, "[m]");
        }
        SizeDistribution::Uniform { min, max } => {
            out.table(&format!("[{table}.size_distribution]"));
            out.word("kind", "uniform", "");
            out.float("min", *min, "[m]");
            out.float("max", *max, "[m]");
        }
        SizeDistribution::Normal {
            mean,
            std_dev,
            min,
            max,
        } => {
            out.table(&format!("[{table}.size_distribution]"));
            out.word("kind", "normal", "");
            out.float("mean", *mean, "[m]");
            out.float("std_dev", *std_dev, "[m]");
            out.float("min", *min, "[m]");
            out.float("max", *max, "[m]");
        }
        SizeDistribution::Discrete {
            diameters,
            fractions,
        } => {
            out.table(&format!("[{table}.size_distribution]"));
            out.word("kind", "discrete", "");
            out.key("diameters", floats(diameters), "[m]");
            out.key("fractions", floats(fractions), "number fractions [-]");
        }
    }
}

/// A grain shape as the inline table the case file gives it: its kind and the keys of
/// that kind, every value as resolved (a rod's default bead count written out, an STL file's
/// absolute path and digest).
fn shape_text(shape: &GrainShape) -> String {
    match &shape.given {
        ShapeGiven::Rod {
            aspect_ratio,
            beads,
        } => format!(
            "{{ kind = \"rod\", aspect_ratio = {}, beads = {beads} }}",
            float(*aspect_ratio)
        ),
        ShapeGiven::Spheres { spheres } => {
            let members: Vec<String> = spheres
                .iter()
                .map(|m| {
                    format!(
                        "{{ centre = {}, radius = {} }}",
                        floats(&m[..3]),
                        float(m[3])
                    )
                })
                .collect();
            format!("{{ kind = \"spheres\", spheres = [{}] }}", members.join(", "))
        }
        ShapeGiven::Stl {
            file,
            sha256,
            cells,
            shortfall,
        } => format!(
            "{{ kind = \"stl\", file = {}, sha256 = \"{sha256}\", cells = {cells}, shortfall = {} }}",
            string(&file.to_string_lossy()),
            float(*shortfall)
        ),
    }
}

/// `shape = { … }` of a component whose grains are shaped.
fn shape_line(out: &mut Lines, shape: &Option<GrainShape>) {
    if let Some(shape) = shape {
        let note = format!("{}; its size the equal-volume diameter", shape.describe());
        out.key("shape", shape_text(shape), &note);
    }
}

/// The `[materials.NAME]` tables and `[[pairs]]` of a case's material table, every value
/// as given (a material keeps whichever of E and G it was given).
fn material_table_lines(out: &mut Lines, table: &MaterialTable) {
    for (name, m) in &table.materials {
        out.table(&format!("[materials.{name}]"));
        let lines = [
            ("density", m.density, "[kg/m³]"),
            ("youngs_modulus", m.youngs_modulus, "E [Pa]"),
            ("shear_modulus", m.shear_modulus, "G [Pa]"),
            ("poisson_ratio", m.poisson_ratio, "[-]"),
        ];
        for (key, value, unit) in lines {
            if let Some(value) = value {
                out.float(key, value, unit);
            }
        }
    }
    for pair in &table.pairs {
        let [a, b] = &pair.materials;
        out.table("[[pairs]]");
        out.key("materials", format_args!("[\"{a}\", \"{b}\"]"), "");
        let lines = [
            ("restitution", pair.restitution),
            ("friction", pair.friction),
            ("rolling_friction", pair.rolling_friction),
        ];
        for (key, value) in lines {
            if let Some(value) = value {
                out.float(key, value, "");
            }
        }
        if let Some(text) = cohesion(&pair.cohesion) {
            out.key("cohesion", text, "");
        }
    }
}

/// The `[geometry]` table of a resolved case. A slab writes no `kind`: it is the default, and
/// its resolved text (which the summary's hash covers) stays what it always was.
fn geometry_lines(out: &mut Lines, geometry: &Geometry) {
    match geometry {
        Geometry::Slab(g) => {
            out.table("[geometry]");
            out.float("width", g.width, "L [m]");
            out.float("height", g.height, "H [m]");
            out.float("thickness", g.thickness, "Z [m]");
            out.float("outlet_width", g.outlet_width, "D [m]");
            out.float("hopper_angle_deg", g.hopper_angle_deg, "α [°]");
            let e = rounded(g.outlet_offset());
            out.float("outlet_gap", g.outlet_gap, &format!("s [m]; e = {e} m"));
        }
        Geometry::Cylinder(g) => {
            out.table("[geometry]");
            out.word("kind", "cylinder", "");
            out.float("radius", g.radius, "R [m]");
            out.float("height", g.height, "H [m]");
            out.float("outlet_diameter", g.outlet_diameter, "D [m]");
            out.float("hopper_angle_deg", g.hopper_angle_deg, "θ [°]");
            out.float("outlet_offset", g.outlet_offset, "e [m]");
            out.word("walls", walls_word(g.walls), "");
            out.key("mesh_segments", g.mesh_segments, "");
        }
        Geometry::Cuboid(g) => {
            out.table("[geometry]");
            out.word("kind", "box", "");
            out.float("width", g.width, "W [m]");
            out.float("depth", g.depth, "B [m]");
            out.float("height", g.height, "H [m]");
            out.word("outlet", g.outlet.word(), "");
            out.float("outlet_width", g.outlet_width, "D [m]");
            out.float("hopper_angle_deg", g.hopper_angle_deg, "α [°]");
            out.float("outlet_offset", g.outlet_offset, "e [m]");
            out.word("walls", walls_word(g.walls), "");
        }
        Geometry::Heap(g) => {
            out.table("[geometry]");
            out.word("kind", "heap", "");
            out.float("cylinder_radius", g.cylinder_radius, "R_c [m]");
            out.float("height", g.height, "H [m]");
            out.float("plate_radius", g.plate_radius, "R_p [m]");
            out.float("lift_speed", g.lift_speed, "[m/s]");
        }
        Geometry::DrawDown(g) => {
            out.table("[geometry]");
            out.word("kind", "draw_down", "");
            out.float("width", g.width(), "W [m]");
            out.float("depth", g.depth(), "B [m]");
            out.float("height", g.height(), "H [m]");
            out.float("slot_width", g.slot_width(), "D [m]");
            out.word("walls", walls_word(g.container.walls), "");
        }
        Geometry::Mesh(g) => {
            out.table("[geometry]");
            out.word("kind", "mesh", "");
            out.key("fill_min", floats(&g.fill_min), "[m]");
            out.key("fill_max", floats(&g.fill_max), "[m]; H is its z");
            let outlet = match &g.outlet {
                MeshOutlet::Disc {
                    centre,
                    radius,
                    segments,
                } => format!(
                    "{{ shape = \"disc\", centre = {}, radius = {}, segments = {segments} }}",
                    floats(centre),
                    float(*radius)
                ),
                MeshOutlet::Rectangle { centre, size } => format!(
                    "{{ shape = \"rectangle\", centre = {}, size = {} }}",
                    floats(centre),
                    floats(size)
                ),
            };
            out.key("outlet", outlet, "in the plane z = 0 [m]");
            for wall in &g.walls {
                out.table("[[geometry.walls]]");
                out.key("name", string(&wall.name), "");
                let file = string(&wall.file.to_string_lossy());
                out.key("file", file, &format!("{} triangles", wall.triangles.len()));
                out.key("sha256", string(&wall.sha256), "");
                out.float("scale", wall.scale, "[m per file unit]");
                out.key("rotate_axis", floats(&wall.rotate_axis), "");
                out.float("rotate_deg", wall.rotate_deg, "[°]");
                out.key("translate", floats(&wall.translate), "[m]");
            }
        }
    }
}

impl Case {
    /// The resolved case as a case file: every key explicit, SI units, units in comments.
    ///
    /// Reading the text back gives an identical case (tested), so a run directory can
    /// hold the exact case it ran.
    pub fn to_toml_string(&self) -> String {
        let mut out = Lines(String::new());
        out.line("# Resolved hopperflow case (SI units).");
        out.key("version", CASE_FORMAT_VERSION, "");
        out.key("seed", self.seed, "");
        // Written only when it differs from the default, so that a case of the default g
        // keeps the text, and so the configuration hash, it had before the key existed.
        if self.gravity != DEFAULT_GRAVITY {
            out.float("gravity", self.gravity, "g [m/s²], along −z");
        }

        geometry_lines(&mut out, &self.geometry);

        if let Some(table) = &self.materials {
            material_table_lines(&mut out, table);
        }

        let p = &self.particles;
        out.table("[particles]");
        // Coarse-grained parcels are written as the case file gave them: the grains and κ.
        let grain_size = |k: usize| match &p.coarse_graining {
            Some(c) => &c.grain_sizes[k],
            None => &p.components[k].size,
        };
        match &p.coarse_graining {
            Some(c) => {
                out.key("count", c.grain_count, "grains");
                let note = format!("κ [-]: {} parcels of κ grains' diameter", p.count);
                out.float("coarse_graining", c.factor, &note);
            }
            None => out.key("count", p.count, ""),
        }
        match p.components.as_slice() {
            [one] => {
                if let Some(name) = &one.material_name {
                    out.word("material", name, "");
                }
                shape_line(&mut out, &one.shape);
                size_lines(&mut out, grain_size(0), "particles");
                if one.material_name.is_none() {
                    out.table("[particles.material]");
                    material_lines(&mut out, &one.material);
                }
            }
            components => {
                let basis = match p.fraction_by {
                    FractionBasis::Number => "number",
                    FractionBasis::Mass => "mass",
                };
                out.word("fraction_by", basis, "");
                // Components without a name in [materials] share particles.material.
                if let Some(shared) = components.iter().find(|c| c.material_name.is_none()) {
                    out.table("[particles.material]");
                    material_lines(&mut out, &shared.material);
                }
                for (k, (c, n)) in components.iter().zip(p.number_fractions()).enumerate() {
                    out.table("[[particles.components]]");
                    out.word("name", &c.name, "");
                    if let Some(name) = &c.material_name {
                        out.word("material", name, "");
                    }
                    let note = format!("by {basis} [-]; {} by number", rounded(n));
                    out.float("fraction", c.fraction, &note);
                    shape_line(&mut out, &c.shape);
                    size_lines(&mut out, grain_size(k), "particles.components");
                }
            }
        }

        let w = &self.wall;
        out.table("[wall]");
        match &w.material {
            WallMaterialSpec::SameAsParticle => {
                out.word("material", "same", "");
            }
            WallMaterialSpec::Rigid => {
                out.word("material", "rigid", "");
            }
            WallMaterialSpec::Named(name) => {
                out.word("material", name, "coefficients from [[pairs]]");
            }
            WallMaterialSpec::Custom(_) => {}
        }
        if !matches!(w.material, WallMaterialSpec::Named(_)) {
            out.float("friction", w.interaction.friction, "");
            out.float("rolling_friction", w.interaction.rolling_friction, "");
            out.float("restitution", w.interaction.restitution, "");
            if let Some(text) = cohesion(&w.interaction.cohesion) {
                out.key("cohesion", text, "");
            }
        }
        if let WallMaterialSpec::Custom(material) = &w.material {
            out.table("[wall.material]");
            material_lines(&mut out, material);
        }

        let c = &self.contact;
        out.table("[contact]");
        if self.materials.is_none() {
            out.float("friction", c.particle.friction, "");
            out.float("rolling_friction", c.particle.rolling_friction, "");
            out.float("restitution", c.particle.restitution, "");
            if let Some(text) = cohesion(&c.particle.cohesion) {
                out.key("cohesion", text, "");
            }
        }
        let tangential = match c.tangential {
            TangentialLawSpec::MindlinNoSlip => "mindlin_no_slip",
            TangentialLawSpec::MindlinDeresiewicz => "mindlin_deresiewicz",
        };
        let rolling = match c.rolling {
            RollingLawSpec::ConstantTorque => "constant_torque",
            RollingLawSpec::Epsd => "epsd",
        };
        out.word("tangential", tangential, "");
        out.word("rolling", rolling, "");
        out.key("normal_clamp", c.normal_clamp, "");

        out.table("[time]");
        let note = format!("[s]; {:.4} Rayleigh times", self.rayleigh_fraction());
        out.float("time_step", self.time_step, &note);

        let pr = &self.protocol;
        out.table("[protocol]");
        out.float("settle_kinetic_energy", pr.settle_kinetic_energy, "[J]");
        out.float("max_settle_time", pr.max_settle_time, "[s]");
        out.float("fill_bottom", pr.fill_bottom, "[m]");
        out.float("fill_top", pr.fill_top, "[m]");
        out.float("fill_speed", pr.fill_speed, "[m/s]");
        out.float("deletion_depth", pr.deletion_depth, "[m]");
        out.float("clog_timeout", pr.clog_timeout, "[s]");
        out.float("time_limit", pr.time_limit, "[s]");
        out.float("stop_fraction", pr.stop_fraction, "[-]");
        // Written only when set, so that the resolved text (and the config hash) of every case
        // without a slip stays as it was.
        if pr.wall_slip > 0.0 {
            out.float("wall_slip", pr.wall_slip, "[m]");
        }
        // Written only when set, as the slip is.
        if let Some(u) = &pr.unclog {
            out.table("[protocol.unclog]");
            let method = match u.method {
                UnclogMethod::AirJet => "air_jet",
            };
            out.word("method", method, "");
            out.float(
                "force_ratio",
                u.force_ratio,
                "[-], over a mean grain's weight",
            );
            out.float(
                "growth",
                u.growth,
                "[-], each further pulse of a clog over the last",
            );
            out.float("duration", u.duration, "[s]");
            out.float("height", u.height, "[m] above the outlet line");
            out.key("avalanches", u.avalanches, "");
            out.key("max_pulses", u.max_pulses, "");
        }

        let m = &self.measure;
        out.table("[measure]");
        out.float("rate_bin_width", m.rate_bin_width, "[s]");
        out.float("x_bin_width", m.x_bin_width, "[m]");
        out.float("strip_height", m.strip_height, "[m]");
        out.float("frame_interval", m.frame_interval, "[s]");
        out.key(
            "crossing_check_interval",
            m.crossing_check_interval,
            "[steps]",
        );
        out.float("steady_start_fraction", m.steady_start_fraction, "");
        out.float("steady_end_fraction", m.steady_end_fraction, "");

        let o = &self.output;
        out.table("[output]");
        out.float("vtu_interval", o.vtu_interval, "[s]");
        out.float("checkpoint_interval", o.checkpoint_interval, "[s]");
        out.key("plots", o.plots, "");
        // Written only when set, so that the resolved text (and the config hash) of every case
        // without fields stays as it was.
        if let Some(f) = &self.fields {
            out.table("[output.fields]");
            let kernel = match f.kernel {
                FieldKernel::Lucy => "lucy",
                FieldKernel::Gaussian => "gaussian",
            };
            out.word("kernel", kernel, "lucy or gaussian");
            out.float("width", f.width, "[m]");
            out.float("cell_size", f.cell_size, "[m]");
            out.float("window", f.window, "[s]");
            out.float("interval", f.interval, "[s]");
            if !f.widths.is_empty() {
                out.key("widths", floats(&f.widths), "[m], the check of the width");
            }
        }
        out.0
    }
}
