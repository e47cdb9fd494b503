//! Turns a located case document into a validated [`Case`], collecting every error.
//!
//! Reading order matters only for defaults: the particle diameters come first because
//! several defaults (deletion depth 5 d, bin width d/2, strip height d) and checks
//! (D ≥ 3 d, Z ≥ d) are stated in particle diameters.

use std::path::Path;
use std::sync::Arc;

use super::case::{
    Case, ContactSpec, InteractionSpec, RollingLawSpec, TangentialLawSpec, WallMaterialSpec,
    WallSpec, CASE_FORMAT_VERSION, MAX_GRAVITY,
};
use files::DEFAULT_GRAVITY;

use super::document::{NodeValue, Table};
use super::error::{number, rounded, ConfigError, ConfigErrors, ErrorKind};
use super::geometry::Geometry;
use super::limits::outlet_too_small;
use super::mesh::MeshOutlet;
use super::particles::MaterialSpec;
use super::reader::{Located, Section};
use super::resolve_materials::{read_materials, NamedMaterials};
use super::resolve_particles::{read_material, read_particles};
use super::resolve_run::{read_measure, read_output, read_protocol, read_time_step};
use super::slab::SlabGeometry;
use super::sources::source;

/// Pairs of keys that are alternatives: giving one through `--set` or a sweep axis
/// removes the other, and giving both in a file is an error.
pub(crate) const ALTERNATIVE_KEYS: &[(&str, &str)] = &[
    ("geometry.outlet_gap", "geometry.outlet_offset"),
    ("time.time_step", "time.rayleigh_fraction"),
    ("particles.diameter", "particles.size_distribution"),
    ("particles.components", "particles.diameter"),
    ("particles.components", "particles.size_distribution"),
    (
        "particles.material.shear_modulus",
        "particles.material.youngs_modulus",
    ),
    (
        "wall.material.shear_modulus",
        "wall.material.youngs_modulus",
    ),
];

const TOP_KEYS: &[&str] = &[
    "version",
    "seed",
    "gravity",
    "geometry",
    "materials",
    "pairs",
    "particles",
    "wall",
    "contact",
    "time",
    "protocol",
    "measure",
    "output",
];

