//! One design, made once: the validated process, the etch plan it implies and the mask set drawn
//! from both. Every later stage (DRC, the sensor model, the report, the studies) reads a
//! [`Design`]; none re-derives teeth or electrodes, so what is simulated is what is drawn.

use std::path::Path;

use crate::etch::EtchPlan;
use crate::layout::{LayoutError, MaskSet};
use crate::process::{LoadError, Loaded, Process};

/// Why no design could be made.
#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    /// The file did not load (every problem, with its place).
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The process is valid but cannot be drawn.
    #[error("layout: {0}")]
    Layout(#[from] LayoutError),
    /// `drc.waive` names a code no rule has: a typo would silently waive nothing.
    #[error("drc.waive: unknown rule code(s) {codes}\n  hint: codes are {known}")]
    UnknownWaivers { codes: String, known: String },
}

/// Process, etch plan and mask set of one process file.
#[derive(Debug, Clone)]
pub struct Design {
    pub process: Process,
    pub plan: EtchPlan,
    pub masks: MaskSet,
}

impl Design {
    /// Plans the etch and draws the masks of a validated process.
    ///
    /// ```
    /// let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    /// let loaded = tactfab::process::load_str(&text, "mis-grasper.yaml", &[]).unwrap();
    /// let design = tactfab::design::Design::new(loaded.process).unwrap();
    /// assert_eq!(design.masks.electrodes.len(), 9);
    /// // The sensor model's teeth are the drawn teeth whose etched base reaches over the channel
    /// // floor (the others stand on the supports).
    /// let [y0, y1] = design.plan.channel_floor_y_um;
    /// let half_base = (design.masks.tooth_top_um + design.plan.steps[0].sidewall_run_out_um) / 2.0;
    /// let over_floor = design.masks.teeth.iter().filter(|t| {
    ///     let cy = t.y_um + design.masks.tooth_top_um / 2.0;
    ///     cy + half_base > y0 && cy - half_base < y1
    /// });
    /// let model = tactfab::sensor::SensorGeometry::new(&design);
    /// assert_eq!(model.teeth.len(), over_floor.count());
    /// ```
    pub fn new(process: Process) -> Result<Self, DesignError> {
        let unknown = crate::drc::unknown_waivers(&process);
        if !unknown.is_empty() {
            return Err(DesignError::UnknownWaivers {
                codes: unknown.join(", "),
                known: crate::finding::DrcCode::ALL
                    .iter()
                    .map(|c| c.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        }
        let plan = crate::etch::plan(&process);
        let masks = crate::layout::build(&process, &plan)?;
        Ok(Design {
            process,
            plan,
            masks,
        })
    }

    /// Loads `file` with `--set` overrides and makes its design; the [`Loaded`] keeps the
    /// defaults used and the overrides for the report.
    pub fn load(file: &Path, overrides: &[String]) -> Result<(Loaded, Self), DesignError> {
        let loaded = crate::process::load(file, overrides)?;
        let design = Design::new(loaded.process.clone())?;
        Ok((loaded, design))
    }
}
