//! Validation of the solid rung: patch test on curved elements, cantilevers against beam theory
//! with shear, a silicon plate against the Kirchhoff rung, equilibrium, symmetry, linearity, the
//! half model, and bad input.

use std::sync::Arc;

use crate::fe::error::{FeError, FeResult};
use crate::fe::material::DieEdge;
use crate::fe::solid::*;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The small strain (Voigt, engineering shears) of the displacement gradient `g[i][j]` =
/// du_i / dx_j.
pub(super) fn voigt_strain(g: &[[f64; 3]; 3]) -> [f64; 6] {
    [
        g[0][0],
        g[1][1],
        g[2][2],
        g[1][2] + g[2][1],
        g[0][2] + g[2][0],
        g[0][1] + g[1][0],
    ]
}

/// The linear field u = u0 + G x (m, x in um) of a patch test.
pub(super) fn linear_field_m(
    u0_m: [f64; 3],
    gradient: [[f64; 3]; 3],
) -> impl Fn([f64; 3]) -> [f64; 3] {
    move |x_um| {
        std::array::from_fn(|i| {
            u0_m[i] + (0..3).map(|j| gradient[i][j] * x_um[j] * 1e-6).sum::<f64>()
        })
    }
}

pub(super) fn plane(axis: Axis3, at_um: f64) -> NodeSet {
    NodeSet::Plane { axis, at_um }
}

/// Holds every node of the six faces of the cube [lo, hi]^3 um to the linear field
/// u = u0 + G x (patch tests, imposed rigid motions).
pub(super) fn prescribe_linear_on_faces(
    p: &mut SolidProblem,
    (lo, hi): (f64, f64),
    u0_m: [f64; 3],
    gradient: [[f64; 3]; 3],
) {
    prescribe_linear_on_box(p, [lo; 3], [hi; 3], u0_m, gradient);
}

/// Holds every node of the six faces of the box [lo, hi] um to the linear field u = u0 + G x.
pub(super) fn prescribe_linear_on_box(
    p: &mut SolidProblem,
    lo: [f64; 3],
    hi: [f64; 3],
    u0_m: [f64; 3],
    gradient: [[f64; 3]; 3],
) {
    for (d, axis) in [Axis3::X, Axis3::Y, Axis3::Z].into_iter().enumerate() {
        for at in [lo[d], hi[d]] {
            p.constraints.push(Constraint {
                group: "boundary".into(),
                nodes: plane(axis, at),
                fixed: [true; 3],
                value: Prescribed::Linear { u0_m, gradient },
            });
        }
    }
}

/// The 2x2x2 block [0, 2000]^3 um with every non-boundary node moved by a smooth map: curved
/// element edges and faces, and mid-side nodes off their midpoints.
fn distorted_block() -> HexGrid {
    let l = [0.0, 1000.0, 2000.0];
    HexGrid::new(&l, &l, &l)
        .unwrap()
        .with_map(Arc::new(|p: [f64; 3]| {
            let s = |v: f64| (std::f64::consts::PI * v / 2000.0).sin();
            let bump = 150.0 * s(p[0]) * s(p[1]) * s(p[2]);
            let wave = 60.0 * s(2.0 * p[0]) * s(p[1]) * s(p[2]);
            [p[0] + bump, p[1] - 0.7 * bump + wave, p[2] + 0.4 * bump]
        }))
}

/// Patch test (Irons; Hughes sec. 4.6): a linear displacement field prescribed on the boundary
/// of a block of curved, anisotropic elements is reproduced exactly inside, with exact constant
/// stress everywhere, with either transverse shear.
#[test]
fn patch_test_on_distorted_elements() {
    for shear in [TransverseShear::Displacement, TransverseShear::Tied] {
        patch_check(shear);
    }
}

