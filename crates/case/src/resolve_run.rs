//! Validation of the run settings of a case: time step, protocol, measurement, output.

use super::case::{
    Case, FieldKernel, FieldsSpec, MeasureSpec, OutputSpec, Protocol, UnclogMethod, UnclogSpec,
    MAX_AVALANCHES, MAX_FIELD_WIDTHS, MAX_FIELD_WIDTH_DIAMETERS, MAX_RAYLEIGH_FRACTION,
    MAX_UNCLOG_FORCE_RATIO, MIN_FIELD_WIDTH_DIAMETERS,
};
use super::error::{number, rounded, ConfigError, ErrorKind};
use super::particles::ParticleSpec;
use super::reader::Section;
use super::sources::{source, ParticleSources};

/// Largest number of steps between outlet-crossing checks: a particle moves < 4 µm per
/// step, so 100 steps keep the linear interpolation of the crossing well below d/2
/// (physics spec §7.2).
pub(crate) const MAX_CROSSING_CHECK_INTERVAL: i64 = 100;

/// "the Rayleigh time t_R = … s (paper Eq. 9), from <the keys it derives from>".
fn rayleigh_origin(t_r: f64, sources: &ParticleSources) -> String {
    let m = &sources.material;
    format!(
        "the Rayleigh time t_R = π r √(ρ/G)/(0.1631 ν + 0.8766) = {} s (paper Eq. 9) comes from \
         {}, {}, {} and r = half the smallest diameter, {}",
        rounded(t_r),
        m.shear_modulus,
        m.density,
        m.poisson_ratio,
        sources.smallest_diameter
    )
}

/// A time step and where it came from: the key that set it, or the Rayleigh fraction and
/// the keys of the Rayleigh time.
pub(crate) type TimeStep = (f64, String);

/// Reads `[time]`: either `time_step` [s] or `rayleigh_fraction` [-], not both.
pub(crate) fn read_time_step(
    section: &mut Section<'_>,
    particles: Option<&(ParticleSpec, ParticleSources)>,
    errors: &mut Vec<ConfigError>,
) -> Option<TimeStep> {
    let step = section.float("time_step", "s", errors);
    let fraction = section.float("rayleigh_fraction", "", errors);
    section.finish(&["time_step", "rayleigh_fraction"], errors);
    let rayleigh = particles.map(|(p, sources)| (p.rayleigh_time(), sources));
    match (step, fraction) {
        (Some(_), Some(fraction)) => {
            errors.push(fraction.error(
                ErrorKind::Conflict,
                "give either time.time_step or time.rayleigh_fraction, not both",
            ));
            None
        }
        (None, Some(fraction)) => {
            if !(fraction.value > 0.0 && fraction.value <= MAX_RAYLEIGH_FRACTION) {
                errors.push(fraction.error(
                    ErrorKind::Invalid,
                    format!(
                        "must lie in (0, {MAX_RAYLEIGH_FRACTION}] (fraction of the Rayleigh time)"
                    ),
                ));
                return None;
            }
            rayleigh.map(|(t, sources)| {
                let step = fraction.value * t;
                let origin = format!(
                    "set by {} × t_R = {} s, where {}",
                    source(&fraction),
                    rounded(step),
                    rayleigh_origin(t, sources)
                );
                (step, origin)
            })
        }
        (step, None) => {
            let step = step.unwrap_or_else(|| {
                section.default_value("time_step", Case::paper_base().time_step, "s")
            });
            if !step.require_positive(errors) {
                return None;
            }
            let (t_r, sources) = rayleigh?;
            if step.value > MAX_RAYLEIGH_FRACTION * t_r {
                errors.push(step.error(
                    ErrorKind::Invalid,
                    format!(
                        "must be ≤ {MAX_RAYLEIGH_FRACTION} Rayleigh times ({} s for the smallest particle), \
                         where {}; the paper uses < 0.1 t_R",
                        rounded(MAX_RAYLEIGH_FRACTION * t_r),
                        rayleigh_origin(t_r, sources)
                    ),
                ));
                return None;
            }
            Some((step.value, format!("set by {}", source(&step))))
        }
    }
}

