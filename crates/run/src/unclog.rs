//! Breaking arches and going on (`[protocol.unclog]`, docs/physics.md §5.11): the record of
//! the clogs of a run, the pulse that breaks each arch, and the avalanches between them
//! (`avalanches.csv`, docs/physics.md §7.14).
//!
//! The avalanches are not stored: they are the outlet crossings (which the run keeps
//! anyway, `crossings.csv`) cut at the clogs. The record holds, per clog, how many
//! crossings came before it, where its arch stood and how many pulses it took.

use serde::{Deserialize, Serialize};

use analysis::clogging::{
    censored_exponential_mean, exponential_size_tail, power_law_tail, TailFit,
};
use case::{Case, UnclogSpec};
use dem::{DVec3, ForceRegion, RegionForce};
use files::{AvalancheSummary, Cell, StopReason, TailFitSummary};
use measure::{Arch, CrossingEvent, OutletGeometry, OutletShape};

/// One clog of a run that breaks its arches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Clog {
    /// When the clog was declared, `protocol.clog_timeout` after the last grain [s].
    pub declared: f64,
    /// Outlet crossings before it: the avalanche it ended is the crossings from the
    /// previous clog's count to this one [-].
    pub crossings: usize,
    /// Grains in the arch [-] (0 where none was found over the opening).
    pub arch_particles: usize,
    /// The arch's apex: its highest grain's centre above the outlet line [m] (NaN without).
    pub arch_apex_height: f64,
    /// The largest horizontal distance between the arch's grains' centres [m] (NaN without).
    pub arch_span: f64,
    /// Pulses given to break it [-].
    pub pulses: u32,
}

/// The clogs of a run that breaks its arches, in order; part of the checkpoint.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct UnclogRecord {
    /// Each clog.
    pub clogs: Vec<Clog>,
    /// When the grains the last pulse lifted are back [s]: a free grain pushed up at
    /// (r − 1) g for the pulse's duration τ (r its force ratio) flies for 2 (r − 1) τ after
    /// it. Before then an opening with no arch over it is no sign that the container has
    /// drained: its grains are in the air.
    pub landing: f64,
}

/// What the run does at a declared clog.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum AtClog {
    /// Give a pulse.
    Pulse,
    /// Stop, for this reason.
    Stop(StopReason),
}

impl UnclogRecord {
    /// Records a clog declared at `time` [s] after `crossings` crossings in all, with the
    /// arch found over the opening, and says what comes next. A clog with no crossing since
    /// the last pulse is that pulse's failure: the same clog, pulsed again, until
    /// `max_pulses` pulses; a clog after new crossings ends an avalanche, and the run stops
    /// once `avalanches` have ended so.
    pub(crate) fn declare(
        &mut self,
        spec: &UnclogSpec,
        time: f64,
        crossings: usize,
        arch: Option<&Arch>,
    ) -> AtClog {
        let before = self.clogs.last().map_or(0, |c| c.crossings);
        let new_avalanche = self.clogs.is_empty() || crossings > before;
        if new_avalanche {
            self.clogs.push(Clog {
                declared: time,
                crossings,
                arch_particles: arch.map_or(0, |a| a.members.len()),
                arch_apex_height: arch.map_or(f64::NAN, Arch::apex_height),
                arch_span: arch.map_or(f64::NAN, Arch::span),
                pulses: 0,
            });
            if self.avalanches() >= spec.avalanches as usize {
                return AtClog::Stop(StopReason::Avalanches);
            }
        }
        let clog = self.clogs.last_mut().expect("a clog was pushed");
        if clog.pulses >= spec.max_pulses {
            return AtClog::Stop(StopReason::Clogged);
        }
        clog.pulses += 1;
        AtClog::Pulse
    }

    /// The force ratio of the pulse now given [-]: that of the last clog's latest pulse
    /// ([`UnclogSpec::force_ratio_of_pulse`]).
    pub(crate) fn current_ratio(&self, spec: &UnclogSpec) -> f64 {
        spec.force_ratio_of_pulse(self.clogs.last().map_or(1, |c| c.pulses))
    }

