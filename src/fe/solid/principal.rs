//! Principal stresses: eigenvalues of the symmetric 3x3 stress tensor in closed form
//! (trigonometric solution of the characteristic cubic, Smith, "Eigenvalues of a symmetric 3 x 3
//! matrix", Commun. ACM 4(4) 168, 1961).

/// Principal stresses (Pa), largest first, of a Voigt stress (xx, yy, zz, yz, xz, xy):
/// q = tr/3, p = sqrt(tr((A - qI)^2)/6), r = det((A - qI)/p)/2, phi = acos(r)/3,
/// s1 = q + 2p cos(phi), s3 = q + 2p cos(phi + 2 pi/3), s2 = 3q - s1 - s3 (Smith 1961).
pub fn principal_stresses_pa(s: &[f64; 6]) -> [f64; 3] {
    let [xx, yy, zz, yz, xz, xy] = *s;
    let off = yz * yz + xz * xz + xy * xy;
    let q = (xx + yy + zz) / 3.0;
    let (a, b, c) = (xx - q, yy - q, zz - q);
    let p2 = a * a + b * b + c * c + 2.0 * off;
    if p2 <= 1e-30 * q * q || p2 == 0.0 {
        return [q; 3];
    }
    let p = (p2 / 6.0).sqrt();
    let (a, b, c, yz, xz, xy) = (a / p, b / p, c / p, yz / p, xz / p, xy / p);
    let det = a * (b * c - yz * yz) - xy * (xy * c - yz * xz) + xz * (xy * yz - b * xz);
    let phi = (0.5 * det).clamp(-1.0, 1.0).acos() / 3.0;
    let s1 = q + 2.0 * p * phi.cos();
    let s3 = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    [s1, 3.0 * q - s1 - s3, s3]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagonal_and_rotated() {
        let e = principal_stresses_pa(&[3.0, -1.0, 2.0, 0.0, 0.0, 0.0]);
        assert!((e[0] - 3.0).abs() < 1e-14 && (e[1] - 2.0).abs() < 1e-14);
        assert!((e[2] + 1.0).abs() < 1e-14);
        // R diag(5, 1, -2) R^T for a rotation by 30 deg about z: xx, yy mix, zz stays.
        let (s, c) = 30.0_f64.to_radians().sin_cos();
        let (l1, l2) = (5.0, 1.0);
        let xx = l1 * c * c + l2 * s * s;
        let yy = l1 * s * s + l2 * c * c;
        let xy = (l1 - l2) * s * c;
        let e = principal_stresses_pa(&[xx, yy, -2.0, 0.0, 0.0, xy]);
        for (a, b) in e.iter().zip([5.0, 1.0, -2.0]) {
            assert!((a - b).abs() < 1e-13, "{e:?}");
        }
        // Invariants of a general tensor: trace and determinant.
        let t = [1.0e6, -2.0e6, 0.5e6, 0.7e6, -0.3e6, 1.2e6];
        let e = principal_stresses_pa(&t);
        assert!((e.iter().sum::<f64>() - (t[0] + t[1] + t[2])).abs() < 1e-6);
        let det = t[0] * (t[1] * t[2] - t[3] * t[3]) - t[5] * (t[5] * t[2] - t[3] * t[4])
            + t[4] * (t[5] * t[3] - t[1] * t[4]);
        assert!((e[0] * e[1] * e[2] - det).abs() < 1e-9 * det.abs());
        assert!(e[0] >= e[1] && e[1] >= e[2]);
        // Hydrostatic.
        assert_eq!(
            principal_stresses_pa(&[2.0, 2.0, 2.0, 0.0, 0.0, 0.0]),
            [2.0; 3]
        );
    }
}
