//! Integration tests of the `tactfab` binary (one test binary, one module per subcommand).

mod harness;
mod masks;