    /// Avalanches ended by a clog so far [-]. A first clog before any grain left is no
    /// avalanche.
    pub fn avalanches(&self) -> usize {
        self.clogs.iter().filter(|c| c.crossings > 0).count()
    }
}

/// The pulse's force for `case`'s orifice (docs/physics.md §5.11): upward, on the grains
/// whose centres lie over the orifice's footprint from a diameter below the outlet line to
/// `height` above it; `ratio` times the weight of a grain of the mean diameter, each grain's
/// share scaled by its cross-section.
pub(crate) fn pulse_force(
    case: &Case,
    spec: &UnclogSpec,
    ratio: f64,
    outlet: &OutletGeometry,
) -> RegionForce {
    let d = case.particles.mean_diameter();
    let r = 0.5 * d;
    let weight =
        case.particles.density() * (4.0 / 3.0) * std::f64::consts::PI * r.powi(3) * case.gravity;
    let traction = ratio * weight / (std::f64::consts::PI * r * r);
    let (bottom, top) = (outlet.outlet_height - d, outlet.outlet_height + spec.height);
    let o = outlet;
    let region = match o.shape {
        OutletShape::Slot => {
            // A slot spans the container's depth: the box reaches well beyond any wall in y.
            let depth = case.geometry.height().max(1.0);
            ForceRegion::Box {
                min: DVec3::new(o.centre - o.half_width, -depth, bottom),
                max: DVec3::new(o.centre + o.half_width, depth, top),
            }
        }
        OutletShape::Circle { centre_y } => ForceRegion::Cylinder {
            axis: [o.centre, centre_y],
            radius: o.half_width,
            bottom,
            top,
        },
        OutletShape::Rectangle {
            centre_y,
            half_depth,
        } => ForceRegion::Box {
            min: DVec3::new(o.centre - o.half_width, centre_y - half_depth, bottom),
            max: DVec3::new(o.centre + o.half_width, centre_y + half_depth, top),
        },
    };
    RegionForce {
        region,
        traction: DVec3::new(0.0, 0.0, traction),
    }
}

/// One avalanche: a run of outlet crossings between two clogs (or from the opening, or to
/// the run's stop).
#[derive(Debug, Clone, PartialEq)]
pub struct Avalanche {
    /// Grains that left [-].
    pub size: usize,
    /// Their mass [kg].
    pub mass: f64,
    /// The first grain's crossing time from the start of the run [s].
    pub start: f64,
    /// The last grain's [s].
    pub end: f64,
    /// From the previous avalanche's last grain to this one's first [s]; NaN for the first.
    pub arrest_before: f64,
    /// Pulses it took to start it [-] (0 for the first, which the gate's opening started).
    pub pulses_before: u32,
    /// The clog that ended it, `None` for the last one when the run stopped otherwise.
    pub ended_by: Option<Clog>,
}

/// The avalanches of a run: the crossings `events` (in time order) cut at the clogs of
/// `record`; the crossings after the last clog make a last avalanche, ended by the run's
/// stop, where there are any.
pub fn avalanches(events: &[CrossingEvent], record: &UnclogRecord) -> Vec<Avalanche> {
    let mut out: Vec<Avalanche> = Vec::new();
    let mut from = 0usize;
    let mut pulses_before = 0u32;
    let mut cuts: Vec<(usize, Option<&Clog>)> = record
        .clogs
        .iter()
        .map(|c| (c.crossings.min(events.len()), Some(c)))
        .collect();
    cuts.push((events.len(), None));
    for (to, clog) in cuts {
        if to > from {
            let grains = &events[from..to];
            let previous_end = out.last().map_or(f64::NAN, |a: &Avalanche| a.end);
            let start = grains.iter().map(|e| e.time).fold(f64::INFINITY, f64::min);
            out.push(Avalanche {
                size: grains.len(),
                mass: grains.iter().map(|e| e.mass).sum(),
                start,
                end: grains
                    .iter()
                    .map(|e| e.time)
                    .fold(f64::NEG_INFINITY, f64::max),
                arrest_before: start - previous_end,
                pulses_before,
                ended_by: clog.cloned(),
            });
            from = to;
        }
        if let Some(c) = clog {
            // A clog with no grain since the one before (the first, before any grain left)
            // adds its pulses to the next avalanche's.
            pulses_before = if to > 0 && out.last().is_some_and(|a| a.ended_by.is_some()) {
                c.pulses
            } else {
                pulses_before + c.pulses
            };
        }
    }
    out
}

