//! Orientation statistics of elongated grains: how their long axes line up with a direction
//! (the flow's, a wall's normal) and with each other (docs/physics.md §11.5).
//!
//! For unit axes uᵢ (a grain's axis and its reverse are the same, so only even functions of u
//! count):
//! - the **alignment** with a unit direction n is ⟨P₂(u·n)⟩ = ⟨(3 (u·n)² − 1)/2⟩: 1 when every
//!   axis lies along n, −1/2 when every one is normal to it, 0 for axes spread evenly in every
//!   direction;
//! - the **order tensor** Q = ⟨(3 u uᵀ − 1)/2⟩ (de Gennes and Prost, *The Physics of Liquid
//!   Crystals*, §2.1) is symmetric and traceless; its largest eigenvalue S is the **nematic
//!   order parameter** (1 all aligned, 0 isotropic, 1/4 for axes spread evenly in a plane) and
//!   its eigenvector the **director**, the direction the axes favour, found without choosing
//!   one beforehand.

/// The order of a set of axes: the nematic order parameter S and the director.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NematicOrder {
    /// S, the order tensor's largest eigenvalue [-], in [0, 1].
    pub order: f64,
    /// The director, a unit vector (its sign is arbitrary).
    pub director: [f64; 3],
}

fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

/// ⟨P₂(u·n)⟩ of the `axes` (normalised here; zero or non-finite ones left out) against the
/// `direction`; `None` without any axis or direction.
pub fn alignment(axes: &[[f64; 3]], direction: [f64; 3]) -> Option<f64> {
    let n = unit(direction)?;
    let (mut sum, mut count) = (0.0, 0usize);
    for u in axes.iter().filter_map(|&a| unit(a)) {
        let c = u[0] * n[0] + u[1] * n[1] + u[2] * n[2];
        sum += 1.5 * c * c - 0.5;
        count += 1;
    }
    (count > 0).then(|| sum / count as f64)
}

/// The order tensor Q = ⟨(3 u uᵀ − 1)/2⟩ of the `axes` (normalised here; zero or non-finite
/// ones left out), `None` without any.
pub fn order_tensor(axes: &[[f64; 3]]) -> Option<[[f64; 3]; 3]> {
    let mut q = [[0.0; 3]; 3];
    let mut count = 0usize;
    for u in axes.iter().filter_map(|&a| unit(a)) {
        for (a, row) in q.iter_mut().enumerate() {
            for (b, x) in row.iter_mut().enumerate() {
                *x += 1.5 * u[a] * u[b];
            }
        }
        count += 1;
    }
    if count == 0 {
        return None;
    }
    for (a, row) in q.iter_mut().enumerate() {
        for x in row.iter_mut() {
            *x /= count as f64;
        }
        row[a] -= 0.5;
    }
    Some(q)
}

/// S and the director of the `axes` ([`order_tensor`]'s largest eigenvalue and its vector).
pub fn nematic_order(axes: &[[f64; 3]]) -> Option<NematicOrder> {
    let q = order_tensor(axes)?;
    let order = largest_eigenvalue(&q);
    Some(NematicOrder {
        order,
        director: eigenvector(&q, order),
    })
}

/// The largest eigenvalue of a symmetric 3×3 matrix, in closed form (Smith 1961, Commun. ACM
/// 4, 168): with m = tr/3 and B = (A − m)/p, the eigenvalues are m + 2p cos(φ + 2πk/3) with
/// cos 3φ = det(B)/2.
fn largest_eigenvalue(a: &[[f64; 3]; 3]) -> f64 {
    let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    let m = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let d = [a[0][0] - m, a[1][1] - m, a[2][2] - m];
    let p2 = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * off) / 6.0;
    if p2 <= 0.0 || p2.is_nan() {
        return m; // a multiple of the identity
    }
    let p = p2.sqrt();
    let b = |i: usize, j: usize| if i == j { d[i] / p } else { a[i][j] / p };
    let det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1))
        - b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0))
        + b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
    let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    m + 2.0 * p * phi.cos()
}

