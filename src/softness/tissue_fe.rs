//! FE softness model: the tissue as plane-strain Q2/P1 (B-bar) continuum on top of the Si plate as
//! an Euler-Bernoulli frame (axial + Hermite bending, per unit length), clamped at both supports.
//!
//! Coupling (perfect bond, as the composite beam): a tissue node on the plate's top face moves with
//! the plate's top fibre, u = u0 - (t_b / 2) theta, v = w (y up, theta = dw/dx). The stiffness is
//! K(E_t) = E_t K_tissue(E = 1, nu) + K_plate on one sparsity pattern: the symbolic Cholesky is
//! done once and every E_t costs one numeric factorisation. Read-out: plate bottom-fibre strain
//! eps = u0' + (t_b / 2) w'', so int eps dx over the electrode = \[u0\] + (t_b / 2) [w'] (exact in
//! the FE space).

use serde::Serialize;

use crate::softness::continuum::{
    lame, lame_combined, Assembler, DofExpr, ElementCache, Order, QuadMesh, ScaledSystem,
    Volumetric,
};
use crate::softness::{SoftnessError, SoftnessSetup};

/// Mesh of the tissue block: Q2 elements across the span and through the thickness.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct TissueMesh {
    pub across: usize,
    pub through: usize,
    pub volumetric: Volumetric,
}

impl TissueMesh {
    /// Default: 40 x 12 Q2/P1 elements (error estimate in `tactfab softness`, three nested meshes).
    pub fn standard() -> Self {
        TissueMesh {
            across: 40,
            through: 12,
            volumetric: Volumetric::Bbar,
        }
    }
    pub fn refined(&self, r: usize) -> Self {
        TissueMesh {
            across: self.across * r,
            through: self.through * r,
            ..*self
        }
    }
}

/// How the tissue block's end faces (over the supports' inner edges) are held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum TissueEnds {
    /// Free: the tissue rests on (is bonded to) the plate only; the plate alone is clamped.
    Free,
    /// Clamped: the whole composite section is built in at the supports, as the composite beam
    /// assumes.
    Clamped,
}

/// The assembled model of one setup and mesh, reusable for any E_t.
pub struct TissueModel {
    setup: SoftnessSetup,
    system: ScaledSystem,
    /// Plate node x positions and their (u0, w, theta) expressions.
    plate_x: Vec<f64>,
    plate_dofs: Vec<[DofExpr; 3]>,
    pub n_unknowns: usize,
}

fn frame_element(ea: f64, ei: f64, h: f64) -> Vec<f64> {
    // Local dofs (u1, w1, t1, u2, w2, t2).
    let mut k = vec![0.0; 36];
    let a = ea / h;
    k[0] = a;
    k[3] = -a;
    k[18] = -a;
    k[21] = a;
    let b = ei / h.powi(3);
    let kb = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
    ];
    let idx = [1, 2, 4, 5];
    for i in 0..4 {
        for j in 0..4 {
            k[idx[i] * 6 + idx[j]] = b * kb[i][j];
        }
    }
    k
}

impl TissueModel {
    /// Assemble tissue (per unit E), plate and a 1 N load (pressure on the tissue top); free tissue
    /// ends.
    pub fn new(setup: &SoftnessSetup, mesh: TissueMesh) -> Result<Self, SoftnessError> {
        Self::with_ends(setup, mesh, TissueEnds::Free)
    }

