//! Writes a resolved case back as a TOML case file that reads back to the same case.

use std::fmt::Write;

use dem::MaterialTable;

use super::case::{Case, RollingLawSpec, TangentialLawSpec, WallMaterialSpec, CASE_FORMAT_VERSION};
use super::error::rounded;
use super::geometry::Geometry;
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

fn material_lines(out: &mut String, material: &MaterialSpec) {
    let _ = writeln!(out, "density = {}  # [kg/m³]", float(material.density));
    let _ = writeln!(
        out,
        "shear_modulus = {}  # [Pa]",
        float(material.shear_modulus)
    );
    let _ = writeln!(
        out,
        "poisson_ratio = {}  # [-]",
        float(material.poisson_ratio)
    );
}

/// The size of the particles or of the last `[[particles.components]]` (`table` names the
/// table the size distribution's header continues): `diameter`, or a size distribution.
fn size_lines(out: &mut String, size: &SizeDistribution, table: &str) {
    match size {
        SizeDistribution::Monodisperse { diameter } => {
            let _ = writeln!(out, "diameter = {}  # [m]", float(*diameter));
        }
        SizeDistribution::Uniform { min, max } => {
            let _ = writeln!(out, "\n[{table}.size_distribution]");
            let _ = writeln!(out, "kind = \"uniform\"");
            let _ = writeln!(out, "min = {}  # [m]", float(*min));
            let _ = writeln!(out, "max = {}  # [m]", float(*max));
        }
        SizeDistribution::Normal {
            mean,
            std_dev,
            min,
            max,
        } => {
            let _ = writeln!(out, "\n[{table}.size_distribution]");
            let _ = writeln!(out, "kind = \"normal\"");
            let _ = writeln!(out, "mean = {}  # [m]", float(*mean));
            let _ = writeln!(out, "std_dev = {}  # [m]", float(*std_dev));
            let _ = writeln!(out, "min = {}  # [m]", float(*min));
            let _ = writeln!(out, "max = {}  # [m]", float(*max));
        }
        SizeDistribution::Discrete {
            diameters,
            fractions,
        } => {
            let _ = writeln!(out, "\n[{table}.size_distribution]");
            let _ = writeln!(out, "kind = \"discrete\"");
            let _ = writeln!(out, "diameters = {}  # [m]", floats(diameters));
            let _ = writeln!(
                out,
                "fractions = {}  # number fractions [-]",
                floats(fractions)
            );
        }
    }
}

/// The `[materials.NAME]` tables and `[[pairs]]` of a case's material table, every value
/// as given (a material keeps whichever of E and G it was given).
fn material_table_lines(out: &mut String, table: &MaterialTable) {
    for (name, m) in &table.materials {
        let _ = writeln!(out, "\n[materials.{name}]");
        let lines = [
            ("density", m.density, "  # [kg/m³]"),
            ("youngs_modulus", m.youngs_modulus, "  # E [Pa]"),
            ("shear_modulus", m.shear_modulus, "  # G [Pa]"),
            ("poisson_ratio", m.poisson_ratio, "  # [-]"),
        ];
        for (key, value, unit) in lines {
            if let Some(value) = value {
                let _ = writeln!(out, "{key} = {}{unit}", float(value));
            }
        }
    }
    for pair in &table.pairs {
        let [a, b] = &pair.materials;
        let _ = writeln!(out, "\n[[pairs]]");
        let _ = writeln!(out, "materials = [\"{a}\", \"{b}\"]");
        let lines = [
            ("restitution", pair.restitution),
            ("friction", pair.friction),
            ("rolling_friction", pair.rolling_friction),
        ];
        for (key, value) in lines {
            if let Some(value) = value {
                let _ = writeln!(out, "{key} = {}", float(value));
            }
        }
    }
}

