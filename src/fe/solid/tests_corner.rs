//! The corner submodel against exact fields: a uniform strain (any material, any rigid rotation
//! in the corotated frame) and Williams' singular field of a re-entrant wedge.

use super::corner::*;
use super::elasticity::Elasticity;
use super::principal::principal_stresses_pa;

const S: [f64; 3] = [1.0, 0.0, 0.0];
const Z: [f64; 3] = [0.0, 0.0, 1.0];
const T: [f64; 3] = [0.0, 1.0, 0.0];

fn frame(origin_um: [f64; 3]) -> CornerFrame {
    CornerFrame {
        origin_um,
        e_s: S,
        e_z: Z,
        e_t: T,
    }
}

fn mesh(p: usize) -> CornerMesh {
    CornerMesh {
        radius_um: 20.0,
        read_at_um: 0.01,
        rings_per_octave: p,
        octaves_inside: 3,
    }
}

fn solve<D: Fn([f64; 3]) -> Option<[f64; 3]>>(
    origin: [f64; 3],
    sectors: &[CornerSector],
    rings_per_octave: usize,
    kinematics: DriverKinematics,
    field: &D,
) -> CornerSolution {
    solve_corner(
        frame(origin),
        sectors,
        mesh(rings_per_octave),
        kinematics,
        field,
        &SectionPatterns::default(),
    )
    .unwrap()
}

fn silicon() -> Elasticity {
    Elasticity::silicon(crate::fe::material::DieEdge::Along110)
}

fn voigt_of(a: [[f64; 3]; 3]) -> [f64; 6] {
    super::elasticity::VOIGT.map(|(i, j)| if i == j { a[i][i] } else { a[i][j] + a[j][i] })
}

fn stress_of(c: &Elasticity, a: [[f64; 3]; 3]) -> [f64; 6] {
    c.stress_pa(&voigt_of(a))
}

/// A full disc of two silicon sectors under u = A X with A non-symmetric (a small rotation in
/// it) and a gradient along the edge: every ring reads C sym(A), to round-off.
#[test]
fn uniform_strain_is_exact_on_a_full_disc() {
    let a = [
        [3e-4, -1e-4, 2e-4],
        [0.5e-4, -2e-4, 1e-4],
        [1.5e-4, -0.7e-4, 1e-4],
    ];
    let origin = [100.0, 200.0, 50.0];
    let field = |p: [f64; 3]| {
        let d = [0, 1, 2].map(|i| (p[i] - origin[i]) * 1e-6);
        Some([0, 1, 2].map(|i| (0..3).map(|j| a[i][j] * d[j]).sum::<f64>() + 1e-7))
    };
    let c = silicon();
    let sectors = [
        CornerSector {
            from_rad: -1.0,
            to_rad: 2.0,
            material: c,
        },
        CornerSector {
            from_rad: 2.0,
            to_rad: -1.0 + std::f64::consts::TAU,
            material: c,
        },
    ];
    let sol = solve(origin, &sectors, 1, DriverKinematics::Linear, &field);
    let want = principal_stresses_pa(&stress_of(&c, a))[0];
    let rings = sol.rings_um();
    for ring in [1, rings.len() / 2, rings.len() - 2] {
        let (got, _) = sol.max_principal_on_ring(ring, |_| true, &field).unwrap();
        assert!(
            (got - want).abs() <= 1e-9 * want.abs(),
            "ring {ring} ({} um): {got} against {want}",
            rings[ring]
        );
    }
}