/// Reads `[protocol]`; `d_max` [m] (set by the key `d_max_source` names, when the
/// particles are valid) and the hopper height [m] set defaults and limits.
pub(crate) fn read_protocol(
    section: &mut Section<'_>,
    d_max: f64,
    d_max_source: Option<&str>,
    height: Option<f64>,
    (d_min, side_walls): (f64, Option<bool>),
    outlet: Option<f64>,
    errors: &mut Vec<ConfigError>,
) -> Option<Protocol> {
    let base = Case::paper_base().protocol;
    let energy = section.float_or(
        "settle_kinetic_energy",
        "J",
        base.settle_kinetic_energy,
        errors,
    );
    let settle = section.float_or("max_settle_time", "s", base.max_settle_time, errors);
    let bottom = section.float_or("fill_bottom", "m", base.fill_bottom, errors);
    let top = section.float_or("fill_top", "m", height.unwrap_or(base.fill_top), errors);
    let speed = section.float_or("fill_speed", "m/s", base.fill_speed, errors);
    let depth = section.float_or("deletion_depth", "m", 5.0 * d_max, errors);
    let clog = section.float_or("clog_timeout", "s", base.clog_timeout, errors);
    let limit = section.float_or("time_limit", "s", base.time_limit, errors);
    let stop = section.float_or("stop_fraction", "-", base.stop_fraction, errors);
    let slip = section.float_or("wall_slip", "m", base.wall_slip, errors);
    let unclog = section.has("unclog").then(|| {
        let mut unclog = section.section("unclog", errors);
        read_unclog(&mut unclog, d_max, outlet, errors)
    });
    section.finish(
        &[
            "unclog",
            "settle_kinetic_energy",
            "max_settle_time",
            "fill_bottom",
            "fill_top",
            "fill_speed",
            "deletion_depth",
            "clog_timeout",
            "time_limit",
            "stop_fraction",
            "wall_slip",
        ],
        errors,
    );
    let mut ok = energy.require_positive(errors)
        & settle.require_positive(errors)
        & bottom.require_non_negative(errors)
        & top.require_positive(errors)
        & speed.require_non_negative(errors)
        & clog.require_positive(errors)
        & limit.require_positive(errors)
        & stop.require_positive(errors);
    if ok && stop.value > 1.0 {
        errors.push(stop.error(ErrorKind::Invalid, "must be in (0, 1]".to_string()));
        ok = false;
    }
    // The slip opens a gap of its size under the side walls (or between a cylinder and its
    // cone): at most half the smallest diameter keeps every sphere inside.
    if slip.require_non_negative(errors) {
        if slip.value > 0.5 * d_min {
            errors.push(slip.error(
                ErrorKind::Invalid,
                format!(
                    "must be in [0, {} m], half the smallest particle diameter, so that the \
                     gap the slip opens under the side walls keeps every sphere inside",
                    rounded(0.5 * d_min)
                ),
            ));
            ok = false;
        } else if slip.value > 0.0 && side_walls == Some(false) {
            errors.push(slip.error(
                ErrorKind::Invalid,
                "must be 0 here: only a cylinder's or a box's side walls can slip past \
                 the bed (geometry.kind = \"cylinder\" or \"box\")",
            ));
            ok = false;
        }
    } else {
        ok = false;
    }
    if ok && bottom.value >= top.value {
        // A default fill_top is geometry.height: name it, since the user wrote neither.
        let origin = match height {
            Some(h) if !top.given => format!("; its default is geometry.height = {} m", number(h)),
            _ => String::new(),
        };
        errors.push(top.error(
            ErrorKind::Invalid,
            format!(
                "must be > {} ({} m){origin}",
                bottom.key,
                number(bottom.value)
            ),
        ));
        ok = false;
    }
    if let Some(h) = height {
        if top.value > h {
            errors.push(top.error(
                ErrorKind::Invalid,
                format!("must be ≤ geometry.height ({} m)", number(h)),
            ));
            ok = false;
        }
    }
    // Particles must be wholly below the outlet line before they vanish, or the
    // crossing and strip measurements would lose them (physics spec §5: about 5 d).
    if !(depth.value.is_finite() && depth.value >= d_max) {
        errors.push(depth.error(
            ErrorKind::Invalid,
            format!(
                "must be ≥ the largest particle diameter ({} m{})",
                rounded(d_max),
                d_max_source.map_or(String::new(), |s| format!(", {s}"))
            ),
        ));
        ok = false;
    }
    ok.then_some(Protocol {
        settle_kinetic_energy: energy.value,
        max_settle_time: settle.value,
        fill_bottom: bottom.value,
        fill_top: top.value,
        fill_speed: speed.value,
        deletion_depth: depth.value,
        clog_timeout: clog.value,
        time_limit: limit.value,
        stop_fraction: stop.value,
        wall_slip: slip.value,
        unclog: unclog.flatten(),
    })
    .filter(|_| !matches!(unclog, Some(None)))
}

