//! The principal frame of a symmetric 3×3 tensor: its eigenvalues in increasing order and a
//! right-handed rotation whose columns are the matching eigenvectors, by cyclic Jacobi
//! rotations (Golub and Van Loan, *Matrix Computations*, §8.5), which converge for every
//! symmetric matrix and are deterministic.

use glam::{DMat3, DQuat, DVec3};

/// Sweeps at most: Jacobi's method converges quadratically, and a 3×3 tensor in double
/// precision needs fewer than ten.
const SWEEPS: usize = 50;

/// Eigenvalues of the symmetric `m`, ascending, and the rotation R (columns: unit
/// eigenvectors, right-handed) with m = R diag(λ) Rᵀ.
#[allow(clippy::needless_range_loop)] // a rotation reads and writes two rows or columns at once
pub fn principal_frame(m: DMat3) -> (DVec3, DMat3) {
    let mut a = m.to_cols_array_2d(); // a[col][row]; symmetric, so a[i][j] reads either way
    let mut v = DMat3::IDENTITY.to_cols_array_2d();
    let scale = m.to_cols_array().iter().fold(0.0f64, |s, x| s.max(x.abs()));
    for _ in 0..SWEEPS {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if !(off > f64::EPSILON * 1e-3 * scale) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // The rotation in the (p, q) plane that zeroes a[p][q] (the smaller angle).
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // a ← Jᵀ a J, column by column then row by row.
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            // v's columns are the eigenvectors: v ← v J.
            let (vp, vq) = (v[p], v[q]);
            for k in 0..3 {
                v[p][k] = c * vp[k] - s * vq[k];
                v[q][k] = s * vp[k] + c * vq[k];
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&x, &y| a[x][x].total_cmp(&a[y][y]));
    let values = DVec3::new(
        a[order[0]][order[0]],
        a[order[1]][order[1]],
        a[order[2]][order[2]],
    );
    let col = |k: usize| DVec3::from_array(v[order[k]]);
    let (e0, e1) = (col(0), col(1));
    // Right-handed: the third axis is the cross product of the first two (the eigenvector up
    // to its sign).
    let rotation = DMat3::from_cols(e0, e1, e0.cross(e1));
    (values, rotation)
}

/// The unit quaternion of a rotation matrix.
pub fn rotation_quaternion(r: DMat3) -> DQuat {
    DQuat::from_mat3(&r).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn worst(m: DMat3) -> f64 {
        m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()))
    }

    #[test]
    fn a_rotated_diagonal_tensor_gives_back_its_values_and_axes() {
        // m = R diag(1, 2.5, 7) Rᵀ for an arbitrary rotation R: the values in order, and
        // m = R' diag R'ᵀ to round-off, with R' a right-handed rotation.
        let q = DQuat::from_axis_angle(DVec3::new(0.3, -1.0, 0.6).normalize(), 1.234);
        let r = DMat3::from_quat(q);
        let d = DMat3::from_diagonal(DVec3::new(2.5, 7.0, 1.0));
        let m = r * d * r.transpose();
        let (values, frame) = principal_frame(m);
        assert!((values - DVec3::new(1.0, 2.5, 7.0)).abs().max_element() <= 1e-13);
        let back = frame * DMat3::from_diagonal(values) * frame.transpose();
        assert!(worst(back - m) <= 1e-13);
        assert!((frame.determinant() - 1.0).abs() <= 1e-13);
        assert!(worst(frame.transpose() * frame - DMat3::IDENTITY) <= 1e-13);
    }

    #[test]
    fn degenerate_and_diagonal_tensors_keep_a_proper_frame() {
        // Isotropic (any frame is principal) and already diagonal tensors.
        for m in [
            DMat3::from_diagonal(DVec3::splat(3.0)),
            DMat3::from_diagonal(DVec3::new(5.0, 1.0, 5.0)),
        ] {
            let (values, frame) = principal_frame(m);
            let back = frame * DMat3::from_diagonal(values) * frame.transpose();
            assert!(worst(back - m) <= 1e-13);
            assert!((frame.determinant() - 1.0).abs() <= 1e-13);
            assert!(values.x <= values.y && values.y <= values.z);
        }
    }
}