fn patch_check(shear: TransverseShear) {
    let grid = distorted_block();
    let c = Elasticity::cubic(165.7e9, 63.9e9, 79.6e9).rotated_about_z(30.0);
    let mut p = SolidProblem::new(grid, vec![c]);
    p.shear = shear;
    let gradient = [
        [1.0e-4, 2.0e-5, -3.0e-5],
        [5.0e-5, -2.0e-4, 1.0e-5],
        [-4.0e-5, 6.0e-5, 1.5e-4],
    ];
    let u0_m = [1e-7, -2e-7, 3e-7];
    prescribe_linear_on_faces(&mut p, (0.0, 2000.0), u0_m, gradient);
    p.load_cases.push(vec![]);
    let s = &p.solve().unwrap()[0];
    let exact = linear_field_m(u0_m, gradient);
    // Interior nodes (the only free ones) and every node.
    let scale = 2000e-6 * 2e-4;
    let mut worst_u: f64 = 0.0;
    for (n, x) in s.node_positions_um().iter().enumerate() {
        let (u, e) = (s.node_displacement_m(n), exact(*x));
        for d in 0..3 {
            worst_u = worst_u.max((u[d] - e[d]).abs() / scale);
        }
    }
    assert!(worst_u < 1e-10, "displacement error {worst_u:e}");
    let eps = voigt_strain(&gradient);
    let sigma = c.stress_pa(&eps);
    let s_scale = sigma.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let mut worst_s: f64 = 0.0;
    for e in 0..8 {
        let ijk = [e % 2, (e / 2) % 2, e / 4];
        for xi in [[0.0, 0.0, 0.0], [-1.0, 1.0, -1.0], [0.77, -0.3, 0.5]] {
            let st = s.stress_at(ijk, xi).unwrap();
            for d in 0..6 {
                worst_s = worst_s.max((st[d] - sigma[d]).abs() / s_scale);
            }
        }
    }
    assert!(worst_s < 1e-10, "stress error {worst_s:e}");
    // A point given by position (after the map) interpolates the field too.
    let at = [700.0, 1300.0, 1100.0];
    let u = s.displacement_m(at).unwrap();
    let e = exact(at);
    assert!(
        (0..3).all(|d| (u[d] - e[d]).abs() < 1e-10 * scale),
        "{u:?} {e:?}"
    );
    // No load: the boundary reactions balance.
    let r = s.reaction_n("boundary").unwrap();
    let big = s
        .nodal_reactions("boundary")
        .iter()
        .map(|(_, f)| f[0].abs().max(f[1].abs()).max(f[2].abs()))
        .fold(0.0, f64::max);
    assert!(r.iter().all(|v| v.abs() < 1e-9 * big), "{r:?} vs {big}");
}

/// Uniform shear traction on the end face x = L as consistent nodal forces: per element face the
/// tensor product of the 1-D quadratic weights (1, 4, 1)/6 (Hughes Eq. 3.9.7 for a constant).
pub(super) fn end_shear(l_um: f64, ys: &[f64], zs: &[f64], force_n: f64) -> Vec<SolidLoad> {
    let weights = |lines: &[f64]| -> Vec<(f64, f64)> {
        let total = lines[lines.len() - 1] - lines[0];
        let mut w = Vec::new();
        for s in lines.windows(2) {
            let f = (s[1] - s[0]) / total;
            w.push((s[0], f / 6.0));
            w.push((0.5 * (s[0] + s[1]), 4.0 * f / 6.0));
            w.push((s[1], f / 6.0));
        }
        w
    };
    let mut out = Vec::new();
    for (y, wy) in weights(ys) {
        for (z, wz) in weights(zs) {
            out.push(SolidLoad::Point {
                at_um: [l_um, y, z],
                force_n: [0.0, 0.0, -force_n * wy * wz],
                snap: Snap::Exact,
            });
        }
    }
    out
}

/// Tip deflection of a clamped square cantilever (h = b = 100 um) relative to Timoshenko's
/// PL^3/(3EI) + PL/(kappa G A), kappa = 10(1+nu)/(12+11nu) (Cowper 1966, rectangle).
fn cantilever_error(slender: f64, nx: usize, n_section: usize, nu: f64) -> (f64, f64) {
    let h = 100.0;
    let l = slender * h;
    let e_pa = 169e9;
    let section = uniform_lines(0.0, h, n_section);
    let grid = HexGrid::new(&uniform_lines(0.0, l, nx), &section, &section).unwrap();
    let mut p = SolidProblem::new(grid, vec![Elasticity::isotropic(e_pa, nu)]);
    p.constraints
        .push(Constraint::clamp("root", plane(Axis3::X, 0.0)));
    let f = 1e-3;
    p.load_cases.push(end_shear(l, &section, &section, f));
    let s = &p.solve().unwrap()[0];
    let w = -s.displacement_m([l, 0.5 * h, 0.5 * h]).unwrap()[2];
    let (hm, lm) = (h * 1e-6, l * 1e-6);
    let i = hm.powi(4) / 12.0;
    let g = e_pa / (2.0 * (1.0 + nu));
    let kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
    let w_ref = f * lm.powi(3) / (3.0 * e_pa * i) + f * lm / (kappa * g * hm * hm);
    // Equilibrium on the way: the clamp returns the load.
    let r = s.reaction_n("root").unwrap();
    assert!(rel(r[2], f) < 1e-9 && r[0].abs() < 1e-9 * f, "{r:?}");
    (w / w_ref - 1.0, w_ref)
}