/// A large rigid rotation on top of a symmetric strain: the corotated submodel reads the strain's
/// stress alone, on a wedge with free faces (the uniform stress must then be traction-free on
/// them: a uniaxial stress along the wedge's edge, t).
#[test]
fn corotation_takes_out_a_rigid_rotation() {
    let eps_t = 4e-4;
    let c = Elasticity::isotropic(150e9, 0.25);
    // Uniaxial stress along t: strains eps_t along t, -nu eps_t across.
    let a = [
        [-0.25 * eps_t, 0.0, 0.0],
        [0.0, eps_t, 0.0],
        [0.0, 0.0, -0.25 * eps_t],
    ];
    let (ax, th) = ([1.0f64, 2.0, 2.0].map(|v| v / 3.0), 0.3f64);
    let (s, co) = th.sin_cos();
    let k = [
        [0.0, -ax[2], ax[1]],
        [ax[2], 0.0, -ax[0]],
        [-ax[1], ax[0], 0.0],
    ];
    let q: [[f64; 3]; 3] = [0, 1, 2].map(|i| {
        [0, 1, 2].map(|j| {
            let kk: f64 = (0..3).map(|m| k[i][m] * k[m][j]).sum();
            f64::from(u8::from(i == j)) + s * k[i][j] + (1.0 - co) * kk
        })
    });
    let origin = [0.0, 0.0, 0.0];
    let field = |p: [f64; 3]| {
        let d = p.map(|v| v * 1e-6);
        let stretched = [0, 1, 2].map(|i| d[i] + (0..3).map(|j| a[i][j] * d[j]).sum::<f64>());
        let x = [0, 1, 2].map(|i| (0..3).map(|j| q[i][j] * stretched[j]).sum::<f64>());
        Some([0, 1, 2].map(|i| x[i] - d[i]))
    };
    let sectors = [CornerSector {
        from_rad: -2.0,
        to_rad: 2.1,
        material: c,
    }];
    let sol = solve(origin, &sectors, 1, DriverKinematics::Corotated, &field);
    let r = sol.rotation();
    for i in 0..3 {
        for j in 0..3 {
            assert!(
                (r[i][j] - q[i][j]).abs() < 1e-12,
                "rotation {r:?} against {q:?}"
            );
        }
    }
    let want = principal_stresses_pa(&stress_of(&c, a))[0];
    assert!((want - 150e9 * eps_t).abs() < 1e-3 * want);
    let ring = sol.ring_at(0.01).unwrap();
    let (got, _) = sol.max_principal_on_ring(ring, |_| true, &field).unwrap();
    assert!((got - want).abs() <= 1e-8 * want, "{got} against {want}");
    // Read linearly, the same driver carries the rotation's spurious strain (1 - cos 0.3).
    let lin = solve(origin, &sectors, 1, DriverKinematics::Linear, &field);
    let (bad, _) = lin.max_principal_on_ring(ring, |_| true, &field).unwrap();
    assert!((bad - want).abs() > 0.1 * want, "{bad} against {want}");
}

/// Williams' symmetric eigenfunction of a wedge of material angle 2 alpha with free faces (plane
/// strain, isotropic): the exponent from lambda sin(2 alpha) + sin(2 lambda alpha) = 0 (Williams
/// 1952, Eq. 8), Airy function r^(lambda+1) (A cos((lambda+1) phi) + B cos((lambda-1) phi)), B/A
/// from sigma_phiphi(alpha) = 0; displacements 2 mu u_r = r^lambda (-(lambda+1) A cos((lambda+1)
/// phi) + (kappa - lambda) B cos((lambda-1) phi)), 2 mu u_phi = r^lambda ((lambda+1) A
/// sin((lambda+1) phi) + (kappa + lambda) B sin((lambda-1) phi)), kappa = 3 - 4 nu (Barber,
/// Elasticity, 3rd ed., sec. 11.2 and Table 8.1).
struct Williams {
    lambda: f64,
    a: f64,
    b: f64,
    mu: f64,
    kappa: f64,
    nu: f64,
}

