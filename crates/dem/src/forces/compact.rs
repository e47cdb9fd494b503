//! Stream compaction of the filters' flags: the indices k whose flag is 1, in order.
//!
//! Both filters (pairs and walls) first write one 0/1 flag per candidate, in a loop the
//! compiler vectorises, and then list the touching candidates. One at a time, that listing
//! stores every index and advances a count by the flag (no branch on the outcome, which
//! would be mispredicted about as often as not): some six instructions per candidate, about
//! a quarter of the pair filter and a fifth of the wall pass (`perf annotate`).
//!
//! With AVX2 the listing takes eight candidates at a time: their flags become an 8-bit mask,
//! a table gives the positions of the mask's ones, packed in the nibbles of one word, and a
//! lane permutation (`vpermd`) moves those eight indices to the front of a vector stored
//! whole at the count; the count advances by the mask's population. The lanes past the
//! count are junk, overwritten by the next store or left beyond the list. The result is the
//! same list as the scalar loop's (integers only; a test checks it), so results do not
//! depend on the build.

/// Lists `flags`' ones in place: `flags[..count]` becomes the indices k with `flags[k] == 1`,
/// in order, and `count` is returned. Each flag must be 0 or 1. In place is sound because
/// the count never passes the index being read: slot `count` ≤ k is written after flag k
/// has been read.
#[inline(always)]
pub(super) fn in_place(flags: &mut [u32]) -> usize {
    let len = flags.len();
    let (mut count, start) = blocks::in_place(flags);
    for k in start..len {
        let t = flags[k];
        flags[count.min(len - 1)] = k as u32;
        count += t as usize;
    }
    count
}

/// Lists in `hits` (count returned) the indices k with `touch[k] == 1`, in order. Each flag
/// must be 0 or 1, and `hits` at least as long as `touch`.
#[inline(always)]
pub(super) fn from_bytes(touch: &[u8], hits: &mut [u32]) -> usize {
    let len = touch.len();
    let hits = &mut hits[..len];
    let (mut count, start) = blocks::from_bytes(touch, hits);
    for (k, &t) in touch.iter().enumerate().skip(start) {
        hits[count.min(len - 1)] = k as u32;
        count += usize::from(t);
    }
    count
}

/// The listing one candidate at a time, for builds without AVX2: nothing is done here, and
/// the callers' scalar loops take every candidate.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2")))]
mod blocks {
    pub(super) fn in_place(_: &mut [u32]) -> (usize, usize) {
        (0, 0)
    }

    pub(super) fn from_bytes(_: &[u8], _: &mut [u32]) -> (usize, usize) {
        (0, 0)
    }
}

#[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
mod blocks {
    use safe_arch::{
        add_i32_m256i, bitand_m256i, cast_to_m256_from_m256i, m256i, move_mask_m256,
        set_splat_i32_m256i, shl_imm_u32_m256i, shr_each_u32_m256i, shuffle_av_i32_all_m256i,
    };

    /// Candidates per block.
    const LANES: usize = 8;

    /// For each 8-bit mask, the positions of its ones in increasing order, one per nibble
    /// from the lowest; the nibbles past the population are zero (junk lanes).
    const POSITIONS: [u32; 256] = positions();

    const fn positions() -> [u32; 256] {
        let mut table = [0u32; 256];
        let mut mask = 0;
        while mask < 256 {
            let (mut bit, mut slot, mut packed) = (0, 0, 0u32);
            while bit < 8 {
                if mask & (1 << bit) != 0 {
                    packed |= (bit as u32) << (4 * slot);
                    slot += 1;
                }
                bit += 1;
            }
            table[mask] = packed;
            mask += 1;
        }
        table
    }