/// Validates a whole case document; `dir` is the case file's folder (`None`: the current
/// folder), from which relative paths in it are taken.
pub(crate) fn resolve_case(
    document: &Table,
    source: &Arc<str>,
    dir: Option<&Path>,
) -> Result<Case, ConfigErrors> {
    let mut errors = Vec::new();
    let mut root = Section::root(document, source);
    let base = Case::paper_base();

    let version = root.integer_or("version", CASE_FORMAT_VERSION, &mut errors);
    if version.value != CASE_FORMAT_VERSION {
        errors.push(version.error(
            ErrorKind::Invalid,
            format!("this hopperflow reads format version {CASE_FORMAT_VERSION} only"),
        ));
    }
    let seed = root.integer_or("seed", base.seed as i64, &mut errors);
    if seed.value < 0 {
        errors.push(seed.error(ErrorKind::Invalid, "must be an integer ≥ 0"));
    }

    let gravity = root.float_or("gravity", "m/s²", DEFAULT_GRAVITY, &mut errors);
    let gravity_ok =
        gravity.value.is_finite() && gravity.value > 0.0 && gravity.value <= MAX_GRAVITY;
    if !gravity_ok {
        // The fill falls, the bed settles and the outlet discharges under gravity: g = 0 has
        // no discharge to measure, and an upward g empties the container through its top.
        errors.push(gravity.error(
            ErrorKind::Invalid,
            format!(
                "must be in (0, {}] m/s² (g, pointing along −z)",
                number(MAX_GRAVITY)
            ),
        ));
    }

    // Liquid bridge volumes, checked against the smallest sphere once it is known.
    let mut volumes = Vec::new();
    let named = read_materials(&mut root, &mut volumes, &mut errors);
    let particles = read_particles(
        &mut root.section("particles", &mut errors),
        named.as_ref(),
        dir,
        &mut errors,
    );
    // Diameter-based defaults and checks fall back to the paper's 3 mm when the particle
    // table itself is invalid; its own errors are already recorded.
    let d_max = particles.as_ref().map_or(3.0e-3, |(p, _)| p.max_diameter());
    let d_max_source = particles.as_ref().map(|(_, s)| s.largest_diameter.as_str());
    let geometry = read_container(
        &mut root.section("geometry", &mut errors),
        particles
            .as_ref()
            .map(|(p, s)| (p.max_diameter(), s.largest_diameter.as_str())),
        dir,
        &mut errors,
    );
    let particle_materials = particles.as_ref().map(|(p, _)| {
        p.components
            .iter()
            .filter_map(|c| c.material_name.clone())
            .collect::<Vec<_>>()
    });
    let wall = read_wall(
        &mut root.section("wall", &mut errors),
        named.as_ref(),
        particle_materials.as_deref(),
        &mut volumes,
        &mut errors,
    );
    let contact = read_contact(
        &mut root.section("contact", &mut errors),
        named.is_some(),
        &mut volumes,
        &mut errors,
    );
    if let Some((p, _)) = &particles {
        // The bridge volumes are the grains', checked against the grains.
        super::resolve_cohesion::check_bridge_volumes(
            &volumes,
            p.grain_min_diameter(),
            &mut errors,
        );
    }
    if let (Some(named), Some(names)) = (&named, &particle_materials) {
        // Every pair the run will meet must be listed or mixable (docs/physics.md §1.2).
        let mut pairs: Vec<(&str, &str)> = Vec::new();
        for (i, a) in names.iter().enumerate() {
            for b in &names[i..] {
                pairs.push((a, b));
            }
        }
        if let Some(WallSpec {
            material: WallMaterialSpec::Named(wall),
            ..
        }) = &wall
        {
            pairs.extend(names.iter().map(|a| (a.as_str(), wall.as_str())));
        }
        named.require_pairs(&pairs, &mut errors);
    }
    let time_step = read_time_step(
        &mut root.section("time", &mut errors),
        particles.as_ref(),
        &mut errors,
    );
    let height = geometry.as_ref().map(Geometry::height);
    let protocol = read_protocol(
        &mut root.section("protocol", &mut errors),
        d_max,
        d_max_source,
        height,
        (
            particles.as_ref().map_or(3.0e-3, |(p, _)| p.min_diameter()),
            geometry.as_ref().map(|g| {
                matches!(
                    g,
                    Geometry::Cylinder(_) | Geometry::Cuboid(_) | Geometry::DrawDown(_)
                )
            }),
        ),
        // The heap has no outlet to unclog: NaN refuses the section below.
        geometry.as_ref().map(Geometry::outlet_size),
        &mut errors,
    );
    let measure = read_measure(
        &mut root.section("measure", &mut errors),
        d_max,
        d_max_source,
        geometry.as_ref().map(|g| (g.outlet_size(), outlet_key(g))),
        time_step.as_ref(),
        protocol.as_ref().map(|p| p.stop_fraction),
        &mut errors,
    );
    // Fields are gridded in (x, z) for a slab or a box, in (r, z) for a cylinder.
    let gridded = geometry.as_ref().map(|g| {
        matches!(
            g,
            Geometry::Slab(_) | Geometry::Cylinder(_) | Geometry::Cuboid(_)
        )
    });
    let (output, fields) = read_output(
        &mut root.section("output", &mut errors),
        (d_max, d_max_source, gridded),
        time_step.as_ref(),
        &mut errors,
    );
    if let Some((p, _)) = &particles {
        if p.has_shapes() {
            let location = root.location().clone();
            let mut refuse = |key: &str, message: &str| {
                errors.push(ConfigError::new(
                    ErrorKind::Conflict,
                    location.clone(),
                    key.to_string(),
                    None,
                    message.to_string(),
                ))
            };
            if matches!(geometry, Some(Geometry::Slab(_))) {
                refuse(
                    "geometry.kind",
                    "shaped grains (particles.shape) need a 3D silo: \"cylinder\", \"box\" or \
                     \"mesh\"; the quasi-2D slab is one sphere thick",
                );
            }
            if p.coarse_graining.is_some() {
                refuse(
                    "particles.coarse_graining",
                    "coarse-grained parcels are spheres; give either particles.shape or \
                     particles.coarse_graining, not both",
                );
            }
            if fields.is_some() {
                refuse(
                    "output.fields",
                    "the coarse-grained fields are computed for spheres only; remove \
                     [output.fields] from a case of shaped grains",
                );
            }
        }
    }
    root.finish(TOP_KEYS, &mut errors);

    let largest_diameter = d_max_source.map(str::to_string);
    let case = match (
        geometry, particles, wall, contact, time_step, protocol, measure, output,
    ) {
        (Some(g), Some((p, _)), Some(w), Some(c), Some((dt, _)), Some(pr), Some(m), Some(o))
            if seed.value >= 0 && gravity_ok && named.as_ref().is_none_or(|n| n.valid) =>
        {
            Some(Case {
                seed: seed.value as u64,
                geometry: g,
                materials: named.map(|n| n.table),
                particles: p,
                wall: w,
                contact: c,
                time_step: dt,
                gravity: gravity.value,
                protocol: pr,
                measure: m,
                output: o,
                fields,
            })
        }
        _ => None,
    };
    if let Some(case) = &case {
        check_fill_band(case, document, source, &mut errors);
        check_particles_fit(
            case,
            document,
            source,
            largest_diameter.as_deref().unwrap_or("particles.diameter"),
            &mut errors,
        );
    }
    match case {
        Some(case) if errors.is_empty() => Ok(case),
        _ => {
            // Document order: errors with a line first, by line; stable for the rest.
            errors.sort_by_key(|e| (e.location.line.unwrap_or(usize::MAX), e.location.column));
            Err(ConfigErrors { errors })
        }
    }
}