/// The time lapses between consecutive grains within each avalanche that a clog ended [s]:
/// the arrests between avalanches, set by the protocol, are left out.
pub fn lapses(events: &[CrossingEvent], record: &UnclogRecord) -> Vec<f64> {
    let mut out = Vec::new();
    let mut from = 0usize;
    for c in &record.clogs {
        let to = c.crossings.min(events.len());
        if to > from {
            let mut times: Vec<f64> = events[from..to].iter().map(|e| e.time).collect();
            times.sort_by(f64::total_cmp);
            out.extend(times.windows(2).map(|w| w[1] - w[0]));
            from = to;
        }
    }
    out
}

/// Columns of `avalanches.csv`, SI units in the names.
pub const AVALANCHE_COLUMNS: [&str; 12] = [
    "avalanche",
    "size_grains",
    "mass_kg",
    "start_s",
    "end_s",
    "duration_s",
    "arrest_before_s",
    "pulses_before",
    "ended_by",
    "arch_grains",
    "arch_apex_height_m",
    "arch_span_m",
];

/// The rows of `avalanches.csv`; the last avalanche, if no clog ended it, says what did
/// (`stop`) in its `ended_by` and has no arch.
pub fn avalanche_rows(avalanches: &[Avalanche], stop: StopReason) -> Vec<Vec<Cell>> {
    let stop = serde_json::to_value(stop)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default();
    avalanches
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let clog = a.ended_by.as_ref();
            vec![
                Cell::Text(k.to_string()),
                Cell::Text(a.size.to_string()),
                a.mass.into(),
                a.start.into(),
                a.end.into(),
                (a.end - a.start).into(),
                a.arrest_before.into(),
                Cell::Text(a.pulses_before.to_string()),
                Cell::Text(clog.map_or(stop.clone(), |_| "clog".to_string())),
                Cell::Text(clog.map_or(0, |c| c.arch_particles).to_string()),
                clog.map_or(f64::NAN, |c| c.arch_apex_height).into(),
                clog.map_or(f64::NAN, |c| c.arch_span).into(),
            ]
        })
        .collect()
}

/// Smallest number of tail samples for a tail fit: below it the asymptotic error is no
/// guide.
const MIN_TAIL_SAMPLES: usize = 10;

