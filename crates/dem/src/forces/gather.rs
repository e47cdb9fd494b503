//! The pair gather: the touching pairs' motion copied into a [`Batch`], four contacts at a
//! time by vector rows where the build has AVX, one at a time otherwise. The same rows
//! serve the pair filter's distances for equal spheres ([`pair_flags`]) and the gather of
//! equal spheres' contacts with a plane ([`plane_motion`]: the slab's faces and the side
//! walls, a third of the wall loop's time when gathered one number at a time; the rows
//! save about 1.4 % of a step on the paper's hopper on AMD processors, within the noise on
//! some Intel ones).
//!
//! The scalar gather (`Batch::set_pair_motion`) stores 16 numbers per contact one at a
//! time, and stores are what the gather is short of (docs/performance.md, "What limits it
//! now"). With AVX each body's position, velocity and spin is loaded whole, as one 4-lane
//! vector (x, y, z, and the next body's x, never used); the differences are taken on these
//! rows, and four contacts' rows are transposed into the batch's columns in registers, so
//! that each column of four is one vector store: 16 stores per contact become 4.
//!
//! Every number is computed by the same operations as in the scalar gather (a lane of a
//! vector subtraction or multiplication rounds as the scalar one), so the batch holds the
//! same bits either way; a test checks it. The intrinsics come through `safe_arch`, whose
//! functions are safe to call where the build enables the feature (the workspace builds for
//! the host, `.cargo/config.toml`): this crate keeps no `unsafe` code.

use glam::DVec3;

use super::filter::live_history;
use super::kernel::{Batch, BATCH};
use super::walls::WallSource;
use crate::history::WAS_LIVE;

/// What the pair gather reads: the bodies, and the candidates with their histories.
pub(super) struct PairState<'a> {
    /// Positions [m].
    pub position: &'a [DVec3],
    /// Velocities [m/s].
    pub velocity: &'a [DVec3],
    /// Angular velocities [rad/s].
    pub omega: &'a [DVec3],
    /// Bodies i and j of each candidate [-].
    pub pi: &'a [u32],
    /// See `pi`.
    pub pj: &'a [u32],
    /// Tangential history ξ of each candidate [m].
    pub history: &'a [DVec3],
    /// Live flags of each candidate (`crate::history`) [-].
    pub live: &'a [u8],
}

impl PairState<'_> {
    /// Bodies i, j, the candidate, and whether its ξ was live before the filter.
    #[inline(always)]
    fn contact(&self, k: u32) -> (usize, usize, usize, bool) {
        let k = k as usize;
        let was_live = self.live[k] & WAS_LIVE != 0;
        (self.pi[k] as usize, self.pj[k] as usize, k, was_live)
    }
}

/// Fills slots `0..group.len()` of `batch` with the motion of the touching candidates
/// `group` (at most [`BATCH`]): what `Batch::set_pair_motion` fills, with the laws' ξ
/// (zero for a contact that was not live, §3.1).
#[inline(always)]
pub(super) fn pair_motion(batch: &mut Batch, group: &[u32], state: &PairState) {
    let group = &group[..group.len().min(BATCH)];
    let done = fours(batch, group, state);
    for (m, &k) in group.iter().enumerate().skip(done) {
        // `m < BATCH` already; the mask tells the compiler so.
        one(batch, m & (BATCH - 1), k, state);
    }
}

/// The scalar gather of candidate `k` into slot `m`.
#[inline(always)]
fn one(batch: &mut Batch, m: usize, k: u32, s: &PairState) {
    let (i, j, k, _) = s.contact(k);
    batch.set_pair_motion(
        m,
        (s.position[i] - s.position[j], s.velocity[i] - s.velocity[j]),
        (s.omega[i], s.omega[j]),
        live_history(s.live[k], s.history[k]),
    );
}

/// Without AVX no contact is gathered by fours.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
fn fours(_: &mut Batch, _: &[u32], _: &PairState) -> usize {
    0
}