/// One and two elements through the thickness, element aspect ratios up to 4: within 1 % of
/// beam theory at L/h = 20 and 100 (no shear locking of the 27-node brick). Measured (nu = 0.3):
/// L/h = 20: 10 / 20 / 40 elements -1.19 / -0.69 / -0.50 %, 20 x 2 x 2 -0.65 %; L/h = 100:
/// 25 / 50 / 100 elements -0.47 / -0.23 / -0.13 %, 50 x 2 x 2 -0.23 %. The limit near -0.5 %
/// (L/h = 20) and -0.1 % (L/h = 100), shrinking like h/L, is the clamp holding the root face's
/// Poisson contraction, which beam theory ignores: with nu = 0 the error is 0.03 %.
#[test]
fn cantilever_matches_timoshenko() {
    for (slender, nx, n_section, nu, tol) in [
        (20.0, 20, 1, 0.3, 0.01),
        (20.0, 40, 1, 0.3, 0.01),
        (20.0, 20, 2, 0.3, 0.01),
        (20.0, 20, 1, 0.0, 0.001),
        (100.0, 25, 1, 0.3, 0.01),
        (100.0, 50, 2, 0.3, 0.01),
        (100.0, 25, 1, 0.0, 0.001),
    ] {
        let (err, w_ref) = cantilever_error(slender, nx, n_section, nu);
        eprintln!(
            "cantilever L/h = {slender}, {nx} x {n_section} x {n_section} elements, nu = {nu}: \
             w_ref = {w_ref:.4e} m, error {:+.3} %",
            100.0 * err
        );
        assert!(
            err.abs() < tol,
            "L/h {slender}, {nx} elements, nu {nu}: {err:e}"
        );
    }
}

const SPAN_UM: f64 = 10_000.0;
const T_UM: f64 = 100.0;

/// Si plate (die edges along <110>) over x in `x`, y in `y` (um), 100 um thick, elements of
/// `h_um` in plane and `nz` through the thickness; the edges x = 0 and x = 10 mm (where in the
/// grid) clamped on their whole faces; symmetry planes at x or y = 5 mm where the grid ends there.
fn si_plate(x: (f64, f64), y: (f64, f64), h_um: f64, nz: usize) -> SolidProblem {
    let lines = |(a, b): (f64, f64)| uniform_lines(a, b, ((b - a) / h_um).round() as usize);
    let grid = HexGrid::new(&lines(x), &lines(y), &uniform_lines(0.0, T_UM, nz)).unwrap();
    let mut p = SolidProblem::new(grid, vec![Elasticity::silicon(DieEdge::Along110)]);
    for (at, name) in [(0.0, "x0"), (SPAN_UM, "x1")] {
        if at == x.0 || at == x.1 {
            p.constraints
                .push(Constraint::clamp(name, plane(Axis3::X, at)));
        }
    }
    let half = 0.5 * SPAN_UM;
    if x.1 == half {
        p.constraints
            .push(Constraint::symmetry("sym-x", Axis3::X, half));
    }
    if y.1 == half {
        p.constraints
            .push(Constraint::symmetry("sym-y", Axis3::Y, half));
    }
    p
}

/// Uniform pressure giving `force_n` over the whole centre square 4.5-5.5 mm on the top face,
/// applied to the part of the square inside the grid (a quarter model gets a quarter).
fn centre_patch(p: &SolidProblem, force_n: f64) -> SolidLoad {
    let [xs, ys, _] = p.grid.lines_um();
    let clip = |l: &[f64]| (4500.0_f64.max(l[0]), 5500.0_f64.min(l[l.len() - 1]));
    let (cx, cy) = (clip(xs), clip(ys));
    SolidLoad::Pressure {
        face: FaceRect {
            axis: Axis3::Z,
            at_um: T_UM,
            outward: Outward::Plus,
            from_um: [cx.0, cy.0],
            to_um: [cx.1, cy.1],
        },
        pressure_pa: force_n / 1e-6,
    }
}