/// Default height of the unclogging pulse's region, in outlet sizes D, plus
/// [`UNCLOG_HEIGHT_DIAMETERS`] largest diameters: an arch stands within D + d of the
/// outlet line (`measure::find_arch`), and the pulse reaches a few grains above it.
const UNCLOG_HEIGHT_OUTLETS: f64 = 1.0;
/// See [`UNCLOG_HEIGHT_OUTLETS`].
const UNCLOG_HEIGHT_DIAMETERS: f64 = 2.0;

/// Reads `[protocol.unclog]` (docs/physics.md §5.11); `d_max` [m] and the outlet size D [m]
/// (when the geometry is valid) set the region's default height and its limits.
fn read_unclog(
    section: &mut Section<'_>,
    d_max: f64,
    outlet: Option<f64>,
    errors: &mut Vec<ConfigError>,
) -> Option<UnclogSpec> {
    let method = section.choice(
        "method",
        &[("air_jet", UnclogMethod::AirJet)],
        UnclogMethod::AirJet,
        errors,
    );
    let ratio = section.float_or("force_ratio", "-", 25.0, errors);
    let growth = section.float_or("growth", "-", 1.5, errors);
    let duration = section.float_or("duration", "s", 0.01, errors);
    let default_height = outlet.map_or(f64::NAN, |d| {
        UNCLOG_HEIGHT_OUTLETS * d + UNCLOG_HEIGHT_DIAMETERS * d_max
    });
    let height = section.float_or("height", "m", default_height, errors);
    let avalanches = section.integer_or("avalanches", 100, errors);
    let pulses = section.integer_or("max_pulses", 10, errors);
    section.finish(
        &[
            "method",
            "force_ratio",
            "growth",
            "duration",
            "height",
            "avalanches",
            "max_pulses",
        ],
        errors,
    );
    let mut ok = true;
    // Below 1 the pulse would not even lift a free grain against its weight.
    if !(ratio.value > 1.0 && ratio.value <= MAX_UNCLOG_FORCE_RATIO) {
        errors.push(ratio.error(
            ErrorKind::Invalid,
            format!(
                "must lie in (1, {MAX_UNCLOG_FORCE_RATIO}] (the pulse's force on a grain over its \
                 weight: above 1 to lift it)"
            ),
        ));
        ok = false;
    }
    // 1 keeps every pulse alike; 4 reaches the strongest pulse from the weakest in three.
    if !(1.0..=4.0).contains(&growth.value) {
        errors.push(growth.error(
            ErrorKind::Invalid,
            "must lie in [1, 4] (each further pulse of a clog over the last)",
        ));
        ok = false;
    }
    let positive = duration.require_positive(errors);
    if positive && duration.value > 1.0 {
        errors.push(duration.error(
            ErrorKind::Invalid,
            "must be in (0, 1] s: a pulse is short beside the flow it restarts",
        ));
        ok = false;
    }
    ok &= positive;
    if outlet.is_some_and(f64::is_nan) {
        errors.push(ConfigError::new(
            ErrorKind::Invalid,
            section.location().clone(),
            section.key("").trim_end_matches('.').to_string(),
            None,
            "needs a container with an outlet (the heap test has none)".to_string(),
        ));
        ok = false;
    } else if outlet.is_some() && !(height.value >= d_max && height.value.is_finite()) {
        errors.push(height.error(
            ErrorKind::Invalid,
            format!(
                "must be finite and ≥ the largest particle diameter ({} m), so that the \
                 region holds the arch's grains",
                rounded(d_max)
            ),
        ));
        ok = false;
    }
    if !(1..=MAX_AVALANCHES).contains(&avalanches.value) {
        errors.push(avalanches.error(
            ErrorKind::Invalid,
            format!("must be an integer in [1, {MAX_AVALANCHES}]"),
        ));
        ok = false;
    }
    if !(1..=1000).contains(&pulses.value) {
        errors.push(pulses.error(ErrorKind::Invalid, "must be an integer in [1, 1000]"));
        ok = false;
    }
    (ok && outlet.is_some()).then_some(UnclogSpec {
        method,
        force_ratio: ratio.value,
        growth: growth.value,
        duration: duration.value,
        height: height.value,
        avalanches: avalanches.value as u32,
        max_pulses: pulses.value as u32,
    })
}