impl Williams {
    fn new(alpha: f64, e: f64, nu: f64) -> Self {
        let lambda = williams_exponent(2.0 * alpha);
        let a = 1e6;
        let b = -a * ((lambda + 1.0) * alpha).cos() / ((lambda - 1.0) * alpha).cos();
        Williams {
            lambda,
            a,
            b,
            mu: e / (2.0 * (1.0 + nu)),
            kappa: 3.0 - 4.0 * nu,
            nu,
        }
    }
    /// (u_r, u_phi) in m at r (m), phi.
    fn displacement(&self, r: f64, phi: f64) -> (f64, f64) {
        let l = self.lambda;
        let rl = r.powf(l) / (2.0 * self.mu);
        (
            rl * (-(l + 1.0) * self.a * ((l + 1.0) * phi).cos()
                + (self.kappa - l) * self.b * ((l - 1.0) * phi).cos()),
            rl * ((l + 1.0) * self.a * ((l + 1.0) * phi).sin()
                + (self.kappa + l) * self.b * ((l - 1.0) * phi).sin()),
        )
    }
    /// (s_rr, s_phiphi, s_rphi, s_zz) in Pa.
    fn stress(&self, r: f64, phi: f64) -> [f64; 4] {
        let l = self.lambda;
        let (c1, c2) = (((l + 1.0) * phi).cos(), ((l - 1.0) * phi).cos());
        let (s1, s2) = (((l + 1.0) * phi).sin(), ((l - 1.0) * phi).sin());
        let rl = r.powf(l - 1.0);
        let srr = rl * (-self.a * l * (l + 1.0) * c1 + self.b * l * (3.0 - l) * c2);
        let spp = rl * l * (l + 1.0) * (self.a * c1 + self.b * c2);
        let srp = rl * l * (self.a * (l + 1.0) * s1 + self.b * (l - 1.0) * s2);
        [srr, spp, srp, self.nu * (srr + spp)]
    }
    fn max_principal(&self, r: f64, phi: f64) -> f64 {
        let [srr, spp, srp, szz] = self.stress(r, phi);
        let inplane = 0.5 * (srr + spp) + (0.25 * (srr - spp).powi(2) + srp * srp).sqrt();
        inplane.max(szz)
    }
}

/// The reference is an elasticity solution: its strains (by central differences) through Hooke's
/// law give its stresses, and its faces are traction-free.
#[test]
fn williams_reference_is_consistent() {
    let alpha = 0.5 * (180.0 + 54.7356f64).to_radians();
    let w = Williams::new(alpha, 150e9, 0.25);
    assert!(w.lambda > 0.5 && w.lambda < 1.0);
    let (e, nu) = (150e9, 0.25);
    let lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let xy = |x: f64, y: f64| {
        let (r, p) = ((x * x + y * y).sqrt(), y.atan2(x));
        let (ur, up) = w.displacement(r, p);
        (ur * p.cos() - up * p.sin(), ur * p.sin() + up * p.cos())
    };
    for (r, p) in [(1e-6, 0.3), (3e-6, -1.5), (2e-6, 1.9)] {
        let (x, y) = (r * f64::cos(p), r * f64::sin(p));
        let h = 1e-4 * r;
        let (uxp, uyp) = xy(x + h, y);
        let (uxm, uym) = xy(x - h, y);
        let (vxp, vyp) = xy(x, y + h);
        let (vxm, vym) = xy(x, y - h);
        let (exx, eyy) = ((uxp - uxm) / (2.0 * h), (vyp - vym) / (2.0 * h));
        let gxy = (uyp - uym) / (2.0 * h) + (vxp - vxm) / (2.0 * h);
        let sxx = lam * (exx + eyy) + 2.0 * w.mu * exx;
        let syy = lam * (exx + eyy) + 2.0 * w.mu * eyy;
        let sxy = w.mu * gxy;
        let [srr, spp, srp, _] = w.stress(r, p);
        let (c, s) = (p.cos(), p.sin());
        let want_xx = srr * c * c + spp * s * s - 2.0 * srp * s * c;
        let want_yy = srr * s * s + spp * c * c + 2.0 * srp * s * c;
        let want_xy = (srr - spp) * s * c + srp * (c * c - s * s);
        let scale = srr.abs().max(spp.abs()).max(srp.abs());
        for (got, want) in [(sxx, want_xx), (syy, want_yy), (sxy, want_xy)] {
            assert!((got - want).abs() < 1e-6 * scale, "{got} against {want}");
        }
    }
    let [_, spp, srp, _] = w.stress(1e-6, alpha);
    assert!(
        spp.abs() < 1e-9 * w.stress(1e-6, 0.0)[1].abs() && srp.abs() < 1e-9 * spp.abs().max(1.0)
    );
}

#[test]
fn williams_exponents_of_known_wedges() {
    // The crack (360 deg) is 1/2, the right-angle re-entrant corner (270 deg) 0.5445
    // (Williams 1952, Fig. 5; Seweryn & Molski 1996, Table 1: 0.5445).
    let deg = |d: f64| d.to_radians();
    assert!((williams_exponent(deg(360.0)) - 0.5).abs() < 1e-9);
    assert!((williams_exponent(deg(270.0)) - 0.544_483_7).abs() < 1e-6);
    let l = williams_exponent(deg(234.7356));
    assert!((l - 0.634_008).abs() < 1e-5, "{l}");
    // Nearly a flat face (180 deg): nearly no singularity.
    assert!(williams_exponent(deg(181.0)) > 0.98);
}