/// Gathers the whole fours of `group` by vector rows; returns how many contacts that is.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
fn fours(batch: &mut Batch, group: &[u32], state: &PairState) -> usize {
    // One length for the three body arrays, so that one bounds test covers all of a
    // contact's rows (`rows::contact_rows`).
    let n = state.position.len();
    let bodies = rows::Bodies {
        position: bytemuck::cast_slice(state.position),
        velocity: bytemuck::cast_slice(&state.velocity[..n]),
        omega: bytemuck::cast_slice(&state.omega[..n]),
        history: bytemuck::cast_slice(state.history),
    };
    for (q, four) in group.chunks_exact(4).enumerate() {
        // Written out, not mapped: `array::map` was not inlined here (3 % of a step).
        let four = [
            state.contact(four[0]),
            state.contact(four[1]),
            state.contact(four[2]),
            state.contact(four[3]),
        ];
        rows::gather_four(batch, 4 * q, &bodies, four);
    }
    group.len() / 4 * 4
}

/// Fills slots `0..4q` of `batch` with the whole fours of `group` (touching candidates of
/// the wall run `source`, a plane with unit normal n and offset [m] `plane`, indices into
/// its `pi`; equal spheres of radius `radius` [m]): the overlap R − (x·n − offset), Δv =
/// v − v_wall, ω_i and ξ (zero where it was not live), with the bits of the scalar gather
/// (`WallSource::gather`, whose `plane_distance` is glam's dot product,
/// ((x n_x + y n_y) + z n_z) − offset). Returns how many contacts that is.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
pub(super) fn plane_motion(
    batch: &mut Batch,
    group: &[u32],
    source: &WallSource,
    plane: (DVec3, f64),
    radius: f64,
) -> usize {
    let group = &group[..group.len().min(BATCH)];
    let p = source.input.particles;
    let n = p.len();
    let bodies = rows::Bodies {
        position: bytemuck::cast_slice(&p.position[..n]),
        velocity: bytemuck::cast_slice(&p.velocity[..n]),
        omega: bytemuck::cast_slice(&p.omega[..n]),
        history: bytemuck::cast_slice(source.history),
    };
    let plane = rows::Plane::new(source.velocity, plane, radius);
    for (q, four) in group.chunks_exact(4).enumerate() {
        let contact = |k: u32| {
            let k = k as usize;
            (source.pi[k] as usize, k, source.live[k] & WAS_LIVE != 0)
        };
        let four = [
            contact(four[0]),
            contact(four[1]),
            contact(four[2]),
            contact(four[3]),
        ];
        rows::plane_four(batch, 4 * q, &bodies, &plane, four);
    }
    group.len() / 4 * 4
}

/// Without AVX no wall contact is gathered by fours.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
pub(super) fn plane_motion(
    _: &mut Batch,
    _: &[u32],
    _: &WallSource,
    _: (DVec3, f64),
    _: f64,
) -> usize {
    0
}

/// Pass 1 of the pair filter for equal spheres, four candidates at a time by vector rows
/// where the build has AVX: `flags[k]` = 1 when candidate k's squared centre distance is not
/// at least `cut2` [m²] (a NaN distance counts as touching), else 0, for the whole fours of
/// `flags`; returns how many candidates that is. The same bits as the scalar pass
/// (`forces::pair_flags`): |d|² is glam's `length_squared`, (x x + y y) + z z.
///
/// Two row loads, a subtraction and a quarter of a transpose per candidate, against the
/// scalar pass's six loads and its shuffles: about 0.9 % of a step on AMD processors,
/// within the noise on some Intel ones.
#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
#[inline(always)]
pub(super) fn pair_flags(
    position: &[DVec3],
    ids: (&[u32], &[u32]),
    flags: &mut [u32],
    cut2: f64,
) -> usize {
    rows::flags_fours(bytemuck::cast_slice(position), ids, flags, cut2)
}

