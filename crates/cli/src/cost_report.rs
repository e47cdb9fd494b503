//! The cost estimate printed before `run` and `study` (docs/user-guide.md, "What a run
//! costs"), and the refusal of work that could not finish unless `--no-cost-check`.

use run::cost::{bytes_in_words, duration_in_words, CostEstimate, PhaseTimes, MAX_WALL_TIME};

/// The estimate of one run, as lines for a person.
pub fn estimate_lines(e: &CostEstimate, physical: Option<f64>) -> Vec<String> {
    let mut lines = vec![format!(
        "estimate  {} spheres, time step {:e} s, {} thread{}",
        e.particles,
        e.time_step,
        e.threads,
        plural(e.threads)
    )];
    let row = |name: &str, how: &str, simulated: f64, particle_steps: f64, wall: f64| {
        let steps = run::cost::steps_of(e.time_step, simulated);
        format!(
            "  {name:<10}{how}{simulated:.3} s simulated, {steps:.3e} steps, \
             {particle_steps:.2e} particle-steps, {how}{}",
            duration_in_words(wall)
        )
    };
    if e.simulated.fill > 0.0 {
        lines.push(row(
            "fill",
            "~",
            e.simulated.fill,
            e.particle_steps.fill,
            e.wall_time.fill,
        ));
    }
    if e.simulated.settle > 0.0 {
        lines.push(row(
            "settle",
            "≤ ",
            e.simulated.settle,
            e.particle_steps.settle,
            e.wall_time.settle,
        ));
    }
    lines.push(row(
        "discharge",
        "≤ ",
        e.simulated.discharge,
        e.particle_steps.discharge,
        e.wall_time.discharge,
    ));
    lines.push(format!(
        "  {:<10}≤ {:.3e} steps, ≤ {:.2e} particle-steps, wall time ≤ {} on this machine",
        "total",
        e.steps,
        e.particle_steps.total(),
        duration_in_words(e.wall_time.total()),
    ));
    lines.push(format!(
        "  {:<10}{:.1} ns per particle-step, timed on a dense block of {} of the case's \
         spheres ({} steps, {:.2} s)",
        "speed", e.speed.ns_per_particle_step, e.speed.spheres, e.speed.steps, e.speed.seconds
    ));
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
        "  (upper bounds: the settling ends when the bed is calm, the discharge when the \
         container is empty, drained or clogged, or at protocol.stop_fraction)"
            .to_string(),
    );
    lines
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
    value["physical_memory"] = physical.into();
    value["max_wall_time_s"] = MAX_WALL_TIME.into();
    value["refusal"] = refusal.into();
    value
}

/// The summed estimate of a study's cases run `jobs` at a time: each part's particle-steps
/// and wall time summed over the cases, the study's wall time max(sum / jobs, longest case),
/// and its peak memory that of the `jobs` largest cases side by side.
pub struct StudyCost {
    /// Cases estimated [-].
    pub cases: usize,
    /// Cases run at a time [-].
    pub jobs: usize,
    /// Summed particle-steps by part [-].
    pub particle_steps: PhaseTimes,
    /// Summed wall time by part [s].
    pub wall_time: PhaseTimes,
    /// Longest case's wall time [s].
    pub longest: f64,
    /// Predicted wall time of the study [s].
    pub study_wall_time: f64,
    /// Predicted peak memory [bytes].
    pub peak_memory: f64,
}

impl StudyCost {
    /// The study of the cases estimated as `estimates`, run `jobs` at a time.
    pub fn of(estimates: &[CostEstimate], jobs: usize) -> Self {
        let jobs = jobs.max(1);
        let sum = |f: &dyn Fn(&CostEstimate) -> PhaseTimes| {
            estimates.iter().fold(PhaseTimes::default(), |a, e| {
                let b = f(e);
                PhaseTimes {
                    fill: a.fill + b.fill,
                    settle: a.settle + b.settle,
                    discharge: a.discharge + b.discharge,
                }
            })
        };
        let wall_time = sum(&|e| e.wall_time);
        let longest = estimates
            .iter()
            .map(|e| e.wall_time.total())
            .fold(0.0, f64::max);
        let mut memories: Vec<f64> = estimates.iter().map(|e| e.peak_memory).collect();
        memories.sort_by(|a, b| b.total_cmp(a));
        Self {
            cases: estimates.len(),
            jobs,
            particle_steps: sum(&|e| e.particle_steps),
            wall_time,
            longest,
            study_wall_time: (wall_time.total() / jobs as f64).max(longest),
            peak_memory: memories.iter().take(jobs).sum(),
        }
    }

    /// The study's estimate as lines for a person.
    pub fn lines(&self, physical: Option<f64>) -> Vec<String> {
        vec![
            format!(
                "estimate  {} case{} to run, {} at a time",
                self.cases,
                plural(self.cases),
                self.jobs
            ),
            format!(
                "  {:<10}≤ {:.2e} particle-steps, ≤ {} of wall time summed over the cases \
                 (fill ~{}, settle ≤ {}, discharge ≤ {})",
                "cases",
                self.particle_steps.total(),
                duration_in_words(self.wall_time.total()),
                duration_in_words(self.wall_time.fill),
                duration_in_words(self.wall_time.settle),
                duration_in_words(self.wall_time.discharge),
            ),
            format!(
                "  {:<10}wall time ≤ {} on this machine (longest case ≤ {})",
                "study",
                duration_in_words(self.study_wall_time),
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
            "  (upper bounds: each discharge usually ends well before protocol.time_limit)"
                .to_string(),
        ]
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}
