//! Plots as SVG strings (plotters, SVG backend, no font files needed: text stays `<text>`).
//!
//! One small vocabulary for every chart tactfab draws (convergence, calibration, orientation,
//! softness, design family), so they look alike and stay deterministic: the same data gives the
//! same bytes.

mod check;
mod layout;
mod xy;

pub use check::text_outside_canvas;
pub use layout::side_by_side;
pub use xy::{tick, xy_svg, Axis, Series, Style, XyPlot, PALETTE};
