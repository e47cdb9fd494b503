//! The threads of one simulation's parallel passes: a rayon pool whose workers are kept
//! awake between the passes of a run.
//!
//! A step of a few thousand to a few tens of thousands of bodies takes 0.1–1 ms and has two
//! or three parallel passes (kick and drift, the pair pass, and under some laws a surface
//! pass). A rayon worker that finds no work yields a few dozen times and then sleeps; the
//! next pass must wake it (a futex wake and a reschedule, tens of µs on a virtual machine),
//! a large part of a pass that short (docs/performance.md, *Threads*). So after each
//! pass the team hands every worker a job that only spins, for up to [`SPIN`] or until the
//! next pass begins, as OpenMP runtimes keep their threads spinning between parallel
//! regions: the next pass then finds its workers awake and they take its tasks at once.
//! Only a pause longer than that (a run protocol's outputs, the end of a run) lets them
//! sleep.
//!
//! A pass deals its tasks to the threads in a fixed way, so that each thread keeps the same
//! bodies from pass to pass ([`Team::map`]).
//!
//! The spinning jobs hold no data of the passes: each ends when the team's pass counter
//! moves on, which [`Team::map`] does before it hands out its tasks, so a thread that
//! picks one up after that returns at once. Which thread runs a task never changes a
//! result: the engine's sums do not depend on it.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// How long an idle worker spins for the next pass before it may sleep: longer than the
/// serial stretches between the passes of a run of steps (a neighbour-list build of 10^5
/// bodies takes about a millisecond), shorter than anything a user would see as a busy idle
/// process.
const SPIN: Duration = Duration::from_millis(2);

/// The threads of one simulation's parallel passes (see the module's documentation).
#[derive(Debug)]
pub struct Team {
    pool: rayon::ThreadPool,
    /// Counts the passes begun: a spinning job stops when it moves past the count it was
    /// handed out at.
    passes: Arc<AtomicU64>,
}

impl Team {
    /// A team of `threads` threads (at least 1).
    pub fn new(threads: usize) -> Result<Self, rayon::ThreadPoolBuildError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.max(1))
            .thread_name(|i| format!("hopperflow-{i}"))
            .build()?;
        Ok(Self {
            pool,
            passes: Arc::new(AtomicU64::new(0)),
        })
    }

    /// Threads of the team.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// Runs `f` on one of the team's threads, and from there every pass it starts: a caller
    /// that alternates short runs of steps with work of its own runs its whole loop inside,
    /// so that each pass starts from a team thread rather than handing its work over to the
    /// team and sleeping until it comes back.
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        self.pool.install(f)
    }

    /// `f` of every task, in the tasks' order. The tasks are dealt to the team's threads in
    /// contiguous shares of (about) equal counts, the first share to the first thread, the
    /// same way at every pass: a pass over body ranges then gives each thread the same
    /// bodies as the pass before, whose numbers may still be in its core's cache. Dealt so,
    /// instead of to whichever thread is free, the paper's hopper went from 0.74× to 1.18×
    /// on two threads against one (docs/performance.md, *Threads*). Then the workers are
    /// kept spinning for the next pass.
    pub fn map<T: Send, R: Send>(&self, tasks: Vec<T>, f: impl Fn(T) -> R + Sync + Send) -> Vec<R> {
        let pass = self.passes.fetch_add(1, Ordering::AcqRel) + 1;
        let n = tasks.len();
        let slots: Vec<Mutex<Option<T>>> = tasks.into_iter().map(|t| Mutex::new(Some(t))).collect();
        let shares = self.pool.broadcast(|ctx| {
            let (t, threads) = (ctx.index(), ctx.num_threads());
            (t * n / threads..(t + 1) * n / threads)
                .map(|k| {
                    let task = slots[k]
                        .lock()
                        .unwrap_or_else(PoisonError::into_inner)
                        .take();
                    f(task.expect("each task is dealt to one thread"))
                })
                .collect::<Vec<R>>()
        });
        self.keep_awake(pass);
        shares.into_iter().flatten().collect()
    }

    /// Hands each worker (all threads but one, which is the caller's or will be the next
    /// pass's) a job that spins until pass `pass` is over or [`SPIN`] has passed.
    fn keep_awake(&self, pass: u64) {
        for _ in 1..self.threads() {
            let passes = Arc::clone(&self.passes);
            self.pool.spawn(move || spin_until_next_pass(&passes, pass));
        }
    }
}