/// Centre deflection of the Kirchhoff rung (BFS, 125 um elements) for the same plate and patch.
fn kirchhoff_centre_m(force_n: f64) -> f64 {
    use crate::fe::{
        Axis, LineSupport, Load, PlateMaterial, PlateProblem, RectMesh, RectUm, SupportKind,
    };
    let l = [0.0, 4500.0, 5000.0, 5500.0, SPAN_UM];
    let mut p = PlateProblem::new(
        RectMesh::build(&l, &l, 125.0, &[]),
        T_UM,
        PlateMaterial::silicon(DieEdge::Along110),
    );
    for (g, at) in [("x0", 0.0), ("x1", SPAN_UM)] {
        p.supports.push(LineSupport {
            group: g.into(),
            kind: SupportKind::Clamped,
            along: Axis::Y,
            at_um: at,
            from_um: 0.0,
            to_um: SPAN_UM,
        });
    }
    p.load_cases.push(vec![Load::Pressure {
        region: Some(RectUm {
            x0_um: 4500.0,
            y0_um: 4500.0,
            x1_um: 5500.0,
            y1_um: 5500.0,
        }),
        total_force_n: force_n,
    }]);
    p.solve().unwrap()[0].deflection_m(5000.0, 5000.0)
}

/// The plain plate: two opposite edges clamped, two free, 1 N on a 1 mm square patch at the
/// centre. The quarter solid (symmetry planes) against the Kirchhoff rung (BFS, 125 um), centre
/// deflection of the solid's mid-plane.
#[test]
fn silicon_plate_matches_kirchhoff() {
    let w_k = kirchhoff_centre_m(1.0);
    let mut last = 0.0;
    for (h, nz) in [(500.0, 1), (250.0, 1), (250.0, 2), (125.0, 1)] {
        let mut p = si_plate((0.0, 5000.0), (0.0, 5000.0), h, nz);
        p.load_cases.push(vec![centre_patch(&p, 1.0)]);
        let s = &p.solve().unwrap()[0];
        let w = -s.displacement_m([5000.0, 5000.0, 50.0]).unwrap()[2];
        eprintln!(
            "Si plate quarter, {h} um x {nz} layers: centre (mid-plane) {w:.6e} m, Kirchhoff \
             {w_k:.6e} m, ratio - 1 = {:+.3} %",
            100.0 * (w / w_k - 1.0)
        );
        // Equilibrium: the clamp carries the quarter load (symmetry planes carry no z force).
        let r = s.reaction_n("x0").unwrap();
        assert!(rel(r[2], 0.25) < 1e-9, "{r:?}");
        assert!(s.reaction_n("sym-x").unwrap()[2].abs() < 1e-12);
        last = w / w_k - 1.0;
    }
    // Measured -0.99 / -0.15 / -0.12 (2 layers) / +0.03 %: the solid converges at about order 2
    // to ~ +0.08 % above Kirchhoff (Richardson on 500/250/125 um), the size of the shear
    // correction at (t / L)^2 = 1e-4 times an O(10) factor of a patch load.
    assert!(last.abs() < 0.002, "{last:e}");
}

