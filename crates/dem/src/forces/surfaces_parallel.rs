//! The surface pass (`surfaces`) on several threads, with the one-thread pass's results to
//! the bit.
//!
//! The bodies are cut into contiguous ranges. A range's task resolves the candidates of its
//! own particles on every curved, meshed or spinning wall: it alone writes those particles'
//! forces and torques, and the remembered contacts of those candidates (in the wall-major
//! list, a wall's particles are in increasing order, so a range's candidates of one wall are
//! one stretch). What the ranges share is summed so that the order does not matter, or
//! replayed in the one-thread order:
//! - a wall's total load is a fixed-point integer sum (`loads`), exact in any order;
//! - the element loads (per triangle or band) are floating-point sums, so each task only
//!   records its bookings, and they are added afterwards, wall by wall and range by range:
//!   the order of the one-thread pass;
//! - the worst overlap keeps the largest, the lowest list index on a tie.
//!
//! Under the default laws the pair pass (`parallel`) runs each range's surface contacts at
//! the end of its own task ([`wall_stretches`], [`range_pass`], [`merge_ranges`]), saving a
//! fork and join per step; under other laws the planar walls are resolved after all pairs,
//! and this pass follows them on its own ([`surface_pass_parallel`]).

use glam::DVec3;

use super::loads::{merge_loads, LoadSum, SurfaceLoads};
use super::surfaces::{resolve_stretch, Stretch, StretchSinks, SurfaceScratch, SurfaceSinks};
use super::{walls, KernelInput, WorstOverlap};
use crate::history::SurfaceSlot;

/// Ranges per thread, so that the pool can balance ranges of unequal cost: the candidates
/// gather along the walls, and the bodies are in cell order.
const RANGES_PER_THREAD: usize = 4;

/// One contact's element booking, kept for the replay: wall, element, normal, force.
#[derive(Debug, Clone, Copy)]
struct Booking {
    wall: u32,
    element: u32,
    normal: DVec3,
    force: DVec3,
}

/// A range's stretch of one wall's candidates: (wall, first list index, the stretch's
/// remembered contacts).
pub(super) type WallStretch<'a> = (usize, usize, &'a mut [SurfaceSlot]);

/// A range's share of the pass: its bodies' forces and torques, and its stretch of each
/// wall's candidates with their remembered contacts.
pub(super) struct RangeTask<'a> {
    pub(super) bodies: std::ops::Range<usize>,
    pub(super) force: &'a mut [DVec3],
    pub(super) torque: &'a mut [DVec3],
    pub(super) stretches: Vec<WallStretch<'a>>,
}

/// What a range's task returns.
pub(super) struct RangeResult {
    worst: WorstOverlap,
    count: usize,
    loads: Vec<(usize, LoadSum)>,
    bookings: Vec<Booking>,
}

/// [`super::surfaces::surface_pass`] over all bodies on `pool`.
pub(crate) fn surface_pass_parallel(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    slots: &mut [SurfaceSlot],
    scratches: &mut Vec<SurfaceScratch>,
    sinks: &mut SurfaceSinks,
    pool: &crate::team::Team,
) -> (WorstOverlap, usize) {
    let n = input.particles.len();
    let ranges = (pool.threads() * RANGES_PER_THREAD).clamp(1, n.max(1));
    let bounds: Vec<usize> = (0..=ranges).map(|r| r * n / ranges).collect();
    scratches.resize_with(ranges, SurfaceScratch::default);
    let bands = element_counts(input, sinks.elements);
    let quanta = sinks.quanta;

    // Cut the bodies' forces and torques into the ranges.
    let mut tasks: Vec<RangeTask> = Vec::with_capacity(ranges);
    {
        let (mut force, mut torque) = (&mut sinks.force[..], &mut sinks.torque[..]);
        let stretches = wall_stretches(input, (pi, pw), slots, &bounds);
        for (r, stretches) in stretches.into_iter().enumerate() {
            let len = bounds[r + 1] - bounds[r];
            let (f, rest_f) = std::mem::take(&mut force).split_at_mut(len);
            let (t, rest_t) = std::mem::take(&mut torque).split_at_mut(len);
            force = rest_f;
            torque = rest_t;
            tasks.push(RangeTask {
                bodies: bounds[r]..bounds[r + 1],
                force: f,
                torque: t,
                stretches,
            });
        }
    }

    let results: Vec<RangeResult> = crate::timing::parallel_region(|| {
        pool.map(
            tasks.into_iter().zip(scratches.iter_mut()).collect(),
            |(task, scratch)| range_pass(input, pi, &bands, quanta, task, scratch),
        )
    });
    merge_ranges(&results, sinks, input.dt)
}