/// A unit eigenvector of the symmetric `a` for its eigenvalue `lambda`: the longest cross
/// product of two rows of a − λ 1 (each row is normal to the eigenvector).
fn eigenvector(a: &[[f64; 3]; 3], lambda: f64) -> [f64; 3] {
    let r = |i: usize| {
        let mut row = a[i];
        row[i] -= lambda;
        row
    };
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let norm2 = |v: [f64; 3]| v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let best = [cross(r(0), r(1)), cross(r(0), r(2)), cross(r(1), r(2))]
        .into_iter()
        .max_by(|x, y| norm2(*x).total_cmp(&norm2(*y)))
        .unwrap_or([0.0; 3]);
    // A degenerate largest eigenvalue (uniaxial about an axis of the smaller ones cannot
    // happen for the largest unless all are equal): any unit vector will do then.
    unit(best).unwrap_or([0.0, 0.0, 1.0])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        // Round-off of sums of a few hundred unit products.
        (a - b).abs() <= 1e-12
    }

    #[test]
    fn aligned_axes_have_order_one_along_their_direction() {
        // Every axis along ±n: S = 1, the director ±n, alignment 1 with n and −1/2 with a
        // direction normal to it.
        let n = [0.48, -0.6, 0.64];
        let axes: Vec<[f64; 3]> = (0..10)
            .map(|k| {
                let s = if k % 2 == 0 { 2.0 } else { -0.5 };
                [n[0] * s, n[1] * s, n[2] * s]
            })
            .collect();
        let order = nematic_order(&axes).expect("axes");
        assert!(close(order.order, 1.0), "{order:?}");
        let dot: f64 = (0..3).map(|k| order.director[k] * n[k]).sum();
        assert!(close(dot.abs(), 1.0), "{order:?}");
        assert!(close(alignment(&axes, n).expect("axes"), 1.0));
        assert!(close(
            alignment(&axes, [0.8, 0.64, 0.0]).expect("axes"),
            -0.5
        ));
    }

    #[test]
    fn evenly_spread_axes_have_the_textbook_orders() {
        // The 3 coordinate axes: isotropic, S = 0 and no alignment with any of them. Axes
        // evenly around the z = 0 plane's circle: S = 1/4, the director in the plane (Q has
        // eigenvalues 1/4, 1/4, −1/2), alignment −1/2 with z.
        let three = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 3.0]];
        assert!(close(nematic_order(&three).expect("axes").order, 0.0));
        assert!(close(
            alignment(&three, [0.0, 0.0, 1.0]).expect("axes"),
            0.0
        ));
        let ring: Vec<[f64; 3]> = (0..12)
            .map(|k| {
                let a = k as f64 * std::f64::consts::PI / 6.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let order = nematic_order(&ring).expect("axes");
        assert!(close(order.order, 0.25), "{order:?}");
        assert!(close(order.director[2], 0.0), "{order:?}");
        assert!(close(
            alignment(&ring, [0.0, 0.0, 1.0]).expect("axes"),
            -0.5
        ));
        // Nothing to average: none.
        assert_eq!(nematic_order(&[[0.0; 3]]), None);
        assert_eq!(alignment(&three, [0.0; 3]), None);
    }

    #[test]
    fn the_closed_form_eigenvalue_is_the_largest_root() {
        // A symmetric matrix with eigenvalues 3, 1, −2 along an arbitrary orthonormal frame:
        // the largest, and its vector.
        let e = [
            [2.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0],
            [-2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0],
            [1.0 / 3.0, -2.0 / 3.0, 2.0 / 3.0],
        ];
        let values = [3.0, 1.0, -2.0];
        let mut a = [[0.0; 3]; 3];
        for (k, v) in e.iter().enumerate() {
            for i in 0..3 {
                for j in 0..3 {
                    a[i][j] += values[k] * v[i] * v[j];
                }
            }
        }
        let top = largest_eigenvalue(&a);
        assert!(close(top, 3.0), "{top}");
        let v = eigenvector(&a, top);
        let dot: f64 = (0..3).map(|k| v[k] * e[0][k]).sum();
        assert!(close(dot.abs(), 1.0), "{v:?}");
    }
}