/// The `[geometry]` table of a resolved case. A slab writes no `kind`: it is the default, and
/// its resolved text (which the summary's hash covers) stays what it always was.
fn geometry_lines(out: &mut String, geometry: &Geometry) {
    match geometry {
        Geometry::Slab(g) => {
            let _ = writeln!(out, "\n[geometry]");
            let _ = writeln!(out, "width = {}  # L [m]", float(g.width));
            let _ = writeln!(out, "height = {}  # H [m]", float(g.height));
            let _ = writeln!(out, "thickness = {}  # Z [m]", float(g.thickness));
            let _ = writeln!(out, "outlet_width = {}  # D [m]", float(g.outlet_width));
            let _ = writeln!(
                out,
                "hopper_angle_deg = {}  # α [°]",
                float(g.hopper_angle_deg)
            );
            let _ = writeln!(
                out,
                "outlet_gap = {}  # s [m]; e = {} m",
                float(g.outlet_gap),
                rounded(g.outlet_offset())
            );
        }
        Geometry::Cylinder(g) => {
            let _ = writeln!(out, "\n[geometry]");
            let _ = writeln!(out, "kind = \"cylinder\"");
            let _ = writeln!(out, "radius = {}  # R [m]", float(g.radius));
            let _ = writeln!(out, "height = {}  # H [m]", float(g.height));
            let _ = writeln!(
                out,
                "outlet_diameter = {}  # D [m]",
                float(g.outlet_diameter)
            );
            let _ = writeln!(
                out,
                "hopper_angle_deg = {}  # θ [°]",
                float(g.hopper_angle_deg)
            );
            let _ = writeln!(out, "outlet_offset = {}  # e [m]", float(g.outlet_offset));
            let _ = writeln!(out, "walls = \"{}\"", walls_word(g.walls));
            let _ = writeln!(out, "mesh_segments = {}", g.mesh_segments);
        }
        Geometry::Cuboid(g) => {
            let _ = writeln!(out, "\n[geometry]");
            let _ = writeln!(out, "kind = \"box\"");
            let _ = writeln!(out, "width = {}  # W [m]", float(g.width));
            let _ = writeln!(out, "depth = {}  # B [m]", float(g.depth));
            let _ = writeln!(out, "height = {}  # H [m]", float(g.height));
            let _ = writeln!(out, "outlet = \"{}\"", g.outlet.word());
            let _ = writeln!(out, "outlet_width = {}  # D [m]", float(g.outlet_width));
            let _ = writeln!(
                out,
                "hopper_angle_deg = {}  # α [°]",
                float(g.hopper_angle_deg)
            );
            let _ = writeln!(out, "outlet_offset = {}  # e [m]", float(g.outlet_offset));
            let _ = writeln!(out, "walls = \"{}\"", walls_word(g.walls));
        }
        Geometry::Mesh(g) => {
            let _ = writeln!(out, "\n[geometry]");
            let _ = writeln!(out, "kind = \"mesh\"");
            let _ = writeln!(out, "fill_min = {}  # [m]", floats(&g.fill_min));
            let _ = writeln!(out, "fill_max = {}  # [m]; H is its z", floats(&g.fill_max));
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
            let _ = writeln!(out, "outlet = {outlet}  # in the plane z = 0 [m]");
            for wall in &g.walls {
                let _ = writeln!(out, "\n[[geometry.walls]]");
                let _ = writeln!(out, "name = {}", string(&wall.name));
                let _ = writeln!(
                    out,
                    "file = {}  # {} triangles",
                    string(&wall.file.to_string_lossy()),
                    wall.triangles.len()
                );
                let _ = writeln!(out, "sha256 = {}", string(&wall.sha256));
                let _ = writeln!(out, "scale = {}  # [m per file unit]", float(wall.scale));
                let _ = writeln!(out, "rotate_axis = {}", floats(&wall.rotate_axis));
                let _ = writeln!(out, "rotate_deg = {}  # [°]", float(wall.rotate_deg));
                let _ = writeln!(out, "translate = {}  # [m]", floats(&wall.translate));
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
        let mut out = String::new();
        let _ = writeln!(out, "# Resolved hopperflow case (SI units).");
        let _ = writeln!(out, "version = {CASE_FORMAT_VERSION}");
        let _ = writeln!(out, "seed = {}", self.seed);
        // Written only when it differs from the default, so that a case of the default g
        // keeps the text, and so the configuration hash, it had before the key existed.
        if self.gravity != DEFAULT_GRAVITY {
            let _ = writeln!(
                out,
                "gravity = {}  # g [m/s²], along −z",
                float(self.gravity)
            );
        }

        geometry_lines(&mut out, &self.geometry);

        if let Some(table) = &self.materials {
            material_table_lines(&mut out, table);
        }

        let p = &self.particles;
        let _ = writeln!(out, "\n[particles]");
        let _ = writeln!(out, "count = {}", p.count);
        match p.components.as_slice() {
            [one] => {
                if let Some(name) = &one.material_name {
                    let _ = writeln!(out, "material = \"{name}\"");
                }
                size_lines(&mut out, &one.size, "particles");
                if one.material_name.is_none() {
                    let _ = writeln!(out, "\n[particles.material]");
                    material_lines(&mut out, &one.material);
                }
            }
            components => {
                let basis = match p.fraction_by {
                    FractionBasis::Number => "number",
                    FractionBasis::Mass => "mass",
                };
                let _ = writeln!(out, "fraction_by = \"{basis}\"");
                // Components without a name in [materials] share particles.material.
                if let Some(shared) = components.iter().find(|c| c.material_name.is_none()) {
                    let _ = writeln!(out, "\n[particles.material]");
                    material_lines(&mut out, &shared.material);
                }
                for (c, n) in components.iter().zip(p.number_fractions()) {
                    let _ = writeln!(out, "\n[[particles.components]]");
                    let _ = writeln!(out, "name = \"{}\"", c.name);
                    if let Some(name) = &c.material_name {
                        let _ = writeln!(out, "material = \"{name}\"");
                    }
                    let _ = writeln!(
                        out,
                        "fraction = {}  # by {basis} [-]; {} by number",
                        float(c.fraction),
                        rounded(n)
                    );
                    size_lines(&mut out, &c.size, "particles.components");
                }
            }
        }

        let w = &self.wall;
        let _ = writeln!(out, "\n[wall]");
        match &w.material {
            WallMaterialSpec::SameAsParticle => {
                let _ = writeln!(out, "material = \"same\"");
            }
            WallMaterialSpec::Rigid => {
                let _ = writeln!(out, "material = \"rigid\"");
            }
            WallMaterialSpec::Named(name) => {
                let _ = writeln!(out, "material = \"{name}\"  # coefficients from [[pairs]]");
            }
            WallMaterialSpec::Custom(_) => {}
        }
        if !matches!(w.material, WallMaterialSpec::Named(_)) {
            let _ = writeln!(out, "friction = {}", float(w.interaction.friction));
            let _ = writeln!(
                out,
                "rolling_friction = {}",
                float(w.interaction.rolling_friction)
            );
            let _ = writeln!(out, "restitution = {}", float(w.interaction.restitution));
        }
        if let WallMaterialSpec::Custom(material) = &w.material {
            let _ = writeln!(out, "\n[wall.material]");
            material_lines(&mut out, material);
        }

        let c = &self.contact;
        let _ = writeln!(out, "\n[contact]");
        if self.materials.is_none() {
            let _ = writeln!(out, "friction = {}", float(c.particle.friction));
            let _ = writeln!(
                out,
                "rolling_friction = {}",
                float(c.particle.rolling_friction)
            );
            let _ = writeln!(out, "restitution = {}", float(c.particle.restitution));
        }
        let tangential = match c.tangential {
            TangentialLawSpec::MindlinNoSlip => "mindlin_no_slip",
            TangentialLawSpec::MindlinDeresiewicz => "mindlin_deresiewicz",
        };
        let rolling = match c.rolling {
            RollingLawSpec::ConstantTorque => "constant_torque",
            RollingLawSpec::Epsd => "epsd",
        };
        let _ = writeln!(out, "tangential = \"{tangential}\"");
        let _ = writeln!(out, "rolling = \"{rolling}\"");
        let _ = writeln!(out, "normal_clamp = {}", c.normal_clamp);

        let _ = writeln!(out, "\n[time]");
        let _ = writeln!(
            out,
            "time_step = {}  # [s]; {:.4} Rayleigh times",
            float(self.time_step),
            self.rayleigh_fraction()
        );

        let pr = &self.protocol;
        let _ = writeln!(out, "\n[protocol]");
        let _ = writeln!(
            out,
            "settle_kinetic_energy = {}  # [J]",
            float(pr.settle_kinetic_energy)
        );
        let _ = writeln!(
            out,
            "max_settle_time = {}  # [s]",
            float(pr.max_settle_time)
        );
        let _ = writeln!(out, "fill_bottom = {}  # [m]", float(pr.fill_bottom));
        let _ = writeln!(out, "fill_top = {}  # [m]", float(pr.fill_top));
        let _ = writeln!(out, "fill_speed = {}  # [m/s]", float(pr.fill_speed));
        let _ = writeln!(out, "deletion_depth = {}  # [m]", float(pr.deletion_depth));
        let _ = writeln!(out, "clog_timeout = {}  # [s]", float(pr.clog_timeout));
        let _ = writeln!(out, "time_limit = {}  # [s]", float(pr.time_limit));
        let _ = writeln!(out, "stop_fraction = {}  # [-]", float(pr.stop_fraction));
        // Written only when set, so that the resolved text (and the config hash) of every case
        // without a slip stays as it was.
        if pr.wall_slip > 0.0 {
            let _ = writeln!(out, "wall_slip = {}  # [m]", float(pr.wall_slip));
        }

        let m = &self.measure;
        let _ = writeln!(out, "\n[measure]");
        let _ = writeln!(out, "rate_bin_width = {}  # [s]", float(m.rate_bin_width));
        let _ = writeln!(out, "x_bin_width = {}  # [m]", float(m.x_bin_width));
        let _ = writeln!(out, "strip_height = {}  # [m]", float(m.strip_height));
        let _ = writeln!(out, "frame_interval = {}  # [s]", float(m.frame_interval));
        let _ = writeln!(
            out,
            "crossing_check_interval = {}  # [steps]",
            m.crossing_check_interval
        );
        let _ = writeln!(
            out,
            "steady_start_fraction = {}",
            float(m.steady_start_fraction)
        );
        let _ = writeln!(
            out,
            "steady_end_fraction = {}",
            float(m.steady_end_fraction)
        );

        let o = &self.output;
        let _ = writeln!(out, "\n[output]");
        let _ = writeln!(out, "vtu_interval = {}  # [s]", float(o.vtu_interval));
        let _ = writeln!(
            out,
            "checkpoint_interval = {}  # [s]",
            float(o.checkpoint_interval)
        );
        let _ = writeln!(out, "plots = {}", o.plots);
        out
    }
}