/// The full plate: reactions balance the load, the field is mirror-symmetric about both centre
/// lines, twice the load gives twice the field in the same factorisation.
#[test]
fn full_plate_equilibrium_symmetry_linearity() {
    let mut p = si_plate((0.0, SPAN_UM), (0.0, SPAN_UM), 500.0, 1);
    p.load_cases.push(vec![centre_patch(&p, 1.0)]);
    p.load_cases.push(vec![centre_patch(&p, 2.0)]);
    // An off-centre oblique point force too: equilibrium of all three components.
    p.load_cases.push(vec![SolidLoad::Point {
        at_um: [3000.0, 7250.0, 100.0],
        force_n: [0.3, -0.2, -1.0],
        snap: Snap::Exact,
    }]);
    let model = SolidModel::new(&p).unwrap();
    let s = model.solve(&p.load_cases).unwrap();
    for sol in &s {
        let f = sol.applied_force_n();
        let mut sum = [0.0; 3];
        for r in sol.reactions() {
            for (s, f) in sum.iter_mut().zip(r.force_n) {
                *s += f;
            }
        }
        let scale = f.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for d in 0..3 {
            assert!((sum[d] + f[d]).abs() < 1e-9 * scale, "{sum:?} vs {f:?}");
        }
    }
    assert!(rel(s[0].applied_force_n()[2], -1.0) < 1e-12);
    let grid = s[0].grid();
    let [nxl, nyl, nzl] = grid.lattice();
    let umax = s[0]
        .displacements_m()
        .iter()
        .map(|v| v.abs())
        .fold(0.0, f64::max);
    let mut worst_mirror: f64 = 0.0;
    let mut worst_linear: f64 = 0.0;
    for k in 0..nzl {
        for j in 0..nyl {
            for i in 0..nxl {
                let u = s[0].node_displacement_m(grid.node([i, j, k]));
                let ux = s[0].node_displacement_m(grid.node([nxl - 1 - i, j, k]));
                let uy = s[0].node_displacement_m(grid.node([i, nyl - 1 - j, k]));
                // x mirror: u_x flips, u_y and u_z stay; y mirror likewise.
                let dx = [u[0] + ux[0], u[1] - ux[1], u[2] - ux[2]];
                let dy = [u[0] - uy[0], u[1] + uy[1], u[2] - uy[2]];
                for v in dx.iter().chain(&dy) {
                    worst_mirror = worst_mirror.max(v.abs() / umax);
                }
                let u2 = s[1].node_displacement_m(grid.node([i, j, k]));
                for d in 0..3 {
                    worst_linear = worst_linear.max((u2[d] - 2.0 * u[d]).abs() / umax);
                }
            }
        }
    }
    assert!(worst_mirror < 1e-9, "mirror {worst_mirror:e}");
    assert!(worst_linear < 1e-12, "linearity {worst_linear:e}");
    // The largest principal stress under the patch is tension on the bottom face.
    let under = grid.elements_in_box([4500.0, 4500.0, 0.0], [5500.0, 5500.0, T_UM]);
    let peak = s[0].max_principal_stress(under).unwrap();
    assert!(
        peak.stress_pa > 0.0 && peak.position_um[2] < 50.0,
        "{peak:?}"
    );
    // Separate solves agree with the multi-column one.
    let one = model.solve(&p.load_cases[2..]).unwrap();
    let (a, b) = (one[0].displacements_m(), s[2].displacements_m());
    let m = b.iter().map(|v| v.abs()).fold(0.0, f64::max);
    assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * m));
}

/// A half model with the symmetry plane x = 5 mm gives the full model's field on the same lines.
#[test]
fn half_model_equals_full_model() {
    let mut full = si_plate((0.0, SPAN_UM), (0.0, SPAN_UM), 500.0, 1);
    full.load_cases.push(vec![centre_patch(&full, 1.0)]);
    let mut half = si_plate((0.0, 5000.0), (0.0, SPAN_UM), 500.0, 1);
    half.load_cases.push(vec![centre_patch(&half, 1.0)]);
    let (f, h) = (&full.solve().unwrap()[0], &half.solve().unwrap()[0]);
    let umax = f
        .displacements_m()
        .iter()
        .map(|v| v.abs())
        .fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    for (n, p) in h.node_positions_um().iter().enumerate() {
        let uf = f.displacement_m(*p).unwrap();
        let uh = h.node_displacement_m(n);
        for d in 0..3 {
            worst = worst.max((uf[d] - uh[d]).abs() / umax);
        }
    }
    assert!(worst < 1e-9, "{worst:e}");
    let (rf, rh) = (f.reaction_n("x0").unwrap(), h.reaction_n("x0").unwrap());
    assert!(
        (0..3).all(|d| (rf[d] - rh[d]).abs() < 1e-9),
        "{rf:?} {rh:?}"
    );
}

