//! A study whose cases all start from one saved bed (`hopperflow study --from-bed DIR`):
//! the same settled packing discharged through every orifice or outlet position of the
//! sweep, without a fill per case.
//!
//! Every case must fit the bed as a single run from it must ([`run::check_bed`]: only
//! the outlet, the discharge rules and [measure] and [output] keys may differ). The seed
//! draws only the fill, so each case takes the bed's, and replicas are refused: they would
//! repeat one run. The cases are therefore not independent samples of the packing; what
//! differs between them is the outlet alone (docs/user-guide.md §5).

use std::path::Path;

use super::StudyError;
use case::SweepPlan;
use files::{StartKind, StartRecord};
use run::{check_bed, read_bed, Bed, Start};

/// Reads the bed in `dir` and makes `plan` start from it ([`plan_from_bed`]): the plan and
/// the start its cases run from.
pub fn plan_from_bed_dir(plan: SweepPlan, dir: &Path) -> Result<(SweepPlan, Start), StudyError> {
    let bed = read_bed(dir).map_err(|e| StudyError::Bed(Box::new(e)))?;
    let plan = plan_from_bed(plan, &bed)?;
    Ok((plan, Start::Bed(Box::new(bed))))
}

/// `plan` with every case set to start from `bed`: each case takes the bed's seed and is
/// checked against the bed, and the plan records the bed as its start (which the manifest and
/// every case folder then carry). Refuses replicas and any case that does not fit.
pub fn plan_from_bed(mut plan: SweepPlan, bed: &Bed) -> Result<SweepPlan, StudyError> {
    if plan.replicas > 1 {
        return Err(StudyError::ReplicasFromOneBed {
            replicas: plan.replicas,
        });
    }
    for case in &mut plan.cases {
        case.case.seed = bed.header().seed;
        check_bed(bed, &case.case).map_err(|source| StudyError::BedDoesNotFit {
            id: case.id.clone(),
            source: Box::new(source),
        })?;
    }
    plan.start = Some(StartRecord {
        kind: StartKind::Bed,
        sha256: bed.sha256().to_string(),
    });
    Ok(plan)
}