/// Reads friction, rolling friction and restitution of one pair type.
fn read_interaction(
    section: &mut Section<'_>,
    volumes: &mut Vec<Located<f64>>,
    errors: &mut Vec<ConfigError>,
) -> Option<InteractionSpec> {
    let paper = InteractionSpec::fan2023();
    let friction = section.float_or("friction", "", paper.friction, errors);
    let rolling = section.float_or("rolling_friction", "", paper.rolling_friction, errors);
    let restitution = section.float_or("restitution", "", paper.restitution, errors);
    let mut ok = friction.require_non_negative(errors) & rolling.require_non_negative(errors);
    // e = 0 makes the damping ratio β = ln e / √(ln² e + π²) undefined (physics spec §2).
    if !(restitution.value > 0.0 && restitution.value <= 1.0) {
        errors.push(restitution.error(ErrorKind::Invalid, "must lie in (0, 1]"));
        ok = false;
    }
    let cohesion = super::resolve_cohesion::read_cohesion(section, volumes, errors);
    ok &= cohesion.is_some();
    ok.then(|| InteractionSpec {
        friction: friction.value,
        rolling_friction: rolling.value,
        restitution: restitution.value,
        cohesion: cohesion.expect("checked"),
    })
}

/// The geometry kinds `geometry.kind` accepts.
const GEOMETRY_KINDS: &[&str] = &["slab", "cylinder", "box", "mesh", "heap", "draw_down"];

/// The key of a geometry's outlet size D, as messages name it.
pub(crate) fn outlet_key(geometry: &Geometry) -> &'static str {
    match geometry {
        Geometry::Slab(_) => "geometry.outlet_width",
        Geometry::Cylinder(_) => "geometry.outlet_diameter",
        Geometry::Cuboid(_) => "geometry.outlet_width",
        Geometry::DrawDown(_) => "geometry.slot_width",
        // No outlet: its size is NaN, which no check compares against.
        Geometry::Heap(_) => "geometry.plate_radius",
        Geometry::Mesh(g) => match g.outlet {
            MeshOutlet::Disc { .. } => "the disc's diameter, 2 × geometry.outlet.radius",
            MeshOutlet::Rectangle { .. } => "the rectangle's side along x, geometry.outlet.size[0]",
        },
    }
}