    /// As [`TissueModel::new`] with a choice of how the tissue's end faces are held.
    pub fn with_ends(
        setup: &SoftnessSetup,
        mesh: TissueMesh,
        ends: TissueEnds,
    ) -> Result<Self, SoftnessError> {
        let s = setup;
        let (l, tt, tb) = (s.span_m, s.tissue_thickness_m, s.plate_thickness_m);
        let qm = QuadMesh {
            order: Order::Q2,
            x_m: (0..=mesh.across)
                .map(|i| l * i as f64 / mesh.across as f64)
                .collect(),
            y_m: (0..=mesh.through)
                .map(|j| tt * j as f64 / mesh.through as f64)
                .collect(),
        };
        let (nxs, nys) = (qm.node_x(), qm.node_y());
        let mut n = 0;
        let mut next = || {
            n += 1;
            n - 1
        };
        let plate_dofs: Vec<[DofExpr; 3]> = (0..nxs.len())
            .map(|k| {
                if k == 0 || k == nxs.len() - 1 {
                    [
                        DofExpr::fixed(0.0),
                        DofExpr::fixed(0.0),
                        DofExpr::fixed(0.0),
                    ]
                } else {
                    [
                        DofExpr::free(next()),
                        DofExpr::free(next()),
                        DofExpr::free(next()),
                    ]
                }
            })
            .collect();
        let mut node_dofs: Vec<[DofExpr; 2]> = Vec::with_capacity(qm.n_nodes());
        for j in 0..nys.len() {
            for (i, pd) in plate_dofs.iter().enumerate() {
                let end = i == 0 || i == nxs.len() - 1;
                if j == 0 {
                    let mut u = pd[0].clone();
                    for &(g, c) in &pd[2].terms {
                        u.terms.push((g, -0.5 * tb * c));
                    }
                    node_dofs.push([u, pd[1].clone()]);
                } else if end && ends == TissueEnds::Clamped {
                    node_dofs.push([DofExpr::fixed(0.0), DofExpr::fixed(0.0)]);
                } else {
                    node_dofs.push([DofExpr::free(next()), DofExpr::free(next())]);
                }
            }
        }
        let mut asm = Assembler::new(n, 2);
        let (lam, mu) = lame(1.0, s.tissue_nu);
        let mut cache = ElementCache::new(Order::Q2, mesh.volumetric);
        for ey in 0..mesh.through {
            for ex in 0..mesh.across {
                let (kmu, klam) =
                    cache.get(qm.x_m[ex + 1] - qm.x_m[ex], qm.y_m[ey + 1] - qm.y_m[ey]);
                let k = lame_combined(kmu, klam, mu, lam);
                let nodes = qm.element_nodes(ex, ey);
                let map: Vec<&DofExpr> = nodes
                    .iter()
                    .flat_map(|&nd| [&node_dofs[nd][0], &node_dofs[nd][1]])
                    .collect();
                asm.add(0, &k, &map);
            }
        }
        let (ea, ei) = (
            s.plate_modulus_pa * tb,
            s.plate_modulus_pa * tb.powi(3) / 12.0,
        );
        for k in 0..nxs.len() - 1 {
            let ke = frame_element(ea, ei, nxs[k + 1] - nxs[k]);
            let map: Vec<&DofExpr> = plate_dofs[k]
                .iter()
                .chain(plate_dofs[k + 1].iter())
                .collect();
            asm.add(1, &ke, &map);
        }
        // 1 N over span x length: pressure p downward on the top edge, Q2 edge weights h (1, 4, 1)
        // / 6.
        let p = s.pressure_pa(1.0);
        let jt = nys.len() - 1;
        for ex in 0..mesh.across {
            let h = qm.x_m[ex + 1] - qm.x_m[ex];
            for (a, w) in [(0, 1.0), (1, 4.0), (2, 1.0)] {
                asm.force(&node_dofs[qm.node(2 * ex + a, jt)][1], -p * h * w / 6.0);
            }
        }
        let n_unknowns = asm.n;
        Ok(TissueModel {
            setup: s.clone(),
            system: asm.finish()?,
            plate_x: nxs,
            plate_dofs,
            n_unknowns,
        })
    }

    fn value(e: &DofExpr, u: &[f64]) -> f64 {
        e.constant + e.terms.iter().map(|&(g, c)| c * u[g]).sum::<f64>()
    }

    /// (u0, w') of the plate at x from the solution (linear u0, Hermite w per frame element).
    fn plate_at(&self, u: &[f64], x: f64) -> (f64, f64, f64) {
        let xs = &self.plate_x;
        let k = xs
            .partition_point(|&v| v <= x)
            .saturating_sub(1)
            .min(xs.len() - 2);
        let h = xs[k + 1] - xs[k];
        let t = ((x - xs[k]) / h).clamp(0.0, 1.0);
        let [u1, w1, r1] = &self.plate_dofs[k];
        let [u2, w2, r2] = &self.plate_dofs[k + 1];
        let (u1, w1, r1, u2, w2, r2) = (
            Self::value(u1, u),
            Self::value(w1, u),
            Self::value(r1, u),
            Self::value(u2, u),
            Self::value(w2, u),
            Self::value(r2, u),
        );
        let u0 = u1 + t * (u2 - u1);
        let dw = (6.0 * t * t - 6.0 * t) * (w1 - w2) / h
            + (3.0 * t * t - 4.0 * t + 1.0) * r1
            + (3.0 * t * t - 2.0 * t) * r2;
        let w = (2.0 * t.powi(3) - 3.0 * t * t + 1.0) * w1
            + (t.powi(3) - 2.0 * t * t + t) * h * r1
            + (-2.0 * t.powi(3) + 3.0 * t * t) * w2
            + (t.powi(3) - t * t) * h * r2;
        (u0, dw, w)
    }