/// The summary of the avalanches a clog ended (docs/physics.md §7.14): their mean size with
/// its standard error, means of mass, duration and arrest, the pulses, and the two tail
/// fits. The size tail starts at the median size (the exponential holds beyond the small
/// sizes, Zuriguel et al. 2005), the lapse tail at ten times the median lapse (the tail
/// of the rare long lapses, beyond the flowing bulk of the distribution).
pub fn avalanche_summary(
    avalanches: &[Avalanche],
    lapses: &[f64],
    record: &UnclogRecord,
) -> AvalancheSummary {
    let ended: Vec<&Avalanche> = avalanches.iter().filter(|a| a.ended_by.is_some()).collect();
    let n = ended.len();
    let mean = |f: &dyn Fn(&Avalanche) -> f64| {
        let values: Vec<f64> = ended
            .iter()
            .map(|a| f(a))
            .filter(|v| v.is_finite())
            .collect();
        if values.is_empty() {
            f64::NAN
        } else {
            values.iter().sum::<f64>() / values.len() as f64
        }
    };
    let sizes: Vec<f64> = ended.iter().map(|a| a.size as f64).collect();
    let mean_size = mean(&|a| a.size as f64);
    let mean_size_error = if n >= 2 {
        let var = sizes.iter().map(|s| (s - mean_size).powi(2)).sum::<f64>() / (n - 1) as f64;
        (var / n as f64).sqrt()
    } else {
        f64::NAN
    };
    let tail = |fit: Result<TailFit, analysis::AnalysisError>| {
        fit.ok()
            .filter(|f| f.samples >= MIN_TAIL_SAMPLES)
            .map(|f| TailFitSummary {
                threshold: f.threshold,
                samples: f.samples,
                value: f.parameter.value,
                error: f.parameter.standard_error,
            })
    };
    let cut: Vec<f64> = avalanches
        .iter()
        .filter(|a| a.ended_by.is_none())
        .map(|a| a.size as f64)
        .collect();
    let censored = censored_exponential_mean(&sizes, &cut).ok();
    let size_tail = tail(exponential_size_tail(&sizes, median(&sizes)));
    let lapse_tail = tail(power_law_tail(lapses, 10.0 * median(lapses)));
    let pulses: usize = record.clogs.iter().map(|c| c.pulses as usize).sum();
    // A clog's pulses all failed but the last, where grains left after it; where none did
    // (the run stopped after its pulses failed), all of them.
    let total: usize = avalanches.iter().map(|a| a.size).sum();
    let failed: usize = record
        .clogs
        .iter()
        .map(|c| {
            let broken = total > c.crossings;
            (c.pulses as usize).saturating_sub(usize::from(broken))
        })
        .sum();
    AvalancheSummary {
        count: n,
        mean_size,
        mean_size_error,
        mean_size_censored: censored.map_or(f64::NAN, |e| e.value),
        mean_size_censored_error: censored.map_or(f64::NAN, |e| e.standard_error),
        mean_mass: mean(&|a| a.mass),
        mean_duration: mean(&|a| a.end - a.start),
        mean_arrest: mean(&|a| a.arrest_before),
        pulses,
        failed_pulses: failed,
        size_tail,
        lapse_tail,
    }
}