/// The submodel reproduces the singular field on the ring it reads, and refining it (more rings
/// per octave, narrower sectors) converges to Williams' value.
#[test]
fn submodel_resolves_the_williams_singular_field() {
    let alpha = 0.5 * (180.0 + 54.7356f64).to_radians();
    let w = Williams::new(alpha, 150e9, 0.25);
    let bisector = -0.3;
    let field = |p: [f64; 3]| {
        let (s, z) = (p[0] * 1e-6, p[2] * 1e-6);
        let r = (s * s + z * z).sqrt();
        if r == 0.0 {
            return Some([0.0; 3]);
        }
        let phi = z.atan2(s) - bisector;
        let phi =
            (phi + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        let (ur, up) = w.displacement(r, phi);
        let th = phi + bisector;
        Some([
            ur * th.cos() - up * th.sin(),
            0.0,
            ur * th.sin() + up * th.cos(),
        ])
    };
    let sectors = [CornerSector {
        from_rad: bisector - alpha,
        to_rad: bisector + alpha,
        material: Elasticity::isotropic(150e9, 0.25),
    }];
    let want = (0..=2000)
        .map(|i| w.max_principal(0.01e-6, -alpha + 2.0 * alpha * f64::from(i) / 2000.0))
        .fold(f64::NEG_INFINITY, f64::max);
    let mut got = Vec::new();
    for p in [1, 2, 4] {
        let sol = solve([0.0; 3], &sectors, p, DriverKinematics::Linear, &field);
        let ring = sol.ring_at(0.01).unwrap();
        got.push(sol.max_principal_on_ring(ring, |_| true, &field).unwrap().0);
    }
    let errors: Vec<f64> = got.iter().map(|g| (g - want).abs() / want).collect();
    // Measured: 7.4e-3, 3.4e-3, 8.0e-4.
    assert!(errors[2] < 1.5e-3, "{errors:?}");
    assert!(errors[2] < errors[1] && errors[1] < errors[0], "{errors:?}");
    // What `sensor::edge_stress` takes as the finer mesh's estimate bounds its error.
    assert!(
        (got[2] - got[1]).abs() / got[2] >= errors[2],
        "{got:?} against {want}"
    );
}

/// Sections sharing one `SectionPatterns` (as one read-out's do) solve exactly as each on its own:
/// a second section of the same topology (another place, another field) takes the first one's
/// pattern and symbolic factorisation, one of another topology (finer rings) adds its own, and
/// every stress is bit-identical to a fresh cache's.
#[test]
fn sections_sharing_patterns_solve_as_each_alone() {
    let c = silicon();
    let wall = 1f64.atan2(1.0 / 2f64.sqrt());
    let sectors = [CornerSector {
        from_rad: -std::f64::consts::PI,
        to_rad: wall,
        material: c,
    }];
    let bending = |k: f64| {
        move |p: [f64; 3]| {
            let (x, y, z) = (p[0] * 1e-3, p[1] * 1e-3, p[2] * 1e-3);
            Some([1e-7 * k * x * z, -2e-7 * y * z, 1e-7 * (x * x + k * y * y)])
        }
    };
    let shared = SectionPatterns::default();
    let cases = [
        ([100.0, 200.0, 50.0], 2, 1.0),
        ([130.0, 180.0, 40.0], 2, -0.5),
        ([100.0, 200.0, 50.0], 4, 2.0),
    ];
    for (i, &(origin, rings, k)) in cases.iter().enumerate() {
        let field = bending(k);
        let run = |patterns: &SectionPatterns| {
            let sol = solve_corner(
                frame(origin),
                &sectors,
                mesh(rings),
                DriverKinematics::Linear,
                &field,
                patterns,
            )
            .unwrap();
            let ring = sol.ring_at(0.01).unwrap();
            sol.stresses_on_ring(ring, |_| true, &field).unwrap()
        };
        let (alone, with_shared) = (run(&SectionPatterns::default()), run(&shared));
        assert!(!alone.is_empty());
        assert_eq!(alone, with_shared, "case {i}");
        assert_eq!(shared.len(), [1, 1, 2][i], "case {i}");
    }
}