/// Reads `[measure]`; diameters, outlet width [m] and time step [s] set defaults and limits.
/// `d_max_source` names the key of the largest diameter (for the default bin width), and
/// the time step comes with where it was set.
pub(crate) fn read_measure(
    section: &mut Section<'_>,
    d_max: f64,
    d_max_source: Option<&str>,
    outlet: Option<(f64, &str)>,
    time_step: Option<&TimeStep>,
    stop_fraction: Option<f64>,
    errors: &mut Vec<ConfigError>,
) -> Option<MeasureSpec> {
    let base = Case::paper_base().measure;
    let rate_bin = section.float_or("rate_bin_width", "s", base.rate_bin_width, errors);
    let x_bin = section.float_or("x_bin_width", "m", 0.5 * d_max, errors);
    let strip = section.float_or("strip_height", "m", d_max, errors);
    let frame = section.float_or("frame_interval", "s", base.frame_interval, errors);
    let crossing = section.integer_or(
        "crossing_check_interval",
        i64::from(base.crossing_check_interval),
        errors,
    );
    let start = section.float_or(
        "steady_start_fraction",
        "",
        base.steady_start_fraction,
        errors,
    );
    let end = section.float_or("steady_end_fraction", "", base.steady_end_fraction, errors);
    section.finish(
        &[
            "rate_bin_width",
            "x_bin_width",
            "strip_height",
            "frame_interval",
            "crossing_check_interval",
            "steady_start_fraction",
            "steady_end_fraction",
        ],
        errors,
    );
    let mut ok = rate_bin.require_positive(errors)
        & x_bin.require_positive(errors)
        & strip.require_positive(errors)
        & frame.require_positive(errors);
    if let Some((dt, origin)) = time_step {
        for interval in [&rate_bin, &frame] {
            if interval.value < *dt {
                errors.push(interval.error(
                    ErrorKind::Invalid,
                    format!("must be ≥ the time step ({} s), {origin}", rounded(*dt)),
                ));
                ok = false;
            }
        }
    }
    if let Some((d, outlet_key)) = outlet {
        if x_bin.value > d {
            // The default bin width is d/2: name the diameter's key when it applies.
            let origin = match d_max_source {
                Some(s) if !x_bin.given => {
                    format!("; its default is half the largest particle diameter, {s}")
                }
                _ => String::new(),
            };
            errors.push(x_bin.error(
                ErrorKind::Invalid,
                format!(
                    "must be ≤ {outlet_key} ({} m) to resolve a profile{origin}",
                    number(d)
                ),
            ));
            ok = false;
        }
    }
    if !(1..=MAX_CROSSING_CHECK_INTERVAL).contains(&crossing.value) {
        errors.push(crossing.error(
            ErrorKind::Invalid,
            format!("must be an integer number of steps in [1, {MAX_CROSSING_CHECK_INTERVAL}]"),
        ));
        ok = false;
    }
    if !(start.value >= 0.0 && start.value < end.value && end.value <= 1.0) {
        errors.push(end.error(
            ErrorKind::Invalid,
            format!(
                "need 0 ≤ {} ({}) < {} ≤ 1",
                start.key,
                number(start.value),
                end.key
            ),
        ));
        ok = false;
    }
    // The window is measured in fractions of the fill (`run::outputs`): a run stopped
    // before its end could not measure it, and would silently fall back to a shorter one.
    if let Some(stop) = stop_fraction {
        if ok && end.value > stop {
            errors.push(end.error(
                ErrorKind::Invalid,
                format!(
                    "must be ≤ protocol.stop_fraction ({}): the run would stop before the \
                     steady window ends; lower it or raise protocol.stop_fraction",
                    number(stop)
                ),
            ));
            ok = false;
        }
    }
    ok.then_some(MeasureSpec {
        rate_bin_width: rate_bin.value,
        x_bin_width: x_bin.value,
        strip_height: strip.value,
        frame_interval: frame.value,
        crossing_check_interval: crossing.value as u32,
        steady_start_fraction: start.value,
        steady_end_fraction: end.value,
    })
}

/// Reads `[output]` and its optional `[output.fields]`; the largest diameter [m] (with the
/// key it comes from) and the time step bound the fields' widths and intervals.
pub(crate) fn read_output(
    section: &mut Section<'_>,
    (d_max, d_max_source, gridded): (f64, Option<&str>, Option<bool>),
    time_step: Option<&TimeStep>,
    errors: &mut Vec<ConfigError>,
) -> (Option<OutputSpec>, Option<FieldsSpec>) {
    let base = Case::paper_base().output;
    let vtu = section.float_or("vtu_interval", "s", base.vtu_interval, errors);
    let checkpoint = section.float_or("checkpoint_interval", "s", base.checkpoint_interval, errors);
    let plots = section.boolean_or("plots", base.plots, errors);
    let fields = section
        .has("fields")
        .then(|| {
            let mut fields = section.section("fields", errors);
            if gridded == Some(false) {
                errors.push(ConfigError::new(
                    ErrorKind::Invalid,
                    fields.location().clone(),
                    fields.key("").trim_end_matches('.').to_string(),
                    None,
                    "coarse-grained fields need a geometry of kind \"slab\", \"box\" or \
                     \"cylinder\" (an (x, z) or (r, z) grid)"
                        .to_string(),
                ));
            }
            read_fields(&mut fields, (d_max, d_max_source), time_step, errors)
        })
        .flatten();
    section.finish(
        &["vtu_interval", "checkpoint_interval", "plots", "fields"],
        errors,
    );
    let ok = vtu.require_non_negative(errors) & checkpoint.require_non_negative(errors);
    let output = ok.then_some(OutputSpec {
        vtu_interval: vtu.value,
        checkpoint_interval: checkpoint.value,
        plots,
    });
    (output, fields)
}