/// Reads `[geometry]` of any kind (`kind`, default `"slab"`); `d_max` is the largest
/// particle diameter [m] with the key that set it, when the particles are valid; `dir` is the
/// case file's folder, from which a mesh's relative STL paths are taken.
fn read_container(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<Geometry> {
    let kind = section.string("kind", errors);
    match kind.as_ref().map(|k| k.value.as_str()) {
        None | Some("slab") => read_geometry(section, d_max, errors).map(Geometry::Slab),
        Some("cylinder") => {
            super::resolve_cylinder::read_cylinder(section, d_max, errors).map(Geometry::Cylinder)
        }
        Some("box") => {
            super::resolve_cuboid::read_cuboid(section, d_max, errors).map(Geometry::Cuboid)
        }
        Some("mesh") => {
            super::resolve_mesh::read_mesh(section, d_max, dir, errors).map(Geometry::Mesh)
        }
        Some("heap") => super::resolve_heap::read_heap(section, d_max, errors).map(Geometry::Heap),
        Some("draw_down") => {
            super::resolve_draw_down::read_draw_down(section, d_max, errors).map(Geometry::DrawDown)
        }
        Some(other) => {
            let kind = kind.as_ref().expect("a kind was given");
            let allowed: Vec<String> = GEOMETRY_KINDS.iter().map(|k| format!("\"{k}\"")).collect();
            errors.push(ConfigError::new(
                ErrorKind::Invalid,
                kind.location.clone(),
                kind.key.clone(),
                Some(format!("\"{other}\"")),
                format!(
                    "unknown geometry kind; must be one of {}",
                    allowed.join(", ")
                ),
            ));
            None
        }
    }
}

/// Reads `[geometry]` of the slab hopper; `d_max` is the largest particle diameter [m] with
/// the key that set it, when the particles are valid.
fn read_geometry(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    errors: &mut Vec<ConfigError>,
) -> Option<SlabGeometry> {
    let paper = SlabGeometry::paper();
    let width = section.float_or("width", "m", paper.width, errors);
    let height = section.float_or("height", "m", paper.height, errors);
    let thickness = section.float_or("thickness", "m", paper.thickness, errors);
    let outlet = section.float_or("outlet_width", "m", paper.outlet_width, errors);
    let angle = section.float_or("hopper_angle_deg", "°", paper.hopper_angle_deg, errors);
    let gap = section.float("outlet_gap", "m", errors);
    let offset = section.float("outlet_offset", "m", errors);
    section.finish(
        &[
            "kind",
            "width",
            "height",
            "thickness",
            "outlet_width",
            "hopper_angle_deg",
            "outlet_gap",
            "outlet_offset",
        ],
        errors,
    );
    let mut ok = width.require_positive(errors)
        & height.require_positive(errors)
        & thickness.require_positive(errors)
        & outlet.require_positive(errors);
    // A bad angle does not stop the outlet checks below; it only stops the funnel check.
    let angle_ok = angle.value > 0.0 && angle.value <= 90.0;
    if !angle_ok {
        errors.push(angle.error(
            ErrorKind::Invalid,
            "must lie in (0°, 90°]: the angle of the bottom plates from the vertical, 90° = flat bottom",
        ));
    }
    if let (Some(gap), Some(offset)) = (&gap, &offset) {
        errors.push(offset.error(
            ErrorKind::Conflict,
            format!(
                "give either {} (s) or {} (e), not both",
                gap.key, offset.key
            ),
        ));
        return None;
    }
    if !ok {
        return None;
    }
    let (l, d) = (width.value, outlet.value);
    if d >= l {
        errors.push(outlet.error(
            ErrorKind::DoesNotFit,
            format!("must be < {} ({} m)", width.key, number(l)),
        ));
        ok = false;
    }
    if let Some((d_max, d_source)) = d_max {
        if let Some(why) = outlet_too_small(d, Some((d_max, d_source))) {
            errors.push(outlet.error(ErrorKind::Invalid, why));
            ok = false;
        }
        if thickness.value < d_max {
            errors.push(thickness.error(
                ErrorKind::Invalid,
                format!(
                    "must be ≥ the largest particle diameter ({} m), {d_source}; the paper \
                     uses 1.01 d",
                    rounded(d_max)
                ),
            ));
            ok = false;
        }
    }
    if !ok {
        return None;
    }
    let half_free = 0.5 * (l - d);
    let gap_value = match (gap, offset) {
        (Some(s), None) => {
            if s.value < 0.0 || !s.value.is_finite() {
                errors.push(s.error(
                    ErrorKind::Invalid,
                    "must be ≥ 0 (the gap from the left wall)",
                ));
                return None;
            }
            if s.value + d > l {
                errors.push(s.error(
                    ErrorKind::DoesNotFit,
                    format!(
                        "the outlet does not fit: s + D = {} m exceeds {} ({} m); s must be ≤ L − D = {} m, \
                         from {} and {}",
                        rounded(s.value + d),
                        width.key,
                        number(l),
                        rounded(l - d),
                        source(&width),
                        source(&outlet)
                    ),
                ));
                return None;
            }
            s.value
        }
        (None, Some(e)) => {
            if !(e.value.is_finite() && e.value.abs() <= half_free) {
                errors.push(e.error(
                    ErrorKind::DoesNotFit,
                    format!(
                        "the outlet does not fit: |e| must be ≤ (L − D)/2 = {} m, from {} and {}",
                        rounded(half_free),
                        source(&width),
                        source(&outlet)
                    ),
                ));
                return None;
            }
            half_free - e.value
        }
        _ => half_free,
    };
    if !angle_ok {
        return None;
    }
    let geometry = SlabGeometry {
        width: l,
        height: height.value,
        thickness: thickness.value,
        outlet_width: d,
        hopper_angle_deg: angle.value,
        outlet_gap: gap_value,
    };
    let funnel = geometry.funnel_height();
    if funnel >= geometry.height {
        // The rise is the longer plate's run (L − D)/2 ± e times cot α.
        let position = if gap_value == half_free {
            "a centred outlet".to_string()
        } else {
            format!("an outlet gap s = {} m", rounded(gap_value))
        };
        errors.push(angle.error(
            ErrorKind::DoesNotFit,
            format!(
                "the bottom plates would rise {} m (the longer plate's run times cot α, from {}, {} and {position}), above {} ({} m)",
                rounded(funnel),
                source(&width),
                source(&outlet),
                height.key,
                number(geometry.height)
            ),
        ));
        return None;
    }
    Some(geometry)
}

/// Particles of a mesh container are inserted in the band below `protocol.fill_top` inside
/// the fill box: the band must reach into the box.
fn check_fill_band(
    case: &Case,
    document: &Table,
    source: &Arc<str>,
    errors: &mut Vec<ConfigError>,
) {
    let Geometry::Mesh(g) = &case.geometry else {
        return;
    };
    if case.protocol.fill_top > g.fill_min[2] {
        return;
    }
    let mut root = Section::root(document, source);
    let mut protocol = root.section("protocol", &mut Vec::new());
    let top = protocol
        .float("fill_top", "m", &mut Vec::new())
        .unwrap_or_else(|| protocol.default_value("fill_top", case.protocol.fill_top, "m"));
    errors.push(top.error(
        ErrorKind::Invalid,
        format!(
            "must be > the fill box's bottom, geometry.fill_min[2] = {} m: particles are \
             inserted below fill_top inside the fill box",
            number(g.fill_min[2])
        ),
    ));
}

/// N particles at the densest assumed packing must fit below H (see `Case::packed_area`);
/// `diameter_source` names the key of the largest diameter with its value.
fn check_particles_fit(
    case: &Case,
    document: &Table,
    source: &Arc<str>,
    diameter_source: &str,
    errors: &mut Vec<ConfigError>,
) {
    if case.particles_fit() {
        return;
    }
    let mut root = Section::root(document, source);
    let mut particles = root.section("particles", &mut Vec::new());
    let count = particles
        .integer("count", &mut Vec::new())
        .unwrap_or_else(|| particles.default_value("count", case.particles.count as i64, ""));
    // The inputs of both areas, with their values: the sizes (and, for a thick slab, Z)
    // set the particles' need, the hopper's keys its cross-section.
    let mut geometry = root.section("geometry", &mut Vec::new());
    let mut key = |name: &str, unit: &'static str, value: f64| {
        let located = geometry
            .float(name, unit, &mut Vec::new())
            .unwrap_or_else(|| geometry.default_value(name, value, unit));
        super::sources::source(&located)
    };
    let g = match &case.geometry {
        Geometry::Slab(g) => g,
        // `Case::particles_fit` holds for STL walls.
        Geometry::Mesh(_) => return,
        Geometry::Cuboid(silo) => {
            let keys = [
                key("width", "m", silo.width),
                key("depth", "m", silo.depth),
                key("height", "m", silo.height),
                key("outlet_width", "m", silo.outlet_width),
                key("hopper_angle_deg", "°", silo.hopper_angle_deg),
            ];
            errors.push(silo_does_not_fit(
                &count,
                case,
                silo.volume(),
                &keys,
                diameter_source,
            ));
            return;
        }
        Geometry::DrawDown(test) => {
            let keys = [
                key("width", "m", test.width()),
                key("depth", "m", test.depth()),
                key("height", "m", test.height()),
            ];
            errors.push(silo_does_not_fit(
                &count,
                case,
                test.container.volume(),
                &keys,
                diameter_source,
            ));
            return;
        }
        Geometry::Heap(test) => {
            let keys = [
                key("cylinder_radius", "m", test.cylinder_radius),
                key("height", "m", test.height),
            ];
            errors.push(silo_does_not_fit(
                &count,
                case,
                test.volume(),
                &keys,
                diameter_source,
            ));
            return;
        }
        Geometry::Cylinder(silo) => {
            let keys = [
                key("radius", "m", silo.radius),
                key("height", "m", silo.height),
                key("outlet_diameter", "m", silo.outlet_diameter),
                key("hopper_angle_deg", "°", silo.hopper_angle_deg),
            ];
            errors.push(silo_does_not_fit(
                &count,
                case,
                silo.volume(),
                &keys,
                diameter_source,
            ));
            return;
        }
    };
    let hopper = [
        key("width", "m", g.width),
        key("height", "m", g.height),
        key("outlet_width", "m", g.outlet_width),
        key("hopper_angle_deg", "°", g.hopper_angle_deg),
    ]
    .join(", ");
    let thickness = key("thickness", "m", g.thickness);
    let (what, packing, need) = if case.is_thick_slab() {
        (
            "sphere volume",
            format!("volume fraction {}", super::case::BULK_VOLUME_FRACTION),
            format!("the largest diameter, {diameter_source}, and {thickness}"),
        )
    } else {
        (
            "disc area",
            format!("area fraction {}", super::case::MONOLAYER_AREA_FRACTION),
            format!("the largest diameter, {diameter_source}"),
        )
    };
    errors.push(count.error(
        ErrorKind::DoesNotFit,
        format!(
            "the particles cannot fit: their {what} needs {} m² of the hopper's cross-section at {packing}, \
             but the hopper below H holds {} m²; lower the count or enlarge the hopper \
             (the need comes from the count and the sizes, {need}; the cross-section from {hopper})",
            rounded(case.packed_area()),
            rounded(g.cross_section_area()),
        ),
    ));
}