/// A point off the material by less than the grid's tolerance (a drawn face the mesh builder
/// moved onto a nearby line) is read at the nearest point of the material: on a face, on an
/// edge; farther off, or on a grid without a tolerance, it is outside.
#[test]
fn a_point_within_the_grids_tolerance_reads_the_nearest_material() {
    let gradient = [
        [1.0e-4, 2.0e-5, -3.0e-5],
        [5.0e-5, -2.0e-4, 1.0e-5],
        [-4.0e-5, 6.0e-5, 1.5e-4],
    ];
    let u0_m = [1e-7, -2e-7, 3e-7];
    let exact = linear_field_m(u0_m, gradient);
    let solve = |tolerance_um: f64| {
        let l = [0.0, 1000.0, 2000.0];
        let grid = HexGrid::new(&l, &l, &l)
            .unwrap()
            .with_tolerance_um(tolerance_um);
        let mut p = SolidProblem::new(grid, vec![Elasticity::isotropic(150e9, 0.25)]);
        prescribe_linear_on_faces(&mut p, (0.0, 2000.0), u0_m, gradient);
        p.load_cases.push(vec![]);
        p.solve().unwrap().remove(0)
    };
    let s = solve(1.0);
    let scale = 2000e-6 * 2e-4;
    let close = |u: [f64; 3], at: [f64; 3]| {
        let e = exact(at);
        (0..3).all(|d| (u[d] - e[d]).abs() < 1e-10 * scale)
    };
    // Off a face by 0.5 um: the face's point; off an edge by 0.6 um (0.42 per axis): the edge's.
    for (p, on) in [
        ([2000.5, 700.0, 1100.0], [2000.0, 700.0, 1100.0]),
        ([-0.5, 1300.0, 250.0], [0.0, 1300.0, 250.0]),
        ([2000.42, 2000.42, 1100.0], [2000.0, 2000.0, 1100.0]),
    ] {
        let u = s.displacement_m(p).expect("within the tolerance");
        assert!(close(u, on), "{p:?}: {u:?} against {:?}", exact(on));
    }
    // Inside, as always: the element holding it.
    assert!(close(
        s.displacement_m([700.0, 1300.0, 1100.0]).unwrap(),
        [700.0, 1300.0, 1100.0]
    ));
    // Beyond the tolerance, and without one, outside.
    assert!(s.displacement_m([2001.5, 700.0, 1100.0]).is_none());
    assert!(s.displacement_m([2000.8, 2000.8, 1100.0]).is_none());
    assert!(solve(0.0).displacement_m([2000.5, 700.0, 1100.0]).is_none());
}

fn small_problem() -> SolidProblem {
    let l = uniform_lines(0.0, 100.0, 2);
    let mut p = SolidProblem::new(
        HexGrid::new(&l, &l, &l).unwrap(),
        vec![Elasticity::isotropic(3e9, 0.35)],
    );
    p.constraints
        .push(Constraint::clamp("base", plane(Axis3::Z, 0.0)));
    p.load_cases.push(vec![SolidLoad::Point {
        at_um: [50.0, 50.0, 100.0],
        force_n: [0.0, 0.0, -1e-3],
        snap: Snap::Exact,
    }]);
    p
}

/// Every bad input is a returned error of the right kind, never a panic.
#[test]
fn bad_input_is_an_error() {
    assert!(small_problem().solve().is_ok());
    let err = |p: &SolidProblem| p.solve().unwrap_err();
    // An inverted element from the node map.
    let mut p = small_problem();
    p.grid = p.grid.clone().with_map(Arc::new(|q: [f64; 3]| {
        let mut r = q;
        if q[0] == 25.0 && q[1] == 25.0 && q[2] == 25.0 {
            r[0] = 60.0; // the first element's centre node pushed past its far face
        }
        r
    }));
    assert!(
        matches!(
            err(&p),
            FeError::DegenerateElement {
                i: 0,
                j: 0,
                k: 0,
                ..
            }
        ),
        "{}",
        err(&p)
    );
    // A flat element: every node of the top layer pushed to z = 50.
    let mut p = small_problem();
    p.grid = p
        .grid
        .clone()
        .with_map(Arc::new(|q: [f64; 3]| [q[0], q[1], q[2].min(50.0)]));
    assert!(matches!(err(&p), FeError::DegenerateElement { .. }));
    // Too large: 101^3 lattice nodes are 3.09 million dofs, refused before assembly.
    let l = uniform_lines(0.0, 1000.0, 50);
    let mut p = small_problem();
    p.grid = HexGrid::new(&l, &l, &l).unwrap();
    assert!(matches!(err(&p), FeError::TooLarge { .. }), "{}", err(&p));
    // A material index with no material, an unstable material.
    let mut p = small_problem();
    p.grid.set_material([1, 1, 1], Some(3));
    assert!(matches!(err(&p), FeError::SolidInput { .. }));
    let mut p = small_problem();
    p.materials[0] = Elasticity::isotropic(3e9, 0.6);
    assert!(matches!(err(&p), FeError::SolidInput { .. }));
    // A constraint off the grid; none at all (rigid body); only a symmetry plane.
    let mut p = small_problem();
    p.constraints
        .push(Constraint::clamp("nowhere", plane(Axis3::X, 150.0)));
    assert!(matches!(err(&p), FeError::SolidInput { .. }));
    let mut p = small_problem();
    p.constraints.clear();
    assert!(matches!(err(&p), FeError::SolidInput { .. }));
    let mut p = small_problem();
    p.constraints = vec![Constraint::symmetry("s", Axis3::Z, 0.0)];
    assert!(err(&p).to_string().contains("rigid"), "{}", err(&p));
    // A second, unconstrained part (separated by a void layer).
    let l = uniform_lines(0.0, 100.0, 4);
    let mut p = small_problem();
    p.grid = HexGrid::new(&l, &l, &l).unwrap();
    p.grid.assign(|c| (c[2] < 50.0 || c[2] > 75.0).then_some(0));
    assert!(err(&p).to_string().contains("rigid"), "{}", err(&p));
    // A point load between nodes; a pressure off the grid lines; a NaN force.
    let mut p = small_problem();
    p.load_cases[0] = vec![SolidLoad::Point {
        at_um: [10.0, 50.0, 100.0],
        force_n: [0.0, 0.0, 1.0],
        snap: Snap::Exact,
    }];
    assert!(matches!(err(&p), FeError::SolidInput { .. }));
    p.load_cases[0] = vec![SolidLoad::Point {
        at_um: [10.0, 50.0, 100.0],
        force_n: [0.0, 0.0, f64::NAN],
        snap: Snap::Nearest,
    }];
    assert!(matches!(err(&p), FeError::SolidInput { .. }));
    p.load_cases[0] = vec![SolidLoad::Pressure {
        face: FaceRect {
            axis: Axis3::Z,
            at_um: 100.0,
            outward: Outward::Minus,
            from_um: [0.0, 0.0],
            to_um: [50.0, 50.0],
        },
        pressure_pa: 1e3,
    }];
    assert!(matches!(err(&p), FeError::SolidInput { .. }));
    // The nearest node is fine.
    p.load_cases[0] = vec![SolidLoad::Point {
        at_um: [10.0, 50.0, 100.0],
        force_n: [0.0, 0.0, 1.0],
        snap: Snap::Nearest,
    }];
    assert!(p.solve().is_ok());
}