/// Without AVX no candidate is filtered by fours.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
#[inline(always)]
pub(super) fn pair_flags(_: &[DVec3], _: (&[u32], &[u32]), _: &mut [u32], _: f64) -> usize {
    0
}

#[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
mod rows {
    use crate::forces::kernel::Batch;
    use glam::DVec3;
    use safe_arch::{
        add_m256d, bitand_m256d, cast_to_m256d_from_m256i, cmp_op, cmp_op_mask_m256d,
        load_unaligned_m256d, m256d, move_mask_m256d, mul_m256d, permute2z_m256d,
        set_reversed_m256d, set_splat_i64_m256i, set_splat_m256d, store_unaligned_m256d, sub_m256d,
        unpack_hi_m256d, unpack_lo_m256d,
    };

    /// Lanes of a body row: x, y, z and one that is not used.
    const LANES: usize = 4;

    /// The bodies' state as flat arrays of 3-vectors, and the candidates' histories.
    pub(super) struct Bodies<'a> {
        /// Positions [m].
        pub position: &'a [f64],
        /// Velocities [m/s].
        pub velocity: &'a [f64],
        /// Angular velocities [rad/s].
        pub omega: &'a [f64],
        /// Tangential histories ξ of the candidates [m].
        pub history: &'a [f64],
    }

    /// Row `i` of a flat array of 3-vectors, as a 4-lane vector whose last lane is junk
    /// (the next vector's x, or zero after the last vector).
    #[inline(always)]
    fn row(flat: &[f64], i: usize) -> m256d {
        match flat.get(3 * i..3 * i + LANES) {
            Some(s) => load_unaligned_m256d(s.try_into().expect("four lanes")),
            None => {
                let s = &flat[3 * i..3 * i + 3];
                set_reversed_m256d(s[0], s[1], s[2], 0.0)
            }
        }
    }

    /// Columns x, y and z of four rows (a 4 × 4 transpose without its last column).
    #[inline(always)]
    fn columns(r: [m256d; 4]) -> [m256d; 3] {
        // [r0.x r1.x r0.z r1.z], [r0.y r1.y r0.w r1.w], and the same for r2, r3.
        let t0 = unpack_lo_m256d(r[0], r[1]);
        let t1 = unpack_hi_m256d(r[0], r[1]);
        let t2 = unpack_lo_m256d(r[2], r[3]);
        let t3 = unpack_hi_m256d(r[2], r[3]);
        [
            permute2z_m256d::<0x20>(t0, t2),
            permute2z_m256d::<0x20>(t1, t3),
            permute2z_m256d::<0x31>(t0, t2),
        ]
    }

    /// Stores four numbers at slots `m..m + 4` of a batch row.
    #[inline(always)]
    fn put(row: &mut [f64], m: usize, v: m256d) {
        let dst: &mut [f64; 4] = (&mut row[m..m + LANES]).try_into().expect("four slots");
        store_unaligned_m256d(dst, v);
    }

    /// One contact's rows: d = x_i − x_j, v_i − v_j, ω_i, ω_j and ξ, or +0.0 where ξ was
    /// not live (the bits `live_history`'s select gives).
    #[inline(always)]
    fn contact_rows(
        bodies: &Bodies,
        (i, j, k, was_live): (usize, usize, usize, bool),
    ) -> [m256d; 5] {
        let keep = cast_to_m256d_from_m256i(set_splat_i64_m256i(-i64::from(was_live)));
        let (n, h) = (bodies.position.len(), bodies.history.len());
        // One test for all seven rows (`&`, not `&&`: one branch), after which the loads
        // need no bounds checks of their own, since `fours` cuts the body arrays to one
        // length. It fails only for the last body or candidate, whose row ends its array.
        // Seven checked rows would cost about 2 % of a step.
        if (3 * i + LANES <= n) & (3 * j + LANES <= n) & (3 * k + LANES <= h) {
            let whole = |flat: &[f64], i: usize| {
                load_unaligned_m256d(flat[3 * i..3 * i + LANES].try_into().expect("four lanes"))
            };
            [
                sub_m256d(whole(bodies.position, i), whole(bodies.position, j)),
                sub_m256d(whole(bodies.velocity, i), whole(bodies.velocity, j)),
                whole(bodies.omega, i),
                whole(bodies.omega, j),
                bitand_m256d(whole(bodies.history, k), keep),
            ]
        } else {
            [
                sub_m256d(row(bodies.position, i), row(bodies.position, j)),
                sub_m256d(row(bodies.velocity, i), row(bodies.velocity, j)),
                row(bodies.omega, i),
                row(bodies.omega, j),
                bitand_m256d(row(bodies.history, k), keep),
            ]
        }
    }

    /// A plane's numbers as vectors: the wall's velocity as a row, the rest splat.
    pub(super) struct Plane {
        velocity: m256d,
        normal: [m256d; 3],
        offset: m256d,
        radius: m256d,
    }

    impl Plane {
        /// From the wall's velocity [m/s], its unit normal and offset [m], and the spheres'
        /// radius [m].
        pub(super) fn new(v: DVec3, (n, offset): (DVec3, f64), radius: f64) -> Self {
            Self {
                velocity: set_reversed_m256d(v.x, v.y, v.z, 0.0),
                normal: [n.x, n.y, n.z].map(set_splat_m256d),
                offset: set_splat_m256d(offset),
                radius: set_splat_m256d(radius),
            }
        }
    }

    /// One wall contact's rows: x_i, v_i − v_wall, ω_i and ξ, or +0.0 where ξ was not live.
    #[inline(always)]
    fn plane_rows(
        bodies: &Bodies,
        wall_velocity: m256d,
        (i, k, was_live): (usize, usize, bool),
    ) -> [m256d; 4] {
        let keep = cast_to_m256d_from_m256i(set_splat_i64_m256i(-i64::from(was_live)));
        let (n, h) = (bodies.position.len(), bodies.history.len());
        // One test for the four rows, as in `contact_rows`.
        if (3 * i + LANES <= n) & (3 * k + LANES <= h) {
            let whole = |flat: &[f64], i: usize| {
                load_unaligned_m256d(flat[3 * i..3 * i + LANES].try_into().expect("four lanes"))
            };
            [
                whole(bodies.position, i),
                sub_m256d(whole(bodies.velocity, i), wall_velocity),
                whole(bodies.omega, i),
                bitand_m256d(whole(bodies.history, k), keep),
            ]
        } else {
            [
                row(bodies.position, i),
                sub_m256d(row(bodies.velocity, i), wall_velocity),
                row(bodies.omega, i),
                bitand_m256d(row(bodies.history, k), keep),
            ]
        }
    }

    /// Gathers four touching candidates of a plane into batch slots `m..m + 4`: for each,
    /// body i, candidate k and whether its ξ was live.
    #[inline(always)]
    pub(super) fn plane_four(
        batch: &mut Batch,
        m: usize,
        bodies: &Bodies,
        plane: &Plane,
        four: [(usize, usize, bool); 4],
    ) {
        let [x0, v0, w0, h0] = plane_rows(bodies, plane.velocity, four[0]);
        let [x1, v1, w1, h1] = plane_rows(bodies, plane.velocity, four[1]);
        let [x2, v2, w2, h2] = plane_rows(bodies, plane.velocity, four[2]);
        let [x3, v3, w3, h3] = plane_rows(bodies, plane.velocity, four[3]);
        let [x, y, z] = columns([x0, x1, x2, x3]);
        let [nx, ny, nz] = plane.normal;
        let dot = add_m256d(
            add_m256d(mul_m256d(x, nx), mul_m256d(y, ny)),
            mul_m256d(z, nz),
        );
        put(
            &mut batch.overlap,
            m,
            sub_m256d(plane.radius, sub_m256d(dot, plane.offset)),
        );
        for (a, c) in columns([v0, v1, v2, v3]).into_iter().enumerate() {
            put(&mut batch.dv[a], m, c);
        }
        for (a, c) in columns([w0, w1, w2, w3]).into_iter().enumerate() {
            put(&mut batch.omega[0][a], m, c);
        }
        for (a, c) in columns([h0, h1, h2, h3]).into_iter().enumerate() {
            put(&mut batch.xi[a], m, c);
        }
    }

    /// The flags of a 4-bit compare mask b: lane l is `b >> l & 1`.
    const FLAGS: [[u32; 4]; 16] = {
        let mut t = [[0; 4]; 16];
        let mut b = 0;
        while b < 16 {
            let mut l = 0;
            while l < 4 {
                t[b][l] = (b as u32 >> l) & 1;
                l += 1;
            }
            b += 1;
        }
        t
    };

    /// The offset row x_i − x_j of one candidate, with a junk last lane.
    #[inline(always)]
    fn offset_row(flat: &[f64], i: usize, j: usize) -> m256d {
        let n = flat.len();
        // One test for both rows, after which the loads need no bounds checks of their own.
        if (3 * i + LANES <= n) & (3 * j + LANES <= n) {
            let whole = |i: usize| {
                load_unaligned_m256d(flat[3 * i..3 * i + LANES].try_into().expect("four lanes"))
            };
            sub_m256d(whole(i), whole(j))
        } else {
            sub_m256d(row(flat, i), row(flat, j))
        }
    }

    /// [`super::pair_flags`] over the flat positions.
    #[inline(always)]
    pub(super) fn flags_fours(
        position: &[f64],
        (pi, pj): (&[u32], &[u32]),
        flags: &mut [u32],
        cut2: f64,
    ) -> usize {
        let cut = set_splat_m256d(cut2);
        let len = flags.len().min(pi.len()).min(pj.len());
        let groups = flags[..len]
            .chunks_exact_mut(4)
            .zip(pi.chunks_exact(4).zip(pj.chunks_exact(4)));
        for (f, (i, j)) in groups {
            // Written out, not mapped, as in `gather_four`.
            let [x, y, z] = columns([
                offset_row(position, i[0] as usize, j[0] as usize),
                offset_row(position, i[1] as usize, j[1] as usize),
                offset_row(position, i[2] as usize, j[2] as usize),
                offset_row(position, i[3] as usize, j[3] as usize),
            ]);
            let dist2 = add_m256d(add_m256d(mul_m256d(x, x), mul_m256d(y, y)), mul_m256d(z, z));
            // `!(≥)`, true for a NaN distance, as the scalar pass.
            let touch = cmp_op_mask_m256d::<{ cmp_op!(NotGreaterEqualUnordered) }>(dist2, cut);
            f.copy_from_slice(&FLAGS[move_mask_m256d(touch) as usize & 15]);
        }
        len / 4 * 4
    }

    /// Gathers four touching pairs into batch slots `m..m + 4`: for each, bodies i, j,
    /// candidate k and whether its ξ was live. Fills what `Batch::set_pair_motion` fills,
    /// with the same bits.
    #[inline(always)]
    pub(super) fn gather_four(
        batch: &mut Batch,
        m: usize,
        bodies: &Bodies,
        contacts: [(usize, usize, usize, bool); 4],
    ) {
        // Written out four times, not looped: a loop kept the rows on the stack.
        let [d0, v0, a0, b0, x0] = contact_rows(bodies, contacts[0]);
        let [d1, v1, a1, b1, x1] = contact_rows(bodies, contacts[1]);
        let [d2, v2, a2, b2, x2] = contact_rows(bodies, contacts[2]);
        let [d3, v3, a3, b3, x3] = contact_rows(bodies, contacts[3]);
        let d = columns([d0, d1, d2, d3]);
        for (a, c) in d.iter().enumerate() {
            put(&mut batch.d[a], m, *c);
        }
        for (a, c) in columns([v0, v1, v2, v3]).into_iter().enumerate() {
            put(&mut batch.dv[a], m, c);
        }
        for (a, c) in columns([a0, a1, a2, a3]).into_iter().enumerate() {
            put(&mut batch.omega[0][a], m, c);
        }
        for (a, c) in columns([b0, b1, b2, b3]).into_iter().enumerate() {
            put(&mut batch.omega[1][a], m, c);
        }
        for (a, c) in columns([x0, x1, x2, x3]).into_iter().enumerate() {
            put(&mut batch.xi[a], m, c);
        }
        // |d|² as glam's `length_squared`: (x x + y y) + z z.
        let dist2 = add_m256d(
            add_m256d(mul_m256d(d[0], d[0]), mul_m256d(d[1], d[1])),
            mul_m256d(d[2], d[2]),
        );
        put(&mut batch.dist2, m, dist2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// Random vectors with components of every sign and size, including zeros of both
    /// signs, which a select and a mask could treat differently.
    fn vectors(rng: &mut Xoshiro256PlusPlus, n: usize) -> Vec<DVec3> {
        let mut c = || match rng.gen_range(0..10) {
            0 => 0.0,
            1 => -0.0,
            _ => rng.gen_range(-1.0..1.0) * 10f64.powi(rng.gen_range(-9..3)),
        };
        (0..n).map(|_| DVec3::new(c(), c(), c())).collect()
    }

    /// `len` random indices below `below`.
    fn indices(rng: &mut Xoshiro256PlusPlus, len: usize, below: usize) -> Vec<u32> {
        (0..len).map(|_| rng.gen_range(0..below as u32)).collect()
    }

    /// The batch as the scalar gather fills it, slot by slot.
    fn scalar(group: &[u32], s: &PairState) -> Batch {
        let mut batch = Batch::default();
        for (m, &k) in group.iter().enumerate() {
            one(&mut batch, m, k, s);
        }
        batch
    }

    #[test]
    fn the_plane_gather_fills_the_batch_bit_for_bit_as_the_scalar_one() {
        // Exact equality of every bit, against the scalar gather itself
        // (`WallSource::gather` with the wall run's plane geometry): the candidates include
        // the last body (whose row cannot be read as four lanes) and the last candidate (the
        // same for ξ), and groups of every length 0..=BATCH exercise both the fours and the
        // slots they leave to the scalar gather.
        use super::super::tests::{jumble_input, Jumble};
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(17);
        // Equal spheres of one material, as the fours require.
        let jumble = Jumble::new(1, false);
        let laws = crate::contact::ContactLaws::default();
        let input = jumble_input(&jumble, &laws);
        let n = jumble.set.len();
        let candidates = 60;
        let mut pi: Vec<u32> = indices(&mut rng, candidates, n);
        pi[candidates - 1] = n as u32 - 1;
        let history = vectors(&mut rng, candidates);
        let live: Vec<u8> = (0..candidates).map(|_| rng.gen_range(0..4)).collect();
        let source = WallSource {
            input: &input,
            velocity: DVec3::new(0.25, -1e-3, 0.0),
            coefficients: None,
            pi: &pi,
            history: &history,
            live: &live,
        };
        let (normal, offset) = (DVec3::new(0.3, -0.5, 0.8).normalize(), -0.02);
        let radius = jumble.set.radius[0];
        let geometry = |b: &mut Batch, m: usize, x: DVec3, r: f64| {
            b.overlap[m] = r - crate::contact::geometry::plane_distance(x, normal, offset);
        };
        for len in 0..=BATCH {
            let mut group: Vec<u32> = indices(&mut rng, len, candidates);
            if len > 0 {
                group[len - 1] = candidates as u32 - 1;
            }
            let (mut want, mut got) = (Batch::default(), Batch::default());
            source.gather(&group, 0, &mut want, geometry);
            let done = plane_motion(&mut got, &group, &source, (normal, offset), radius);
            source.gather(&group, done, &mut got, geometry);
            let bits = |b: &Batch| {
                let rows = b.dv.iter().chain(&b.omega[0]).chain(&b.xi);
                rows.chain(std::iter::once(&b.overlap))
                    .flat_map(|r| r[..len].iter().map(|x| x.to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&got), bits(&want), "group of {len}");
        }
    }

    #[test]
    fn the_pair_filter_by_fours_flags_what_the_scalar_filter_flags() {
        // Exact equality of every flag: one that differs adds or drops a contact. The
        // candidates include the last body (whose row cannot be read as four lanes), a NaN
        // position (which must count as touching) and a distance equal to the cut (which
        // must not), and a count that is not a multiple of four, for the scalar rest.
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let n = 40;
        let mut position = vectors(&mut rng, n);
        position[3].y = f64::NAN;
        let candidates = 103;
        let mut pi: Vec<u32> = indices(&mut rng, candidates, n);
        let mut pj: Vec<u32> = indices(&mut rng, candidates, n);
        (pi[0], pj[1], pj[candidates - 1], pi[7]) = (n as u32 - 1, n as u32 - 1, 3, 3);
        let mut dist2: Vec<f64> = pi
            .iter()
            .zip(&pj)
            .map(|(&i, &j)| (position[i as usize] - position[j as usize]).length_squared())
            .filter(|d| !d.is_nan())
            .collect();
        dist2.sort_by(f64::total_cmp);
        // A cut that one candidate's distance equals, with about half the candidates inside.
        let cut2 = dist2[dist2.len() / 2];

        let mut want = vec![9; candidates];
        super::super::filter::pair_flags::<false>(&position, (&pi, &pj), &mut want, &|_, _| cut2);
        let mut got = vec![9; candidates];
        let done = pair_flags(&position, (&pi, &pj), &mut got, cut2);
        super::super::filter::pair_flags::<false>(
            &position,
            (&pi[done..], &pj[done..]),
            &mut got[done..],
            &|_, _| cut2,
        );
        assert_eq!(got, want);
        // The NaN's candidates touch, and some do not: the test saw both outcomes.
        assert_eq!(want[candidates - 1], 1);
        assert!(want.contains(&0));
    }

    #[test]
    fn the_gather_fills_the_batch_bit_for_bit_as_the_scalar_one() {
        // Exact equality of every bit: the vector path must not change a trajectory.
        // Bodies include the last one (whose row cannot be read as four lanes) and
        // candidates the last one (the same for ξ); groups of every length 0..=BATCH
        // exercise both the fours and the remainder.
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let n = 40;
        let (position, velocity, omega) = (
            vectors(&mut rng, n),
            vectors(&mut rng, n),
            vectors(&mut rng, n),
        );
        let candidates = 60;
        let pi: Vec<u32> = indices(&mut rng, candidates, n);
        let mut pj: Vec<u32> = indices(&mut rng, candidates, n);
        pj[candidates - 1] = n as u32 - 1;
        let history = vectors(&mut rng, candidates);
        let live: Vec<u8> = (0..candidates).map(|_| rng.gen_range(0..4)).collect();
        let state = PairState {
            position: &position,
            velocity: &velocity,
            omega: &omega,
            pi: &pi,
            pj: &pj,
            history: &history,
            live: &live,
        };
        for len in 0..=BATCH {
            let mut group: Vec<u32> = indices(&mut rng, len, candidates);
            if len > 0 {
                group[len - 1] = candidates as u32 - 1;
            }
            let want = scalar(&group, &state);
            let mut got = Batch::default();
            pair_motion(&mut got, &group, &state);
            let bits = |b: &Batch| {
                let rows =
                    b.d.iter()
                        .chain(&b.dv)
                        .chain(&b.omega[0])
                        .chain(&b.omega[1]);
                rows.chain(&b.xi)
                    .chain(std::iter::once(&b.dist2))
                    .flat_map(|r| r[..len].iter().map(|x| x.to_bits()))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(&got), bits(&want), "group of {len}");
        }
    }
}
