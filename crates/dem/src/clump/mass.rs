//! A clump's volume, centre of mass and inertia: the moments of the union of its member
//! balls, overlapping members counted once (docs/physics.md §11.2).
//!
//! By inclusion–exclusion, the union's indicator is Σ 1ᵢ − Σ 1ᵢ1ⱼ + R, where the remainder
//! R is non-zero only where three or more members overlap. The balls and the lenses of
//! overlapping pairs have closed-form moments ([`super::cap`]), so a clump in which no three
//! members overlap at once (touching beads, dumbbells, most rods of widely spaced spheres)
//! gets its moments exactly, to round-off. Otherwise R is integrated: exactly along each line
//! parallel to z (the union of the members' chords, less their chords, plus their pairwise
//! overlaps), and by the midpoint rule over a grid of such lines, taken along the direction in
//! which the members spread most. The integrand vanishes wherever fewer than three members
//! meet, so only the triples' region is integrated numerically ([`REMAINDER_LINES`] gives the
//! accuracy).

use glam::{DMat3, DVec3};

use super::cap::{ball, lens, Moments};
use super::principal::principal_frame;

/// Lines across the remainder's extent, each way. With this many, rods of overlapping spheres
/// (RB3 of the verification suite) get their volume and moments within 2.4·10⁻⁶ of the closed
/// form, and a tetrahedral cluster of four balls 1.2 r apart its volume within 1.4·10⁻⁶ of a
/// grid four times finer: the stated accuracy is 10⁻⁵ of the union (docs/physics.md §11.2).
pub const REMAINDER_LINES: usize = 600;

/// One member ball: its centre [m] in the clump's frame and its radius [m].
pub type Ball = (DVec3, f64);

/// The moments of the union of `members` (validated: finite centres, positive radii).
pub fn union_moments(members: &[Ball]) -> Moments {
    let mut sum = members
        .iter()
        .fold(Moments::ZERO, |m, &(c, r)| m + ball(c, r));
    let pairs = overlapping_pairs(members);
    for &(i, j) in &pairs {
        sum = sum - lens(members[i], members[j]);
    }
    let in_triples = members_of_triples(members.len(), &pairs);
    if in_triples.is_empty() {
        return sum;
    }
    let subset: Vec<Ball> = in_triples.iter().map(|&k| members[k]).collect();
    sum + aligned_remainder(&subset, REMAINDER_LINES)
}

/// [`remainder`] with its lines along the direction in which the members' centres spread
/// most: along a rod, each line then crosses the members' surfaces only near its ends, and
/// the grid's error falls by one to two orders of magnitude against lines across the rod.
fn aligned_remainder(members: &[Ball], lines: usize) -> Moments {
    let n = members.len() as f64;
    let mean = members.iter().map(|&(c, _)| c).sum::<DVec3>() / n;
    let spread = members.iter().fold(DMat3::ZERO, |s, &(c, _)| {
        let d = c - mean;
        s + DMat3::from_cols(d * d.x, d * d.y, d * d.z)
    });
    // Columns ascending: the third is the widest spread, which becomes the lines' z.
    let (_, q) = principal_frame(spread);
    let turned: Vec<Ball> = members
        .iter()
        .map(|&(c, r)| (q.transpose() * c, r))
        .collect();
    let m = remainder(&turned, lines);
    Moments {
        volume: m.volume,
        first: q * m.first,
        second: q * m.second * q.transpose(),
    }
}