/// The median of finite samples (NaN for none).
fn median(values: &[f64]) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn event(time: f64) -> CrossingEvent {
        CrossingEvent {
            time,
            x: 0.0,
            velocity_z: -0.5,
            mass: 1.0e-4,
            inside_outlet: true,
            velocity_x: 0.0,
            radius: 1.5e-3,
            id: 0,
            y: 0.0,
        }
    }

    fn spec(avalanches: u32, max_pulses: u32) -> UnclogSpec {
        UnclogSpec {
            method: case::UnclogMethod::AirJet,
            force_ratio: 3.0,
            growth: 1.5,
            duration: 0.02,
            height: 0.03,
            avalanches,
            max_pulses,
        }
    }

    #[test]
    fn clogs_cut_the_crossings_into_avalanches_and_failed_pulses_repeat() {
        let spec = spec(3, 2);
        let mut record = UnclogRecord::default();
        // Three grains, a clog; a pulse that fails (no grain), a second that works; two
        // grains, a clog; then a last grain before the run's time limit.
        assert_eq!(record.declare(&spec, 1.0, 3, None), AtClog::Pulse);
        assert_eq!(record.declare(&spec, 1.5, 3, None), AtClog::Pulse);
        assert_eq!(record.declare(&spec, 2.5, 5, None), AtClog::Pulse);
        assert_eq!(record.clogs.len(), 2);
        assert_eq!(record.clogs[0].pulses, 2);
        let times = [0.1, 0.2, 0.4, 1.9, 2.0, 2.9];
        let events: Vec<CrossingEvent> = times.iter().map(|&t| event(t)).collect();
        let list = avalanches(&events, &record);
        let sizes: Vec<usize> = list.iter().map(|a| a.size).collect();
        assert_eq!(sizes, [3, 2, 1]);
        // The second avalanche's arrest runs from 0.4 s to 1.9 s and took two pulses.
        assert!((list[1].arrest_before - 1.5).abs() < 1e-12);
        assert_eq!(list[1].pulses_before, 2);
        assert!(list[0].arrest_before.is_nan());
        assert!(list[2].ended_by.is_none());
        // Lapses within the two clog-ended avalanches only: 0.1, 0.2 and 0.1 s.
        let l = lapses(&events, &record);
        assert_eq!(l.len(), 3);
        assert!((l.iter().sum::<f64>() - 0.4).abs() < 1e-12);
        // A third clog after new grains ends the third avalanche: the count is reached.
        assert_eq!(
            record.declare(&spec, 3.5, 6, None),
            AtClog::Stop(StopReason::Avalanches)
        );
        // With two pulses failing in a row at most, a third failure stops the run.
        let mut stuck = UnclogRecord::default();
        assert_eq!(stuck.declare(&spec, 1.0, 4, None), AtClog::Pulse);
        assert_eq!(stuck.declare(&spec, 2.0, 4, None), AtClog::Pulse);
        assert_eq!(
            stuck.declare(&spec, 3.0, 4, None),
            AtClog::Stop(StopReason::Clogged)
        );
    }

    #[test]
    fn each_further_pulse_of_a_clog_grows_up_to_fifty_weights() {
        // κ = 3, growth 1.5: 3, 4.5, 6.75, … while one clog holds; 1.5^10 · 3 ≈ 173 is cut
        // to the largest ratio a case accepts, 50; a new clog starts again from κ.
        let spec = spec(5, 100);
        let mut record = UnclogRecord::default();
        let ratios: Vec<f64> = (0..12)
            .map(|_| {
                assert_eq!(record.declare(&spec, 1.0, 7, None), AtClog::Pulse);
                record.current_ratio(&spec)
            })
            .collect();
        assert_eq!(&ratios[..3], &[3.0, 4.5, 6.75]);
        assert_eq!(ratios[11], 50.0);
        assert_eq!(record.declare(&spec, 2.0, 9, None), AtClog::Pulse);
        assert_eq!(record.current_ratio(&spec), 3.0);
    }

    #[test]
    fn the_summary_averages_the_clog_ended_avalanches_only() {
        let spec = spec(10, 3);
        let mut record = UnclogRecord::default();
        let mut events = Vec::new();
        let mut t = 0.0;
        // Avalanches of 2, 4 and 6 grains 10 ms apart, each ended by a clog, then 100
        // grains cut by the time limit, which the means must leave out.
        for size in [2usize, 4, 6] {
            for _ in 0..size {
                t += 0.01;
                events.push(event(t));
            }
            t += 0.5;
            record.declare(&spec, t, events.len(), None);
        }
        for _ in 0..100 {
            t += 0.01;
            events.push(event(t));
        }
        let list = avalanches(&events, &record);
        let s = avalanche_summary(&list, &lapses(&events, &record), &record);
        assert_eq!(s.count, 3);
        assert!((s.mean_size - 4.0).abs() < 1e-12);
        // The sample standard deviation of 2, 4, 6 is 2, over √3.
        assert!((s.mean_size_error - 2.0 / 3f64.sqrt()).abs() < 1e-12);
        // With the cut avalanche as a censored size: (2 + 4 + 6 + 100)/3, error that over √3.
        assert!((s.mean_size_censored - 112.0 / 3.0).abs() < 1e-12);
        assert!((s.mean_size_censored_error - 112.0 / 3.0 / 3f64.sqrt()).abs() < 1e-12);
        // Three clogs, a pulse each: the first two restarted the flow, the third's did too
        // (the 100 grains after it); none failed.
        assert_eq!((s.pulses, s.failed_pulses), (3, 0));
        assert!(s.size_tail.is_none(), "three sizes are too few for a tail");
        // A last clog pulsed three times in vain (no grain after it): three failures.
        record.clogs.push(Clog {
            crossings: events.len(),
            pulses: 3,
            ..record.clogs[0].clone()
        });
        let s = avalanche_summary(&avalanches(&events, &record), &[], &record);
        assert_eq!((s.pulses, s.failed_pulses), (6, 3));
    }
}