    /// Stores at `out[count..count + 8]` the indices `first + p` for the positions p of
    /// `mask`'s ones, and returns the new count. `out` must have room for eight.
    #[inline(always)]
    fn emit(out: &mut [u32], count: usize, first: u32, mask: u32) -> usize {
        let packed = set_splat_i32_m256i(POSITIONS[mask as usize] as i32);
        let shifts = m256i::from([0, 4, 8, 12, 16, 20, 24, 28]);
        let lanes = bitand_m256i(shr_each_u32_m256i(packed, shifts), set_splat_i32_m256i(7));
        let iota = m256i::from([0, 1, 2, 3, 4, 5, 6, 7]);
        // vpermd: lane s takes the iota lane named by the s-th nibble, i.e. the s-th one.
        let picked = shuffle_av_i32_all_m256i(iota, lanes);
        let indices = add_i32_m256i(picked, set_splat_i32_m256i(first as i32));
        let slot: &mut [u32; LANES] = (&mut out[count..count + LANES])
            .try_into()
            .expect("eight slots");
        *slot = <[u32; LANES]>::from(indices);
        count + mask.count_ones() as usize
    }

    /// The whole blocks of [`super::in_place`]: returns the count and the first index left
    /// to the scalar loop.
    #[inline(always)]
    pub(super) fn in_place(flags: &mut [u32]) -> (usize, usize) {
        let blocks = flags.len() / LANES;
        let mut count = 0;
        for b in 0..blocks {
            let k = b * LANES;
            let block: [u32; LANES] = flags[k..k + LANES].try_into().expect("eight flags");
            // A flag's one moved to the sign bit; the sign bits make the mask.
            let signs = shl_imm_u32_m256i::<31>(m256i::from(block));
            let mask = move_mask_m256(cast_to_m256_from_m256i(signs)) as u32;
            // count ≤ k, so the eight slots written end at or before this block's end.
            count = emit(flags, count, k as u32, mask);
        }
        (count, blocks * LANES)
    }

    /// The whole blocks of [`super::from_bytes`].
    #[inline(always)]
    pub(super) fn from_bytes(touch: &[u8], hits: &mut [u32]) -> (usize, usize) {
        let blocks = touch.len() / LANES;
        let mut count = 0;
        for b in 0..blocks {
            let k = b * LANES;
            let bytes: [u8; LANES] = touch[k..k + LANES].try_into().expect("eight flags");
            // Byte i (0 or 1) lands on bit 56 + i: the multiplier's terms 2^(56 − 7i) put
            // every other byte's bit below 56 or past 63, with no two on one bit, so no carry.
            let mask = (u64::from_le_bytes(bytes).wrapping_mul(0x0102_0408_1020_4080) >> 56) as u32;
            count = emit(hits, count, k as u32, mask);
        }
        (count, blocks * LANES)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The listing one at a time, as the filters did before blocks.
    fn reference(flags: &[u8]) -> Vec<u32> {
        (0..flags.len() as u32)
            .filter(|&k| flags[k as usize] == 1)
            .collect()
    }

    proptest! {
        // Lengths across the block size, densities from empty to full: the lists must be
        // exactly the scalar one (integers, so no tolerance).
        #[test]
        fn both_listings_give_the_indices_of_the_ones_in_order(
            flags in prop::collection::vec(prop::bool::weighted(0.4), 0..100),
        ) {
            let bytes: Vec<u8> = flags.iter().map(|&f| u8::from(f)).collect();
            let expect = reference(&bytes);

            let mut words: Vec<u32> = bytes.iter().map(|&f| u32::from(f)).collect();
            let count = in_place(&mut words);
            prop_assert_eq!(&words[..count], &expect[..]);

            let mut hits = vec![u32::MAX; bytes.len()];
            let count = from_bytes(&bytes, &mut hits);
            prop_assert_eq!(&hits[..count], &expect[..]);
        }
    }

    #[test]
    fn every_eight_bit_pattern_is_listed_exactly() {
        // All 256 masks of one block, behind a block of ones and before a partial block, so
        // that the count, the offset and the junk lanes are all exercised.
        for mask in 0..256u32 {
            let mut bytes = vec![1u8; 8];
            bytes.extend((0..8).map(|b| ((mask >> b) & 1) as u8));
            bytes.extend([1, 0, 1]);
            let expect = reference(&bytes);
            let mut words: Vec<u32> = bytes.iter().map(|&f| u32::from(f)).collect();
            let count = in_place(&mut words);
            assert_eq!(&words[..count], &expect[..], "mask {mask:08b}");
            let mut hits = vec![0; bytes.len()];
            let count = from_bytes(&bytes, &mut hits);
            assert_eq!(&hits[..count], &expect[..], "mask {mask:08b}");
        }
    }
}
