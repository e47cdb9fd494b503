//! How the parallel passes cut the particles: contiguous index ranges of about equal length.

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
}