/// The refusal of a silo's count at `count` whose particles need more than the silo's
/// `volume` [m³] below H, naming the sizes' key `diameter_source` and the silo's `keys`.
fn silo_does_not_fit(
    count: &super::reader::Located<i64>,
    case: &Case,
    volume: f64,
    keys: &[String],
    diameter_source: &str,
) -> ConfigError {
    count.error(
        ErrorKind::DoesNotFit,
        format!(
            "the particles cannot fit: their volume needs {} m³ of the silo at volume fraction \
             {}, but the silo below H holds {} m³; lower the count or enlarge the silo (the need \
             comes from the count and the sizes, the largest diameter being {diameter_source}; \
             the volume from {})",
            rounded(case.packed_volume()),
            super::case::BULK_VOLUME_FRACTION,
            rounded(volume),
            keys.join(", ")
        ),
    )
}

/// Reads `[wall]`. `named` is the case's material table, if any, and `particle_materials`
/// the names of the particles' materials in it (when the particles are valid).
fn read_wall(
    section: &mut Section<'_>,
    named: Option<&NamedMaterials>,
    particle_materials: Option<&[String]>,
    volumes: &mut Vec<Located<f64>>,
    errors: &mut Vec<ConfigError>,
) -> Option<WallSpec> {
    let is_table = section
        .entry("material")
        .is_some_and(|e| matches!(e.node.value, NodeValue::Table(_)));
    let material = if is_table {
        read_material(
            &mut section.section("material", errors),
            MaterialSpec::fan2023(),
            errors,
        )
        .map(|(material, _)| WallMaterialSpec::Custom(material))
    } else {
        let word = section.string("material", errors);
        match word.as_ref().map(|w| w.value.as_str()) {
            None if section.has("material") => None,
            None | Some("same") => match (named, particle_materials) {
                (None, _) => Some(WallMaterialSpec::SameAsParticle),
                // With a table, "same" is the particles' one material, named.
                (Some(_), Some([first, rest @ ..])) if rest.iter().all(|n| n == first) => {
                    Some(WallMaterialSpec::Named(first.clone()))
                }
                (Some(_), Some(_)) => {
                    let location = word
                        .as_ref()
                        .map_or_else(|| section.location().clone(), |w| w.location.clone());
                    errors.push(ConfigError::new(
                        ErrorKind::Missing,
                        location,
                        section.key("material"),
                        word.as_ref().map(|w| format!("\"{}\"", w.value)),
                        "the particles are of several materials: name the walls' material \
                         (a [materials] entry) or \"rigid\"",
                    ));
                    None
                }
                (Some(_), None) => None,
            },
            Some("rigid") => Some(WallMaterialSpec::Rigid),
            Some(_) => {
                let word = word.as_ref().expect("a word was given");
                match named {
                    Some(named) => named
                        .require_known(word, errors)
                        .then(|| WallMaterialSpec::Named(word.value.clone())),
                    None => {
                        errors.push(word.error(
                            ErrorKind::Invalid,
                            "must be one of \"same\", \"rigid\", or a table with density, \
                             shear_modulus, poisson_ratio (a material's name needs a \
                             [materials] table that defines it)",
                        ));
                        None
                    }
                }
            }
        }
    };
    let interaction = read_interaction(section, volumes, errors);
    if matches!(material, Some(WallMaterialSpec::Named(_))) {
        refuse_pair_keys(
            section,
            "the walls are of a named material: each particle material meets them with its \
             [[pairs]] entry (or the mixing rules)",
            errors,
        );
    }
    section.finish(
        &[
            "material",
            "friction",
            "rolling_friction",
            "restitution",
            "cohesion",
        ],
        errors,
    );
    Some(WallSpec {
        material: material?,
        interaction: interaction?,
    })
}

