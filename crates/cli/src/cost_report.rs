//! The cost estimate printed before `run` and `study` (docs/user-guide.md, "What a run
//! costs"), and the refusal of work that could not finish unless `--no-cost-check`.

use run::cost::{
    bytes_in_words, duration_in_words, CostEstimate, DischargeModel, PhaseTimes, MAX_WALL_TIME,
};

/// The estimate of one run, as lines for a person: each part likely and at most, the
/// discharge's law, the total wall time "likely ~X, at most Y".
pub fn estimate_lines(e: &CostEstimate, physical: Option<f64>) -> Vec<String> {
    let mut lines = vec![format!(
        "estimate  {} spheres, time step {:e} s, {} thread{}",
        e.particles,
        e.time_step,
        e.threads,
        plural(e.threads)
    )];
    let steps = |t: f64| run::cost::steps_of(e.time_step, t);
    let l = &e.likely;
    if e.simulated.fill > 0.0 {
        lines.push(format!(
            "  {:<10}~{:.3} s simulated, {:.3e} steps, {:.2e} particle-steps, ~{}",
            "fill",
            e.simulated.fill,
            steps(e.simulated.fill),
            e.particle_steps.fill,
            duration_in_words(e.wall_time.fill)
        ));
    }
    let row = |name: &str, likely: f64, bound: f64, ps: (f64, f64), wall: (f64, f64)| {
        format!(
            "  {name:<10}~{likely:.3} s simulated (≤ {bound:.3} s), ~{:.3e} steps, \
             ~{:.2e} particle-steps (≤ {:.2e}), ~{} (≤ {})",
            steps(likely),
            ps.0,
            ps.1,
            duration_in_words(wall.0),
            duration_in_words(wall.1)
        )
    };
    if e.simulated.settle > 0.0 {
        lines.push(row(
            "settle",
            l.simulated.settle,
            e.simulated.settle,
            (l.particle_steps.settle, e.particle_steps.settle),
            (l.wall_time.settle, e.wall_time.settle),
        ));
    }
    lines.push(row(
        "discharge",
        l.simulated.discharge,
        e.simulated.discharge,
        (l.particle_steps.discharge, e.particle_steps.discharge),
        (l.wall_time.discharge, e.wall_time.discharge),
    ));
    lines.push(format!("  {:<10}{}", "", discharge_basis(&l.discharge)));
    lines.push(format!(
        "  {:<10}wall time likely ~{}, at most {} on this machine (~{:.3e} steps, ≤ {:.3e}; \
         ~{:.2e} particle-steps, ≤ {:.2e})",
        "total",
        duration_in_words(l.wall_time.total()),
        duration_in_words(e.wall_time.total()),
        steps(l.simulated.fill) + steps(l.simulated.settle) + steps(l.simulated.discharge),
        e.steps,
        l.particle_steps.total(),
        e.particle_steps.total(),
    ));
    lines.push(match &e.speed {
        Some(speed) if speed.grains != speed.spheres => format!(
            "  {:<10}{:.1} ns per grain-step (its members together), timed on a dense block \
             of {} of the case's grains, {} spheres ({} steps, {:.2} s)",
            "speed",
            speed.ns_per_particle_step,
            speed.grains,
            speed.spheres,
            speed.steps,
            speed.seconds
        ),
        Some(speed) => format!(
            "  {:<10}{:.1} ns per particle-step, timed on a dense block of {} of the case's \
             spheres ({} steps, {:.2} s)",
            "speed", speed.ns_per_particle_step, speed.spheres, speed.steps, speed.seconds
        ),
        None => format!(
            "  {:<10}not timed: a short run (≤ {:.0e} particle-steps at its bounds); wall \
             times at {:.0} ns per particle-step, the slow end of the engine's range",
            "speed",
            run::cost::SHORT_RUN_PARTICLE_STEPS,
            e.ns_per_particle_step
        ),
    });
    lines.push(format!(
        "  {:<10}peak ≈ {}{}",
        "memory",
        bytes_in_words(e.peak_memory),
        physical.map_or(String::new(), |m| format!(
            " of this machine's {}",
            bytes_in_words(m)
        ))
    ));
    lines.push(
        "  (~ likely; ≤ at most: the settling ends when the bed is calm, the discharge when the \
         container is empty, drained or clogged, or at protocol.stop_fraction)"
            .to_string(),
    );
    lines
}

/// How the likely discharge was reckoned, in words.
fn discharge_basis(d: &DischargeModel) -> String {
    match (&d.bounded, d.law) {
        (Some(why), _) => format!("(no likely discharge: {why})"),
        (None, law) => format!(
            "({:.3} kg{} at {:.1} g/s by the {} Beverloo law: {:.3} s of flow{})",
            d.fraction * d.mass,
            if d.fraction < 1.0 {
                format!(" ({:.0} % of the fill)", 100.0 * d.fraction)
            } else {
                String::new()
            },
            1e3 * d.rate,
            if law == Some("beverloo_2d") {
                "slot's (2D)"
            } else {
                "orifice's (3D)"
            },
            d.flowing,
            if d.fraction >= 1.0 {
                ", then protocol.clog_timeout for the stagnant zones"
            } else {
                ""
            }
        ),
    }
}