/// Consistent pressure forces on a slanted (mapped) face: their sum is -p times the face's area
/// vector, here the top z = 100 + 0.2 x over 100 x 100 um (the base stays flat), n dA =
/// (-0.2, 0, 1) dx dy.
#[test]
fn pressure_on_a_mapped_face_sums_to_p_times_area_vector() {
    let mut p = small_problem();
    p.grid = p.grid.clone().with_map(Arc::new(|q: [f64; 3]| {
        [q[0], q[1], q[2] * (1.0 + 0.002 * q[0])]
    }));
    p.load_cases[0] = vec![SolidLoad::Pressure {
        face: FaceRect {
            axis: Axis3::Z,
            at_um: 100.0,
            outward: Outward::Plus,
            from_um: [0.0, 0.0],
            to_um: [100.0, 100.0],
        },
        pressure_pa: 1e6,
    }];
    let s = &p.solve().unwrap()[0];
    let f = s.applied_force_n();
    let a_m2 = 1e-8;
    let expect = [0.2 * 1e6 * a_m2, 0.0, -1e6 * a_m2];
    assert!(
        (0..3).all(|d| (f[d] - expect[d]).abs() < 1e-12 * 1e-2),
        "{f:?}"
    );
    // And the base carries it.
    let r = s.reaction_n("base").unwrap();
    assert!((0..3).all(|d| (r[d] + f[d]).abs() < 1e-9 * 1e-2), "{r:?}");
    // Every axis and side of a box pushes into the material: x = 100 (outward +x) gives -x,
    // y = 0 (outward -y) gives +y, over half of each face.
    let mut p = small_problem();
    let face = |axis, at_um, outward| FaceRect {
        axis,
        at_um,
        outward,
        from_um: [0.0, 50.0],
        to_um: [100.0, 100.0],
    };
    p.load_cases[0] = vec![
        SolidLoad::Pressure {
            face: face(Axis3::X, 100.0, Outward::Plus),
            pressure_pa: 1e6,
        },
        SolidLoad::Pressure {
            face: face(Axis3::Y, 0.0, Outward::Minus),
            pressure_pa: 2e6,
        },
    ];
    let f = p.solve().unwrap()[0].applied_force_n();
    let expect = [-1e6 * 0.5e-8, 2e6 * 0.5e-8, 0.0];
    assert!((0..3).all(|d| (f[d] - expect[d]).abs() < 1e-14), "{f:?}");
}

