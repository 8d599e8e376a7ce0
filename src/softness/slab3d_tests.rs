//! Tests of the 3-D slab against closed forms, the axisymmetric scene and its own invariants.

use super::*;
use crate::softness::axislab;

fn lump() -> Feature {
    Feature::Lump {
        e_pa: 200e3,
        nu: 0.4,
    }
}

/// Paper 002's slab (30 mm along, 10 mm thick, 20 kPa, nu 0.49, 10 %) 15 mm across, its sphere
/// (2 mm, 4 mm up) at (x, y).
fn slab(feature: Feature, x_m: f64, y_m: f64) -> Slab3d {
    let mut s = Slab3d::from_slab(&Slab::paper_002(feature), 15e-3, y_m);
    s.centre_m[0] = x_m;
    s
}

#[test]
fn without_poisson_the_squeeze_is_uniform() {
    // nu = 0: the bonded block is in uniform uniaxial strain whatever its free sides, P0 = E
    // delta / H at every face node, corners included; equilibrium face = jaw.
    let s = Slab3d {
        tissue_nu: 0.0,
        ..slab(Feature::None, 15e-3, 7.5e-3)
    };
    let f = face_field(&s, &Mesh3d::DEFAULT).unwrap();
    let want = s.tissue_e_pa * s.compression;
    let worst = f
        .p0_pa
        .iter()
        .map(|v| (v / want - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "nu 0: worst |P0 / (E delta / H) - 1| = {worst:.2e} over {} nodes, {:?} bricks",
        f.p0_pa.len(),
        f.elements
    );
    assert!(worst < 1e-10, "{worst}");
    let total = want * s.length_m * s.width_m;
    assert!((f.face_force_n / total - 1.0).abs() < 1e-10);
    assert!((f.jaw_force_n / total - 1.0).abs() < 1e-10);
}

#[test]
fn a_nearly_incompressible_strip_squeezes_out_parabolically_in_its_middle() {
    // Gent & Lindley (Proc. IMechE 173, 1959): a bonded incompressible layer, long in y, of
    // half-length a along x and thickness H shortened by delta: in plane strain p = 6 G delta
    // (a^2 - x^2) / H^3 (lubrication: int_0^H u dz = -(H^3 / (12 G)) dp/dx carries the squeezed
    // volume x delta). The strip's middle section (y = W / 2, 20 H from its free ends) at nu =
    // 0.4999, a = 5 H: within 5 % at x = a (the centre); a locked mesh would be thousands of
    // times stiffer.
    let h = 10e-3;
    let s = Slab3d {
        length_m: 10.0 * h,
        width_m: 40.0 * h,
        thickness_m: h,
        tissue_nu: 0.4999,
        ..slab(Feature::None, 0.0, 0.0)
    };
    let f = face_field(
        &s,
        &Mesh3d {
            near_m: 5e-3,
            far_m: 5e-3,
        },
    )
    .unwrap();
    let g = s.tissue_e_pa / (2.0 * (1.0 + s.tissue_nu));
    let a = 0.5 * s.length_m;
    let delta = s.compression * h;
    let mid = f.p0_at_pa(a, 0.5 * s.width_m);
    let want = 6.0 * g * delta * a * a / h.powi(3);
    let e = mid / want - 1.0;
    // And half-way out, (a^2 - x^2) = 3/4 a^2.
    let half = f.p0_at_pa(1.5 * a, 0.5 * s.width_m) / (0.75 * want) - 1.0;
    eprintln!(
        "Gent-Lindley strip at nu 0.4999 ({:?} bricks): centre {mid:.4e} Pa against {want:.4e}: \
         {e:+.3e}; x = a / 2: {half:+.3e}",
        f.elements
    );
    assert!(e.abs() < 0.05, "{e}");
    assert!(half.abs() < 0.05, "{half}");
}

#[test]
fn equilibrium_linearity_and_the_mirror_planes() {
    // A lump at the centre (quarter block) against the same lump moved 1e-7 m along the jaw
    // (no mirror in x: the half block): the same field within the shift's effect; the face's
    // force equals the jaw's; twice the squeeze, twice the pressure.
    let m = Mesh3d {
        near_m: 1e-3,
        far_m: 2.5e-3,
    };
    let q = face_field(&slab(lump(), 15e-3, 7.5e-3), &m).unwrap();
    let h = face_field(&slab(lump(), 15e-3 + 1e-7, 7.5e-3), &m).unwrap();
    assert_eq!(q.mirrored, [true, true]);
    assert_eq!(h.mirrored, [false, true]);
    let mut worst: f64 = 0.0;
    for (j, &y) in q.y_m.iter().enumerate() {
        for (i, &x) in q.x_m.iter().enumerate() {
            let v = q.p_pa[j * q.x_m.len() + i];
            worst = worst.max((h.p_at_pa(x, y) / v - 1.0).abs());
        }
    }
    eprintln!(
        "quarter {:?} vs half {:?} bricks: worst |P_half / P_quarter - 1| {worst:.2e}; peak {:.5} \
         vs {:.5}; face {:.6e} N, jaw {:.6e} N",
        q.elements, h.elements, q.peak_ratio, h.peak_ratio, q.face_force_n, q.jaw_force_n
    );
    assert!(worst < 1e-3, "{worst}");
    assert!((q.peak_ratio - h.peak_ratio).abs() < 1e-3);
    for f in [&q, &h] {
        assert!((f.face_force_n / f.jaw_force_n - 1.0).abs() < 1e-9);
    }
    let s2 = Slab3d {
        compression: 0.2,
        ..slab(lump(), 15e-3, 7.5e-3)
    };
    let d = face_field(&s2, &m).unwrap();
    let lin = d
        .p_pa
        .iter()
        .zip(&q.p_pa)
        .map(|(a, b)| (a / (2.0 * b) - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(lin < 1e-9, "{lin}");
}

#[test]
fn an_off_axis_sphere_mirrors_across_the_jaw() {
    // A lump 3 mm from one free edge and 3 mm from the other: mirror-image fields (the full
    // block across the jaw, meshed independently each time).
    let m = Mesh3d {
        near_m: 1e-3,
        far_m: 2.5e-3,
    };
    let a = face_field(&slab(lump(), 15e-3, 4.5e-3), &m).unwrap();
    let b = face_field(&slab(lump(), 15e-3, 10.5e-3), &m).unwrap();
    let w = 15e-3;
    let mut worst: f64 = 0.0;
    for (j, &y) in a.y_m.iter().enumerate() {
        for (i, &x) in a.x_m.iter().enumerate() {
            let v = a.p_pa[j * a.x_m.len() + i];
            worst = worst.max((b.p_at_pa(x, w - y) / v - 1.0).abs());
        }
    }
    eprintln!(
        "lump at y = 4.5 and 10.5 mm: worst mirror mismatch {worst:.2e}; peak {:.4} at {:?}",
        a.peak_ratio, a.peak_at_m
    );
    assert!(worst < 1e-9, "{worst}");
    // The lump raises the pressure over itself, not at the far edge.
    assert!(a.peak_ratio > 1.2 && (a.peak_at_m[1] - 4.5e-3).abs() < 1.5e-3);
}

#[test]
fn bad_input_is_an_error() {
    let m = Mesh3d::DEFAULT;
    for s in [
        slab(lump(), 15e-3, 1e-3),  // through the side
        slab(lump(), 1e-3, 7.5e-3), // through the end
        Slab3d {
            radius_m: f64::NAN,
            ..slab(lump(), 15e-3, 7.5e-3)
        },
        Slab3d {
            tissue_nu: 0.5,
            ..slab(lump(), 15e-3, 7.5e-3)
        },
        Slab3d {
            width_m: -1.0,
            ..slab(Feature::None, 15e-3, 7.5e-3)
        },
        Slab3d {
            compression: f64::INFINITY,
            ..slab(Feature::None, 15e-3, 7.5e-3)
        },
    ] {
        assert!(face_field(&s, &m).is_err(), "{s:?}");
    }
    for mesh in [
        Mesh3d {
            near_m: 0.0,
            far_m: 1e-3,
        },
        Mesh3d {
            near_m: 2e-3,
            far_m: 1e-3,
        },
        Mesh3d {
            near_m: 1e-5,
            far_m: 1e-5,
        },
        Mesh3d {
            near_m: 1e-6,
            far_m: 2.5e-3,
        },
    ] {
        let e = face_field(&slab(lump(), 15e-3, 7.5e-3), &mesh);
        assert!(matches!(e, Err(SoftnessError::BadInput { .. })), "{mesh:?}");
    }
}

#[test]
fn a_wide_box_agrees_with_the_axisymmetric_cylinder_near_the_axis() {
    // Far from its sides the box's background is the cylinder's when both are wide against
    // their thickness and the tissue is compressible enough for the middle to be in uniaxial
    // strain (nu 0.3, half-widths 3 H: at nu 0.49 the background itself is a squeeze-flow
    // parabola set by the width, and a square box is no cylinder). The centred lump in a 60 x 60
    // mm box against the axisymmetric cylinder of radius 30 mm: d = P / P0 - 1 at r = 0 (the
    // peak) to 4 mm. The axisymmetric side is the reference: its mesh is fitted to the sphere
    // and converged (its peak to ~1e-3, `sphere_convergence`). The box cuts its bricks with the
    // sphere and mixes their stiffness by volume share, which reads the disturbance high at
    // 0.67 mm bricks: measured 0.111 at the peak, 0.103 at 1 mm, 0.064 at 2 mm, 0.023 and 0.005
    // beyond (the box's peak still falls with refinement, 1.918 to 1.822 from 1 to 0.4 mm
    // bricks in `the_peak_converges...`). Tolerance: that bias with a margin, 0.13 at r <= 1
    // mm and 0.08 beyond; the box must also read high (the bias's sign), never low.
    let wide = |s: Slab| Slab {
        width_m: 60e-3,
        tissue_nu: 0.3,
        ..s
    };
    let mut s = Slab3d::from_slab(&wide(Slab::paper_002(lump())), 60e-3, 30e-3);
    s.centre_m[0] = 30e-3;
    let f = face_field(
        &s,
        &Mesh3d {
            near_m: 2e-3 / 3.0,
            far_m: 5e-3,
        },
    )
    .unwrap();
    let axi = axislab::sphere_profile(&wide(Slab::paper_002(lump())), 45, 15).unwrap();
    let mut lines = Vec::new();
    let mut worst: f64 = 0.0;
    for r_mm in [0.0, 1.0, 2.0, 3.0, 4.0] {
        let r = r_mm * 1e-3;
        let d3 = f.p_at_pa(30e-3 + r, 30e-3) / f.p0_at_pa(30e-3 + r, 30e-3) - 1.0;
        let k = axi.r_m.iter().position(|&v| (v - r).abs() < 1e-9).unwrap();
        let da = axi.p_pa[k] / axi.p0_pa[k] - 1.0;
        let tol = if r_mm <= 1.0 { 0.13 } else { 0.08 };
        assert!(
            d3 >= da - 0.01,
            "r {r_mm} mm: the box reads low: {d3} < {da}"
        );
        worst = worst.max((d3 - da).abs() / tol);
        lines.push(format!("r {r_mm} mm: d 3-D {d3:+.4}, axisym {da:+.4}"));
    }
    assert!(
        (f.p0_at_pa(30e-3, 30e-3) / axi.p0_pa[0] - 1.0).abs() < 0.01,
        "the backgrounds differ"
    );
    eprintln!(
        "box {:?} bricks, {} unknowns: peak {:.4}; axisym peak {:.4}; P0 middle {:.5e} vs {:.5e}\n{}",
        f.elements,
        f.unknowns,
        f.peak_ratio,
        axi.peak_ratio,
        f.p0_at_pa(30e-3, 30e-3),
        axi.p0_pa[0],
        lines.join("\n")
    );
    assert!(worst < 1.0, "{worst} of the tolerance");
}

#[test]
fn the_peak_converges_and_does_not_lock() {
    // The centred lump on the jaw-wide block (15 mm across) on three meshes: the peak P / P0
    // and the lump's extra force int (P - P0) dA.
    let mut peaks = Vec::new();
    let mut extra = Vec::new();
    for near in [1e-3, 2e-3 / 3.0, 0.5e-3] {
        let m = Mesh3d {
            near_m: near,
            far_m: 2.5e-3,
        };
        let f = face_field(&slab(lump(), 15e-3, 7.5e-3), &m).unwrap();
        peaks.push(f.peak_ratio);
        // Trapezoid over the face nodes (the field is smooth on this scale).
        let (nx, ny) = (f.x_m.len(), f.y_m.len());
        let mut sum = 0.0;
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let a = (f.x_m[i + 1] - f.x_m[i]) * (f.y_m[j + 1] - f.y_m[j]);
                let d = |i: usize, j: usize| f.p_pa[j * nx + i] - f.p0_pa[j * nx + i];
                sum += 0.25 * a * (d(i, j) + d(i + 1, j) + d(i, j + 1) + d(i + 1, j + 1));
            }
        }
        extra.push(sum);
    }
    eprintln!("peaks on near 1, 0.67, 0.5 mm: {peaks:?}; extra force (N): {extra:?}");
    assert!(peaks[2] < peaks[1] && peaks[1] < peaks[0], "{peaks:?}");
    assert!(peaks.iter().all(|&p| p > 1.5 && p < 2.1), "{peaks:?}");
    // Measured 0.0479, 0.0415, 0.0393 N: the differences shrink (the peak, a point value of a
    // field whose mixed elements follow the sphere's surface by volume share, converges less
    // regularly: 1.918, 1.984, 1.894, 1.840, 1.822 on 1, 0.8, 0.67, 0.5, 0.4 mm, release
    // example).
    assert!(
        (extra[2] - extra[1]).abs() < (extra[1] - extra[0]).abs() && extra[2] > 0.0,
        "{extra:?}"
    );
    // nu 0.4999: no locking (a locked mesh reads the lump as no stiffer than the tissue,
    // P / P0 -> 1).
    let s = Slab3d {
        tissue_nu: 0.4999,
        ..slab(lump(), 15e-3, 7.5e-3)
    };
    let f = face_field(&s, &Mesh3d::DEFAULT).unwrap();
    eprintln!("nu 0.4999: peak {:.4}", f.peak_ratio);
    assert!(
        (f.peak_ratio / peaks[1] - 1.0).abs() < 0.1,
        "{}",
        f.peak_ratio
    );
}
