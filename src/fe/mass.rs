//! The plate's consistent mass: an areal mass per element (rho t of the silicon, teeth through
//! their thickness regions, plus any layer that moves with the plate but adds no stiffness),
//! stored like the element stiffness so it assembles and multiplies on the same pattern.

use serde::Serialize;

use crate::fe::assemble::ElementStiffness;
use crate::fe::bfs;
use crate::fe::error::{FeError, FeResult};
use crate::fe::mesh::RectMesh;

/// What the plate weighs per unit area: `density_kg_per_m3` times each element's thickness, plus
/// `added_kg_per_m2` everywhere (a bonded film whose stiffness the plate model leaves out).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MassModel {
    pub density_kg_per_m3: f64,
    pub added_kg_per_m2: f64,
}

impl MassModel {
    /// A bare plate of density `density_kg_per_m3`.
    pub fn plate(density_kg_per_m3: f64) -> Self {
        MassModel {
            density_kg_per_m3,
            added_kg_per_m2: 0.0,
        }
    }

    /// Areal mass (kg/m^2) of an element `thickness_um` thick: rho t + the added layer.
    pub fn areal_kg_per_m2(&self, thickness_um: f64) -> f64 {
        self.density_kg_per_m3 * thickness_um * 1e-6 + self.added_kg_per_m2
    }
}

/// The consistent mass matrix of every element ([`bfs::mass`]), shared between elements of
/// equal size and areal mass, in the crate's element-matrix store ([`ElementStiffness`] holds
/// any 16 x 16 element matrices; these are masses). A non-positive or non-finite areal mass is
/// an error naming the element.
pub fn element_mass(
    mesh: &RectMesh,
    thickness_um: &[f64],
    model: MassModel,
) -> FeResult<ElementStiffness> {
    let mut cache = std::collections::HashMap::new();
    let mut matrices = Vec::new();
    let mut kind = Vec::with_capacity(thickness_um.len());
    for (e, &t) in thickness_um.iter().enumerate() {
        let m = model.areal_kg_per_m2(t);
        if !(m > 0.0 && m.is_finite() && model.added_kg_per_m2 >= 0.0) {
            return Err(FeError::InvalidMass {
                element: e,
                hint: "the density and thickness must be positive and any added layer's areal \
                       mass non-negative",
            });
        }
        let (x0, y0, x1, y1) = mesh.element_bounds_um(e);
        let (a, b) = ((x1 - x0) * 1e-6, (y1 - y0) * 1e-6);
        let key = [a.to_bits(), b.to_bits(), m.to_bits()];
        let id = *cache.entry(key).or_insert_with(|| {
            matrices.push(Box::new(bfs::mass(a, b, m)));
            (matrices.len() - 1) as u32
        });
        kind.push(id);
    }
    Ok(ElementStiffness { kind, matrices })
}
