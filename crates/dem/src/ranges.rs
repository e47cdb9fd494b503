//! How the parallel passes cut the particles into contiguous index ranges: of about equal
//! length (the kick and drift), or of about equal cost (the forces).

/// Bounds (from 0 to `n`, increasing) of `per_thread` ranges for each of `threads` threads,
/// fewer when a range would hold less than `min_len` particles, and at least one range.
/// More ranges than threads let the pool balance ranges of unequal cost.
pub(crate) fn even_bounds(
    n: usize,
    threads: usize,
    per_thread: usize,
    min_len: usize,
) -> Vec<usize> {
    let ranges = (threads * per_thread).min(n / min_len).max(1);
    (0..=ranges).map(|r| r * n / ranges).collect()
}

/// Index of the first pair whose i is at least `body`, in a pair list sorted by i.
pub(crate) fn pair_start(pi: &[u32], body: usize) -> usize {
    pi.partition_point(|&i| (i as usize) < body)
}

/// Bounds (from 0 to `n`, increasing) of `ranges` ranges of bodies of about equal cost: a
/// body costs `body_cost` plus its own candidate pairs (`pi`, the pairs' i, sorted). Each cut
/// is the first body whose cumulative cost reaches its share.
pub(crate) fn cost_bounds(pi: &[u32], n: usize, ranges: usize, body_cost: usize) -> Vec<usize> {
    let cost = |body: usize| pair_start(pi, body) + body_cost * body;
    let total = cost(n);
    let mut bounds = Vec::with_capacity(ranges + 1);
    bounds.push(0);
    for r in 1..ranges {
        let target = r * total / ranges;
        // `cost` increases with the body: a binary search from the previous cut.
        let (mut a, mut b) = (*bounds.last().unwrap_or(&0), n);
        while a < b {
            let mid = a + (b - a) / 2;
            if cost(mid) < target {
                a = mid + 1;
            } else {
                b = mid;
            }
        }
        bounds.push(a);
    }
    bounds.push(n);
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_cover_every_particle_once_in_ranges_of_at_least_the_minimum() {
        // The passes rely on it: contiguous, increasing, from 0 to n, each range no shorter
        // than the minimum unless there is only one.
        for n in [0, 1, 127, 128, 3000, 10_000] {
            for threads in [1, 2, 3, 5] {
                let b = even_bounds(n, threads, 8, 128);
                assert_eq!((b[0], *b.last().unwrap()), (0, n));
                assert!(b.len() >= 2 && b.len() - 1 <= threads * 8);
                assert!(b.windows(2).all(|w| w[0] <= w[1]));
                if b.len() > 2 {
                    assert!(
                        b.windows(2).all(|w| w[1] - w[0] >= 128),
                        "{n} {threads}: {b:?}"
                    );
                }
            }
        }
        assert_eq!(
            even_bounds(3000, 2, 8, 128).len(),
            17,
            "16 ranges for 3000 on 2 threads"
        );
    }

    #[test]
    fn ranges_are_cut_at_about_equal_cost_and_cover_every_body_once() {
        // Bodies 0..1000; body b owns b % 7 pairs (a lumpy list, sorted by i as the real
        // one). Every cut must be increasing from 0 to n, and each range's cost (own pairs
        // plus BODY_COST per body) within one body's largest cost (6 + BODY_COST) of the
        // mean, plus one: the cut is the first body reaching its share, so it overshoots by
        // at most one body. BODY_COST is the force pass's.
        const BODY_COST: usize = 2;
        let n = 1000;
        let pi: Vec<u32> = (0..n as u32)
            .flat_map(|b| vec![b; b as usize % 7])
            .collect();
        let cost = |a: usize, b: usize| {
            pi.iter()
                .filter(|&&i| (a..b).contains(&(i as usize)))
                .count()
                + BODY_COST * (b - a)
        };
        for ranges in [1, 2, 3, 7, 16] {
            let b = cost_bounds(&pi, n, ranges, BODY_COST);
            assert_eq!(b.len(), ranges + 1);
            assert_eq!((b[0], b[ranges]), (0, n));
            assert!(b.windows(2).all(|w| w[0] <= w[1]), "{b:?}");
            let mean = cost(0, n) as f64 / ranges as f64;
            for w in b.windows(2) {
                let c = cost(w[0], w[1]) as f64;
                // One more for the integer division of the targets.
                assert!(
                    (c - mean).abs() <= (7 + BODY_COST) as f64,
                    "{ranges}: {c} vs {mean}"
                );
            }
        }
        // No pairs at all, and fewer bodies than ranges: still an increasing cover (some
        // ranges empty).
        let b = cost_bounds(&[], 3, 4, BODY_COST);
        assert_eq!((b.len(), b[0], b[4]), (5, 0, 3));
        assert!(b.windows(2).all(|w| w[0] <= w[1]), "{b:?}");
    }
}
