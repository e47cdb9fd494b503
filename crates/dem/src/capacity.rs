//! How the engine's largest arrays grow.
//!
//! The candidate lists and their histories are rebuilt every few steps at nearly the same
//! length. `Vec`'s own growth doubles the capacity when a rebuild needs a little more, which
//! can leave up to half of those arrays, the bulk of a large run's memory, allocated and
//! unused. These arrays grow instead to what is needed plus an eighth.

/// Makes `v`'s capacity at least `len` elements in all (not `len` more), growing to `len`
/// plus an eighth when it must grow. Changes no element.
#[inline]
pub(crate) fn reserve_total<T>(v: &mut Vec<T>, len: usize) {
    if v.capacity() < len {
        v.reserve_exact(len + len / 8 - v.len());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn growth_is_an_eighth_beyond_the_need_and_none_within_the_capacity() {
        let mut v: Vec<u32> = Vec::with_capacity(100);
        v.extend(0..60);
        reserve_total(&mut v, 100);
        assert_eq!(v.capacity(), 100, "enough room already: no reallocation");
        reserve_total(&mut v, 160);
        // reserve_exact may round up (the allocator's size classes), never below the need,
        // and here not to the doubling (200) that `reserve` would give.
        assert!((180..200).contains(&v.capacity()), "{}", v.capacity());
        assert_eq!(v, (0..60).collect::<Vec<_>>());
    }
}
