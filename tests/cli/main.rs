//! The one integration-test binary: the real `tactfab` binary driven through a small harness,
//! plus property tests of the library.

mod analyses;
mod bad_input;
mod build;
mod etch_sim;
mod harness;
mod kill;
mod masks;
mod modes;
mod options;
mod output_files;
mod peer;
mod pipe;
mod process_cli;
mod properties;
mod readme;
mod readout;
mod sensor;
mod slab3d;
mod softsweep;
mod solid;
mod solid_export;