    /// Plate response for tissue modulus E_t (Pa) and force F (N): (int eps dx over the electrode
    /// (m), mid-span deflection along the load (m)). Linear in F.
    pub fn response(&self, tissue_e_pa: f64, force_n: f64) -> Result<(f64, f64), SoftnessError> {
        if !(tissue_e_pa > 0.0 && tissue_e_pa.is_finite()) {
            return Err(SoftnessError::BadInput {
                field: "tissue_e_pa",
                value: tissue_e_pa,
                hint: "a positive modulus in Pa",
            });
        }
        let u = self.system.solve(&[tissue_e_pa, 1.0])?;
        let tb = self.setup.plate_thickness_m;
        let (ua, da, _) = self.plate_at(&u, self.setup.electrode_s0_m);
        let (ub, db, _) = self.plate_at(&u, self.setup.electrode_s1_m);
        let (_, _, wmid) = self.plate_at(&u, 0.5 * self.setup.span_m);
        Ok((
            force_n * ((ub - ua) + 0.5 * tb * (db - da)),
            -force_n * wmid,
        ))
    }

    /// Middle-electrode voltage (V).
    pub fn voltage_v(&self, tissue_e_pa: f64, force_n: f64) -> Result<f64, SoftnessError> {
        Ok(self.setup.volts_per_strain_m * self.response(tissue_e_pa, force_n)?.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::softness::composite_beam::CompositeBeam;

    pub(crate) fn setup() -> SoftnessSetup {
        SoftnessSetup {
            span_m: 0.01,
            loaded_length_m: 0.03,
            plate_thickness_m: 100e-6,
            plate_modulus_pa: 169.76e9,
            tissue_thickness_m: 5e-3,
            tissue_nu: 0.49,
            electrode_s0_m: 0.0025,
            electrode_s1_m: 0.0075,
            volts_per_strain_m: 1.0,
            electrode_name: "M2".into(),
        }
    }

    /// A vanishing tissue leaves the bare clamped plate under the pressure: w_mid = q l^4 / (384
    /// D), int eps = (t_b / 2) [w'] with w' = q x (l - x)(l - 2x) / (12 D) (composite beam with
    /// E_t -> 0). With nu = 0 the pressure passes the tissue as uniaxial stress (no shear on
    /// the plate), so the limit is exact; with nu = 0.49 the bonded base restrains the tissue's
    /// lateral bulging, which shears the plate's top face even as E_t -> 0 (reported by
    /// `tactfab softness`).
    #[test]
    fn soft_limit_is_the_bare_plate() {
        let s = SoftnessSetup {
            tissue_nu: 0.0,
            ..setup()
        };
        let m = TissueModel::new(
            &s,
            TissueMesh {
                across: 20,
                through: 6,
                volumetric: Volumetric::Bbar,
            },
        )
        .unwrap();
        let (strain, w) = m.response(1e-3, 1.0).unwrap();
        let q = s.pressure_pa(1.0);
        let d = 169.76e9 * 1e-12 / 12.0;
        assert!((w / (q * 1e-8 / (384.0 * d)) - 1.0).abs() < 1e-6, "{w}");
        let cb =
            CompositeBeam::new(&s, 1e-3).strain_integral_m(q, s.electrode_s0_m, s.electrode_s1_m);
        assert!((strain / cb - 1.0).abs() < 1e-6, "{strain} vs {cb}");
        // Linear in F, monotone in E.
        let (s5, _) = m.response(1e-3, 5.0).unwrap();
        assert!((s5 / strain - 5.0).abs() < 1e-9);
        let v: Vec<f64> = [1e4, 1e5, 1e6, 1e7, 1e8]
            .iter()
            .map(|&e| m.response(e, 1.0).unwrap().0)
            .collect();
        assert!(v.windows(2).all(|w| w[1] < w[0]), "{v:?}");
    }

    /// With the whole section clamped and a thin, stiff layer (plane sections hold: depth / span =
    /// 0.01), the FE is the composite beam of Eq. 7-12: the coupling's offsets and moduli are
    /// right.
    #[test]
    fn thin_clamped_layer_is_the_composite_beam() {
        let s = SoftnessSetup {
            tissue_thickness_m: 100e-6,
            tissue_nu: 0.3,
            ..setup()
        };
        let m = TissueModel::with_ends(
            &s,
            TissueMesh {
                across: 80,
                through: 2,
                volumetric: Volumetric::Bbar,
            },
            TissueEnds::Clamped,
        )
        .unwrap();
        let q = s.pressure_pa(1.0);
        for e in [1e9, 50e9] {
            let (strain, w) = m.response(e, 1.0).unwrap();
            let cb = CompositeBeam::new(&s, e);
            let (cs, cw) = (
                cb.strain_integral_m(q, s.electrode_s0_m, s.electrode_s1_m),
                cb.mid_deflection_m(q),
            );
            assert!((w / cw - 1.0).abs() < 5e-3, "E {e}: w {w} vs {cw}");
            assert!(
                (strain / cs - 1.0).abs() < 1e-2,
                "E {e}: strain {strain} vs {cs}"
            );
        }
    }
}