/// Spins while the pass count is `pass`, for at most [`SPIN`], yielding the core now and
/// then to any other thread that wants it.
fn spin_until_next_pass(passes: &AtomicU64, pass: u64) {
    spin_while(|| passes.load(Ordering::Acquire) == pass, Some(SPIN));
}

/// Spins while `waiting()` holds, for at most `limit` when one is given, yielding the core
/// every 256 turns to any other thread that wants it: how the team's threads wait for each
/// other inside a run of passes, where sleeping would cost a wake-up.
pub(crate) fn spin_while(waiting: impl Fn() -> bool, limit: Option<Duration>) {
    let start = Instant::now();
    let mut spins = 0u32;
    while waiting() {
        spins = spins.wrapping_add(1);
        if spins.is_multiple_of(256) {
            if limit.is_some_and(|limit| start.elapsed() > limit) {
                return;
            }
            std::thread::yield_now();
        } else {
            std::hint::spin_loop();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_gives_each_task_its_result_in_order() {
        // Back to back, and after a pause longer than the spin (the workers sleep then and
        // must be woken): every task once, its result in its place.
        let team = Team::new(3).expect("a team");
        for n in [0, 1, 2, 3, 7, 100] {
            let got = team.map((0..n).collect(), |k: u64| k * k);
            assert_eq!(got, (0..n).map(|k| k * k).collect::<Vec<_>>());
        }
        std::thread::sleep(SPIN * 3);
        assert_eq!(team.map(vec![1, 2, 3], |x: i32| x + 1), vec![2, 3, 4]);
    }

    #[test]
    fn the_tasks_of_a_pass_run_on_several_threads() {
        // Two tasks that each wait until both have started cannot finish on one thread: the
        // pass must hand them to two threads at once, spinning jobs or not.
        let team = Team::new(2).expect("a team");
        for _ in 0..200 {
            let started = AtomicU64::new(0);
            let ids = Mutex::new(Vec::new());
            team.map(vec![0, 1], |_: i32| {
                started.fetch_add(1, Ordering::AcqRel);
                let t0 = Instant::now();
                while started.load(Ordering::Acquire) < 2 {
                    assert!(
                        t0.elapsed() < Duration::from_secs(10),
                        "the other task never ran"
                    );
                    std::hint::spin_loop();
                }
                ids.lock().unwrap().push(std::thread::current().id());
            });
            let ids = ids.into_inner().unwrap();
            assert_ne!(ids[0], ids[1]);
        }
    }

    #[test]
    fn a_spinning_job_ends_when_the_next_pass_begins() {
        let passes = Arc::new(AtomicU64::new(7));
        let spinner = {
            let passes = Arc::clone(&passes);
            std::thread::spawn(move || {
                let t0 = Instant::now();
                spin_until_next_pass(&passes, 7);
                t0.elapsed()
            })
        };
        std::thread::sleep(Duration::from_micros(200));
        passes.fetch_add(1, Ordering::AcqRel);
        let spun = spinner.join().expect("the spinner returns");
        // It spun until the count moved (200 µs or more) and, bounded by SPIN, not forever.
        assert!(spun <= SPIN + Duration::from_millis(50), "{spun:?}");
        // A job handed out for a pass already over returns at once.
        let t0 = Instant::now();
        spin_until_next_pass(&passes, 7);
        assert!(t0.elapsed() < Duration::from_millis(1));
    }
}