/// The estimate of a run as JSON: the estimate's fields, the machine's memory and the
/// refusal, if any.
pub fn estimate_json(
    e: &CostEstimate,
    physical: Option<f64>,
    refusal: Option<&str>,
) -> serde_json::Value {
    let mut value = serde_json::to_value(e).unwrap_or_default();
    value["wall_time_total_s"] = e.wall_time.total().into();
    value["likely_wall_time_total_s"] = e.likely.wall_time.total().into();
    value["physical_memory"] = physical.into();
    value["max_wall_time_s"] = MAX_WALL_TIME.into();
    value["refusal"] = refusal.into();
    value
}

/// The summed estimate of a study's cases run `jobs` at a time: each part's particle-steps
/// and wall time summed over the cases, likely and at most, the study's wall time
/// max(sum / jobs, longest case), and its peak memory that of the `jobs` largest cases side by
/// side.
pub struct StudyCost {
    /// Cases estimated [-].
    pub cases: usize,
    /// Cases run at a time [-].
    pub jobs: usize,
    /// Summed particle-steps by part, at most [-].
    pub particle_steps: PhaseTimes,
    /// Summed wall time by part, at most [s].
    pub wall_time: PhaseTimes,
    /// Longest case's wall time, at most [s].
    pub longest: f64,
    /// Predicted wall time of the study, at most [s].
    pub study_wall_time: f64,
    /// Summed likely wall time by part [s].
    pub likely_wall_time: PhaseTimes,
    /// Longest case's likely wall time [s].
    pub likely_longest: f64,
    /// Likely wall time of the study [s]: what its refusal checks.
    pub likely_study_wall_time: f64,
    /// Cases whose likely discharge is its bound (no law applies, or they may clog) [-].
    pub bounded_discharges: usize,
    /// Predicted peak memory [bytes].
    pub peak_memory: f64,
}

/// Each part's sum over `estimates` of what `f` picks.
fn sum_parts(estimates: &[CostEstimate], f: impl Fn(&CostEstimate) -> PhaseTimes) -> PhaseTimes {
    estimates.iter().fold(PhaseTimes::default(), |a, e| {
        let b = f(e);
        PhaseTimes {
            fill: a.fill + b.fill,
            settle: a.settle + b.settle,
            discharge: a.discharge + b.discharge,
        }
    })
}

impl StudyCost {
    /// The study of the cases estimated as `estimates`, run `jobs` at a time.
    pub fn of(estimates: &[CostEstimate], jobs: usize) -> Self {
        let jobs = jobs.max(1);
        let longest =
            |f: &dyn Fn(&CostEstimate) -> f64| estimates.iter().map(f).fold(0.0, f64::max);
        let wall_time = sum_parts(estimates, |e| e.wall_time);
        let likely_wall_time = sum_parts(estimates, |e| e.likely.wall_time);
        let longest_bound = longest(&|e| e.wall_time.total());
        let likely_longest = longest(&|e| e.likely.wall_time.total());
        let mut memories: Vec<f64> = estimates.iter().map(|e| e.peak_memory).collect();
        memories.sort_by(|a, b| b.total_cmp(a));
        Self {
            cases: estimates.len(),
            jobs,
            particle_steps: sum_parts(estimates, |e| e.particle_steps),
            wall_time,
            longest: longest_bound,
            study_wall_time: (wall_time.total() / jobs as f64).max(longest_bound),
            likely_wall_time,
            likely_longest,
            likely_study_wall_time: (likely_wall_time.total() / jobs as f64).max(likely_longest),
            bounded_discharges: estimates
                .iter()
                .filter(|e| e.likely.discharge.bounded.is_some())
                .count(),
            peak_memory: memories.iter().take(jobs).sum(),
        }
    }

    /// The study's estimate as lines for a person.
    pub fn lines(&self, physical: Option<f64>) -> Vec<String> {
        let l = &self.likely_wall_time;
        let w = &self.wall_time;
        let mut lines = vec![
            format!(
                "estimate  {} case{} to run, {} at a time",
                self.cases,
                plural(self.cases),
                self.jobs
            ),
            format!(
                "  {:<10}~{} of wall time summed over the cases, ≤ {} (fill ~{}, settle ~{} \
                 ≤ {}, discharge ~{} ≤ {}); ≤ {:.2e} particle-steps",
                "cases",
                duration_in_words(l.total()),
                duration_in_words(w.total()),
                duration_in_words(l.fill),
                duration_in_words(l.settle),
                duration_in_words(w.settle),
                duration_in_words(l.discharge),
                duration_in_words(w.discharge),
                self.particle_steps.total(),
            ),
            format!(
                "  {:<10}wall time likely ~{}, at most {} on this machine (longest case ~{}, \
                 ≤ {})",
                "study",
                duration_in_words(self.likely_study_wall_time),
                duration_in_words(self.study_wall_time),
                duration_in_words(self.likely_longest),
                duration_in_words(self.longest)
            ),
            format!(
                "  {:<10}peak ≈ {}{}",
                "memory",
                bytes_in_words(self.peak_memory),
                physical.map_or(String::new(), |m| format!(
                    " of this machine's {}",
                    bytes_in_words(m)
                ))
            ),
        ];
        if self.bounded_discharges > 0 {
            lines.push(format!(
                "  ({} case{} counted to protocol.time_limit: no discharge law applies, or the \
                 orifice may clog)",
                self.bounded_discharges,
                plural(self.bounded_discharges)
            ));
        }
        lines.push(
            "  (~ likely: each discharge as its mass over its Beverloo rate; ≤ at most: to \
             protocol.time_limit)"
                .to_string(),
        );
        lines
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}