/// The pairs (i < j) of members whose balls overlap (share volume).
fn overlapping_pairs(members: &[Ball]) -> Vec<(usize, usize)> {
    let mut pairs = Vec::new();
    for (i, &(ci, ri)) in members.iter().enumerate() {
        for (j, &(cj, rj)) in members.iter().enumerate().skip(i + 1) {
            if ci.distance(cj) < ri + rj {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// The members that belong to some triple of mutually overlapping members (only there can
/// three balls share a point), in increasing order.
fn members_of_triples(n: usize, pairs: &[(usize, usize)]) -> Vec<usize> {
    let mut overlap = vec![false; n * n];
    for &(i, j) in pairs {
        overlap[i * n + j] = true;
        overlap[j * n + i] = true;
    }
    let mut member = vec![false; n];
    for &(i, j) in pairs {
        for k in 0..n {
            if overlap[i * n + k] && overlap[j * n + k] {
                member[i] = true;
                member[j] = true;
                member[k] = true;
            }
        }
    }
    (0..n).filter(|&k| member[k]).collect()
}

/// ∫ (1 along z) on a line: length, ∫ z dz and ∫ z² dz over [lo, hi].
fn segment(lo: f64, hi: f64) -> [f64; 3] {
    [
        hi - lo,
        (hi * hi - lo * lo) / 2.0,
        (hi * hi * hi - lo * lo * lo) / 3.0,
    ]
}

/// The remainder R = 1_union − Σ 1ᵢ + Σ 1ᵢ1ⱼ of `members`, integrated exactly along lines
/// parallel to z through the centres of an `lines` × `lines` grid over the members' extent
/// in (x, y), and by the midpoint rule across them.
pub(crate) fn remainder(members: &[Ball], lines: usize) -> Moments {
    let lo = members
        .iter()
        .fold(DVec3::splat(f64::INFINITY), |m, &(c, r)| m.min(c - r));
    let hi = members
        .iter()
        .fold(DVec3::splat(f64::NEG_INFINITY), |m, &(c, r)| m.max(c + r));
    let (hx, hy) = ((hi.x - lo.x) / lines as f64, (hi.y - lo.y) / lines as f64);
    let area = hx * hy;
    let mut chords: Vec<(f64, f64)> = Vec::with_capacity(members.len());
    let mut total = Moments::ZERO;
    for a in 0..lines {
        let x = lo.x + (a as f64 + 0.5) * hx;
        for b in 0..lines {
            let y = lo.y + (b as f64 + 0.5) * hy;
            chords.clear();
            for &(c, r) in members {
                let rho2 = (x - c.x) * (x - c.x) + (y - c.y) * (y - c.y);
                if rho2 < r * r {
                    let half = (r * r - rho2).sqrt();
                    chords.push((c.z - half, c.z + half));
                }
            }
            if chords.len() < 3 {
                continue; // fewer than three members here: R vanishes on this line
            }
            let line = line_remainder(&mut chords);
            if line == [0.0; 3] {
                continue;
            }
            let [l0, l1, l2] = line.map(|v| v * area);
            total = total
                + Moments {
                    volume: l0,
                    first: DVec3::new(x * l0, y * l0, l1),
                    second: DMat3::from_cols(
                        DVec3::new(x * x * l0, x * y * l0, x * l1),
                        DVec3::new(x * y * l0, y * y * l0, y * l1),
                        DVec3::new(x * l1, y * l1, l2),
                    ),
                };
        }
    }
    total
}

/// Along one line, with the members' chords: ∫ R, ∫ R z and ∫ R z², where R is the union's
/// length less the chords' plus their pairwise overlaps. Sorts `chords`.
fn line_remainder(chords: &mut [(f64, f64)]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut add = |sign: f64, (lo, hi): (f64, f64)| {
        let s = segment(lo, hi);
        for k in 0..3 {
            sum[k] += sign * s[k];
        }
    };
    for (i, &a) in chords.iter().enumerate() {
        add(-1.0, a);
        for &b in &chords[i + 1..] {
            let (lo, hi) = (a.0.max(b.0), a.1.min(b.1));
            if lo < hi {
                add(1.0, (lo, hi));
            }
        }
    }
    chords.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut run = chords[0];
    for &c in &chords[1..] {
        if c.0 <= run.1 {
            run.1 = run.1.max(c.1);
        } else {
            add(1.0, run);
            run = c;
        }
    }
    add(1.0, run);
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn relative(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn pairwise_overlaps_are_exact_against_the_lens_closed_form() {
        // Three equal balls on a line, each overlapping its neighbours but the outer two not
        // each other (spacing s = 1.2 r): no triple, so the volume is 3 V − 2 lens with the
        // lens π (4r + s)(2r − s)²/12, to round-off, and the centroid is the middle centre.
        let (r, s) = (0.002, 0.0024);
        let axis = DVec3::new(0.3, -0.4, 0.5).normalize();
        let c = DVec3::new(0.01, 0.02, -0.03);
        let members: Vec<Ball> = [-s, 0.0, s].iter().map(|&t| (c + axis * t, r)).collect();
        let got = union_moments(&members);
        let want = 4.0 * PI * r.powi(3) - 2.0 * PI * (4.0 * r + s) * (2.0 * r - s).powi(2) / 12.0;
        assert!(relative(got.volume, want) <= 1e-13, "{} {want}", got.volume);
        assert!((got.first / got.volume - c).length() <= 1e-15);
    }

    #[test]
    fn the_remainder_vanishes_where_no_three_members_meet_and_converges_where_they_do() {
        // Without a triple, the line integrals cancel exactly; with five members 0.4 r apart
        // along x, halving the lines' spacing moves the remainder's volume by less than the
        // 10⁻⁵ of the union that REMAINDER_LINES is chosen for.
        let r = 0.002;
        let apart: Vec<Ball> = (0..3)
            .map(|k| (DVec3::X * (k as f64 * 1.2 * r), r))
            .collect();
        assert_eq!(remainder(&apart, 200).volume, 0.0);
        let rod: Vec<Ball> = (0..5)
            .map(|k| (DVec3::X * (k as f64 * 0.4 * r), r))
            .collect();
        let union = union_moments(&rod).volume;
        let coarse = aligned_remainder(&rod, REMAINDER_LINES / 2);
        let fine = aligned_remainder(&rod, REMAINDER_LINES);
        assert!(
            fine.volume > 1e-3 * union,
            "the rod has a triple overlap: {}",
            fine.volume
        );
        assert!(
            (fine.volume - coarse.volume).abs() <= 1e-5 * union,
            "{} {}",
            coarse.volume,
            fine.volume
        );
    }
}
