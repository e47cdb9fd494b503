//! The guards that stop a run with a typed error instead of going on with a broken state:
//! non-finite motion and overlaps beyond the configured fraction of a radius.

use super::*;

/// The error for the first particle with a non-finite velocity or spin, if any; `time` [s].
pub(super) fn non_finite_velocity(p: &ParticleSet, time: f64) -> Option<DemError> {
    let k = (0..p.len()).find(|&k| !(p.velocity[k].is_finite() && p.omega[k].is_finite()))?;
    Some(DemError::NonFinite {
        tag: p.tag[k],
        position: p.position[k],
        quantity: "velocity",
        time,
    })
}

/// The error for an overlap deeper than the configured limit, if `eval` found one.
pub(super) fn check_overlaps(
    s: &SimulationState,
    eval: &forces::Evaluation,
) -> Result<(), DemError> {
    let limit = s.config.max_overlap_fraction;
    if eval.worst_pair.fraction > limit {
        let w = eval.worst_pair;
        let (i, j) = (s.pairs.i[w.index] as usize, s.pairs.j[w.index] as usize);
        return Err(overlap_error(
            &s.particles,
            i,
            format!("particle {}", s.particles.tag[j]),
            w,
            limit,
            s.time,
        ));
    }
    if eval.worst_wall.fraction > limit {
        let w = eval.worst_wall;
        let i = s.wall_pairs.particle[w.index] as usize;
        return Err(overlap_error(
            &s.particles,
            i,
            format!("wall {}", s.wall_pairs.wall[w.index]),
            w,
            limit,
            s.time,
        ));
    }
    Ok(())
}

pub(super) fn overlap_error(
    p: &ParticleSet,
    i: usize,
    other: String,
    worst: WorstOverlap,
    limit: f64,
    time: f64,
) -> DemError {
    DemError::ExcessiveOverlap {
        tag: p.tag[i],
        other,
        position: p.position[i],
        fraction: worst.fraction,
        limit,
        time,
    }
}

impl Simulation {
    /// Reports what a kick-and-drift pass found: a velocity made non-finite by the previous
    /// step's deferred kick, or a non-finite position.
    pub(super) fn check_drift(&self, drift: Drift) -> Result<(), DemError> {
        let p = &self.state.particles;
        if !drift.kicked_finite {
            // The previous step's deferred kick: reported as `kick` would have.
            if let Some(e) = non_finite_velocity(p, self.state.time) {
                return Err(e);
            }
        }
        if !drift.finite {
            // The fast check flags a non-finite or absurdly distant (|Δx|² overflowing)
            // particle; only a truly non-finite one is an error.
            if let Some(k) = p.position.iter().position(|x| !x.is_finite()) {
                return Err(DemError::NonFinite {
                    tag: p.tag[k],
                    position: p.position[k],
                    quantity: "position",
                    time: self.state.time,
                });
            }
        }
        Ok(())
    }
}