/// Reads `[output.fields]` (docs/physics.md §7.13): every width within
/// [`MIN_FIELD_WIDTH_DIAMETERS`, `MAX_FIELD_WIDTH_DIAMETERS`] largest diameters, the cells
/// no larger than the smallest width (so that they sample the kernel), the window and the
/// interval at least a time step, the interval no longer than the window.
fn read_fields(
    section: &mut Section<'_>,
    (d_max, d_max_source): (f64, Option<&str>),
    time_step: Option<&TimeStep>,
    errors: &mut Vec<ConfigError>,
) -> Option<FieldsSpec> {
    let kernel = section.choice(
        "kernel",
        &[
            ("lucy", FieldKernel::Lucy),
            ("gaussian", FieldKernel::Gaussian),
        ],
        FieldKernel::Lucy,
        errors,
    );
    let width = section.float_or("width", "m", 0.5 * d_max, errors);
    let widths = section
        .float_array("widths", "m", errors)
        .unwrap_or_default();
    let smallest = widths.iter().map(|w| w.value).fold(width.value, f64::min);
    let cell = section.float_or("cell_size", "m", 0.5 * smallest, errors);
    let window = section.float_or("window", "s", 0.5, errors);
    let interval = section.float_or("interval", "s", 1.0e-3, errors);
    section.finish(
        &[
            "kernel",
            "width",
            "widths",
            "cell_size",
            "window",
            "interval",
        ],
        errors,
    );
    let mut ok = cell.require_positive(errors)
        & window.require_positive(errors)
        & interval.require_positive(errors);
    let (low, high) = (
        MIN_FIELD_WIDTH_DIAMETERS * d_max,
        MAX_FIELD_WIDTH_DIAMETERS * d_max,
    );
    let diameter = d_max_source.unwrap_or("the largest particle diameter");
    for w in std::iter::once(&width).chain(&widths) {
        if !(w.value >= low && w.value <= high) {
            errors.push(w.error(
                ErrorKind::Invalid,
                format!(
                    "must be in [{}, {}] m: {MIN_FIELD_WIDTH_DIAMETERS} to {MAX_FIELD_WIDTH_DIAMETERS} times the largest diameter ({diameter}); the branch quadrature is sized for w ≥ d/4",
                    number(low),
                    number(high)
                ),
            ));
            ok = false;
        }
    }
    if widths.len() > MAX_FIELD_WIDTHS {
        errors.push(widths[MAX_FIELD_WIDTHS].error(
            ErrorKind::Invalid,
            format!("at most {MAX_FIELD_WIDTHS} widths may be checked"),
        ));
        ok = false;
    }
    if ok && cell.value > smallest {
        errors.push(cell.error(
            ErrorKind::Invalid,
            format!(
                "must be in (0, {}] m: no larger than the smallest kernel width, so that the cells sample the kernel",
                number(smallest)
            ),
        ));
        ok = false;
    }
    if let Some((dt, origin)) = time_step {
        for t in [&window, &interval] {
            if t.value < *dt {
                errors.push(t.error(
                    ErrorKind::Invalid,
                    format!("must be ≥ the time step ({} s), {origin}", rounded(*dt)),
                ));
                ok = false;
            }
        }
    }
    if window.value > 0.0 && interval.value > window.value {
        errors.push(interval.error(
            ErrorKind::Invalid,
            format!(
                "must be in (0, {}] s: no longer than output.fields.window, so that every                  window holds a frame",
                number(window.value)
            ),
        ));
        ok = false;
    }
    ok.then(|| FieldsSpec {
        kernel,
        width: width.value,
        cell_size: cell.value,
        window: window.value,
        interval: interval.value,
        widths: widths.iter().map(|w| w.value).collect(),
    })
}