/// New materials on the same factorised pattern: twice the stiffness, half the displacement.
#[test]
fn refactor_materials_scales_the_field() {
    let p = small_problem();
    let mut m = SolidModel::new(&p).unwrap();
    let u1 = m.solve(&p.load_cases).unwrap()[0]
        .displacements_m()
        .to_vec();
    m.refactor_materials(&[Elasticity::isotropic(6e9, 0.35)])
        .unwrap();
    let u2 = m.solve(&p.load_cases).unwrap()[0]
        .displacements_m()
        .to_vec();
    let umax = u1.iter().map(|v| v.abs()).fold(0.0, f64::max);
    assert!(u1
        .iter()
        .zip(&u2)
        .all(|(a, b)| (a - 2.0 * b).abs() < 1e-10 * umax));
    assert!(m
        .refactor_materials(&[Elasticity::isotropic(6e9, 0.7)])
        .is_err());
}

#[test]
fn graded_lines_too_fine_for_any_grid_stop_before_allocating_them() {
    // 1 mm in 1e-9 um steps would be 1e12 lines (8 TB); growth 1 from 1 nm, a million.
    let max = grid::MAX_LATTICE_NODES / 18 + 4;
    let reversed = |mut v: Vec<f64>| {
        v.reverse();
        v
    };
    for lines in [
        graded_lines(0.0, 1000.0, 1e-9, 1.5, 1e-9),
        reversed(graded_lines(1000.0, 0.0, 1e-3, 1.0, 100.0)),
    ] {
        assert!(lines.len() <= max, "{}", lines.len());
        let e = HexGrid::new(&lines, &[0.0, 1.0], &[0.0, 1.0]).unwrap_err();
        assert!(matches!(e, FeError::TooLarge { .. }), "{e}");
    }
    // Sizes a grid can take are untouched: from h0 by the growth to h_max, ending at `to`.
    let l = graded_lines(0.0, 100.0, 1.0, 2.0, 10.0);
    assert_eq!(&l[..5], &[0.0, 1.0, 3.0, 7.0, 15.0]);
    assert_eq!(*l.last().unwrap(), 100.0);
}

/// The model without the refinement step (the vertex submodels', `SolidModel::without_refinement`)
/// still passes the patch test through `solve_prescribed`, and on a drive its elements cannot
/// reproduce (quadratic) gives the refined model's field to the direct solve's residual.
#[test]
fn the_unrefined_driven_solve_keeps_the_patch_test_and_the_refined_field() {
    let c = Elasticity::cubic(165.7e9, 63.9e9, 79.6e9).rotated_about_z(30.0);
    let mut p = SolidProblem::new(distorted_block(), vec![c]);
    for axis in [Axis3::X, Axis3::Y, Axis3::Z] {
        for at_um in [0.0, 2000.0] {
            p.constraints
                .push(Constraint::clamp("driven", plane(axis, at_um)));
        }
    }
    let refined = SolidModel::new(&p).unwrap();
    let plain = SolidModel::new(&p).unwrap().without_refinement();
    let gradient = [
        [1.0e-4, 2.0e-5, -3.0e-5],
        [5.0e-5, -2.0e-4, 1.0e-5],
        [-4.0e-5, 6.0e-5, 1.5e-4],
    ];
    let exact = linear_field_m([1e-7, -2e-7, 3e-7], gradient);
    let s = plain.solve_prescribed(|x| Ok(exact(x))).unwrap();
    let scale = 2000e-6 * 2e-4;
    for (n, x) in s.node_positions_um().iter().enumerate() {
        let (u, e) = (s.node_displacement_m(n), exact(*x));
        for d in 0..3 {
            assert!(
                (u[d] - e[d]).abs() < 1e-10 * scale,
                "node {n}: {u:?} against {e:?}"
            );
        }
    }
    let bend = |x: [f64; 3]| -> FeResult<[f64; 3]> {
        let (a, b) = (x[0] * 1e-3, x[1] * 1e-3);
        Ok([1e-7 * a * b, -2e-7 * a * a, 3e-7 * (a * a - b * b)])
    };
    let (u1, u2) = (
        refined.solve_prescribed(bend).unwrap(),
        plain.solve_prescribed(bend).unwrap(),
    );
    let (u1, u2) = (u1.displacements_m(), u2.displacements_m());
    let umax = u1.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let worst = u1
        .iter()
        .zip(u2)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(umax > 1e-7 && worst < 1e-10 * umax, "{worst:e} of {umax:e}");
}