/// Refuses the coefficient keys of `[contact]` or `[wall]` where `[[pairs]]` gives them.
fn refuse_pair_keys(section: &mut Section<'_>, why: &str, errors: &mut Vec<ConfigError>) {
    for key in ["friction", "rolling_friction", "restitution", "cohesion"] {
        if let Some(entry) = section.entry(key) {
            errors.push(ConfigError::new(
                ErrorKind::Conflict,
                entry.key_location.clone(),
                section.key(key),
                Some(entry.node.value.to_string()),
                format!("not used: {why}; give it in [[pairs]]"),
            ));
        }
    }
}

/// Reads `[contact]`; with a material table (`named`), its coefficients come from
/// `[[pairs]]` and the keys here are refused.
fn read_contact(
    section: &mut Section<'_>,
    named: bool,
    volumes: &mut Vec<Located<f64>>,
    errors: &mut Vec<ConfigError>,
) -> Option<ContactSpec> {
    let before = errors.len();
    if named {
        refuse_pair_keys(
            section,
            "the case defines [materials], whose particle pairs come from [[pairs]] (or the \
             mixing rules)",
            errors,
        );
    }
    let interaction = read_interaction(section, volumes, errors);
    let tangential = section.choice(
        "tangential",
        &[
            ("mindlin_no_slip", TangentialLawSpec::MindlinNoSlip),
            ("mindlin_deresiewicz", TangentialLawSpec::MindlinDeresiewicz),
        ],
        TangentialLawSpec::MindlinNoSlip,
        errors,
    );
    let rolling = section.choice(
        "rolling",
        &[
            ("constant_torque", RollingLawSpec::ConstantTorque),
            ("epsd", RollingLawSpec::Epsd),
        ],
        RollingLawSpec::ConstantTorque,
        errors,
    );
    let normal_clamp = section.boolean_or("normal_clamp", false, errors);
    section.finish(
        &[
            "friction",
            "rolling_friction",
            "restitution",
            "cohesion",
            "tangential",
            "rolling",
            "normal_clamp",
        ],
        errors,
    );
    let particle = interaction?;
    (errors.len() == before).then_some(ContactSpec {
        particle,
        tangential,
        rolling,
        normal_clamp,
    })
}