/// Cuts each resolved wall's run of candidates in the wall-major list (`pi`, `pw`), with
/// their remembered contacts `slots`, at the body bounds `bounds` (ascending, from 0 to the
/// body count): the stretches of each range, in wall order. A wall's particles are in
/// increasing order, so a range's candidates of one wall are one stretch.
pub(super) fn wall_stretches<'a>(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    slots: &'a mut [SurfaceSlot],
    bounds: &[usize],
) -> Vec<Vec<WallStretch<'a>>> {
    let mut out: Vec<Vec<WallStretch<'a>>> = (1..bounds.len()).map(|_| Vec::new()).collect();
    let mut rest = slots;
    let mut taken = 0;
    for (w, run) in walls::wall_runs(pw) {
        let resolved = input.walls[w as usize]
            .as_ref()
            .is_some_and(|wall| wall.resolved_one_by_one());
        let (_, after) = std::mem::take(&mut rest).split_at_mut(run.start - taken);
        rest = after;
        taken = run.start;
        if !resolved {
            continue;
        }
        let ids = &pi[run.clone()];
        for (stretches, &hi) in out.iter_mut().zip(&bounds[1..]) {
            let end = run.start + ids.partition_point(|&i| (i as usize) < hi);
            let (stretch, after) = std::mem::take(&mut rest).split_at_mut(end - taken);
            stretches.push((w as usize, taken, stretch));
            rest = after;
            taken = end;
        }
    }
    out
}

/// Elements (triangles or bands) of each wall's load record in `elements`, at least 1.
pub(super) fn element_counts(input: &KernelInput, elements: &[SurfaceLoads]) -> Vec<usize> {
    (0..input.walls.len())
        .map(|w| elements.get(w).map_or(1, |e| e.elements.len().max(1)))
        .collect()
}

/// Sums the ranges' results in a fixed order: loads exactly (integers), element bookings
/// replayed wall by wall, range by range, each range's in list order: the one-thread pass's
/// order. Returns the worst overlap and the number of contacts.
pub(super) fn merge_ranges(
    results: &[RangeResult],
    sinks: &mut SurfaceSinks,
    dt: f64,
) -> (WorstOverlap, usize) {
    let mut worst = WorstOverlap::default();
    let mut count = 0;
    for result in results {
        worst = worst.merge(result.worst);
        count += result.count;
        for (w, sum) in &result.loads {
            merge_loads(&mut sinks.loads[*w..=*w], std::slice::from_ref(sum));
        }
    }
    replay(results, sinks.elements, dt);
    (worst, count)
}

/// Adds the recorded bookings to the element loads in the one-thread pass's order.
fn replay(results: &[RangeResult], elements: &mut [SurfaceLoads], dt: f64) {
    if elements.is_empty() {
        return;
    }
    // Each range's bookings are wall-major (its stretches come in wall order): walk the
    // walls in order and take each range's bookings of that wall in turn.
    let mut cursors = vec![0usize; results.len()];
    let walls = results
        .iter()
        .flat_map(|r| r.bookings.iter().map(|b| b.wall))
        .max()
        .map_or(0, |w| w as usize + 1);
    for w in 0..walls {
        for (result, cursor) in results.iter().zip(cursors.iter_mut()) {
            while let Some(b) = result
                .bookings
                .get(*cursor)
                .filter(|b| b.wall as usize == w)
            {
                if let Some(loads) = elements.get_mut(w) {
                    loads.book(b.element as usize, b.normal, b.force, dt);
                }
                *cursor += 1;
            }
        }
    }
}

pub(super) fn range_pass(
    input: &KernelInput,
    pi: &[u32],
    bands: &[usize],
    quanta: &super::loads::LoadQuanta,
    task: RangeTask,
    scratch: &mut SurfaceScratch,
) -> RangeResult {
    let mut result = RangeResult {
        worst: WorstOverlap::default(),
        count: 0,
        loads: Vec::new(),
        bookings: Vec::new(),
    };
    let RangeTask {
        bodies,
        force,
        torque,
        stretches,
    } = task;
    for (w, first, stretch) in stretches {
        if stretch.is_empty() {
            continue;
        }
        let wall = input.walls[w]
            .as_ref()
            .expect("a resolved wall's candidates come from a present wall");
        let mut sum = LoadSum::default();
        let len = stretch.len();
        let bookings = &mut result.bookings;
        result.count += resolve_stretch(
            input,
            Stretch {
                wall,
                index: w,
                bands: bands[w],
                ids: &pi[first..first + len],
                first,
                slots: stretch,
            },
            &mut StretchSinks {
                force: &mut *force,
                torque: &mut *torque,
                offset: bodies.start,
                sum: &mut sum,
                quanta,
            },
            scratch,
            &mut result.worst,
            &mut |element, normal, force| {
                bookings.push(Booking {
                    wall: w as u32,
                    element,
                    normal,
                    force,
                })
            },
        );
        result.loads.push((w, sum));
    }
    result
}
