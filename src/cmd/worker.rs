//! The hidden worker subcommand the runner starts (`harness::isolate`); its flags on the
//! parent's side are `args::isolate`.

use crate::registry::Registry;

/// The worker subcommand: serves the parent over `registry`, then exits. The parent starts this
/// same executable, whose `main_with` passes the registry the parent runs with.
pub fn serve(registry: Registry) -> ! {
    harness::isolate::worker::serve(registry)
}
