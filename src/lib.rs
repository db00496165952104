//! `scatterbench`: the command line (ARCHITECTURE §8) as a library, over the method registry
//! it is given. `src/main.rs` is `main_with(methods::REGISTRY)`; an out-of-tree crate gets the
//! whole command line for its own methods beside the built-in ones from a binary of the same
//! three lines (examples/external-method/src/main.rs). Every command, the hidden worker the
//! runner starts (this same executable, so it serves the same registry) and the frame-time
//! bench ([`bench`]) use that registry and no other.
//!
//! `src/` parses and checks arguments (`args.rs`, shared arguments declared once), prints
//! progress (`progress.rs`) and calls library code: `harness` (runner, reference, stress,
//! merge), `experiments` (reproduce, scaling), `report`. One module per subcommand in
//! `src/cmd/`.
//!
//! Exit codes (ARCHITECTURE §8.3): 0 success; 1 the work ran and failed (or the registry lists
//! an id twice); 2 bad input refused before any work (clap's usage errors, and [`args::Usage`]).

mod args;
pub mod bench;
mod cmd;
mod progress;
mod registry;

use std::process::ExitCode;

use clap::{Parser, Subcommand};
pub use registry::Registry;

#[derive(Parser)]
#[command(
    name = "scatterbench",
    version,
    about = "Benchmark real-time single scattering with volumetric shadows against a CPU ground truth"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Every GPU adapter wgpu can see (name, backend, driver, type, software or not) with the
    /// features the suite uses; `--adapter NAME` on the rendering commands picks one.
    Adapters(cmd::adapters::AdaptersArgs),
    /// Scenes with their features; methods with their params and support.
    List(cmd::list::ListArgs),
    /// Validate scene files: exit 0, or exit 2 listing every problem.
    Validate(cmd::validate::ValidateArgs),
    /// Write a scene as binary glTF (.glb) for Blender or a glTF viewer; importing it restores
    /// the scene (medium and what glTF can't say travel in extras).
    Export(cmd::export::ExportArgs),
    /// Render the CPU ground truth of a scene (EXR + PNG + a JSON with time and convergence).
    Reference(cmd::reference::ReferenceArgs),
    /// Fill a reference cache with every frame of scenes at resolutions (for runs and bundles).
    References(cmd::references::ReferencesArgs),
    /// Write RUN_DIR/report/index.html (images, tables, Pareto plots) from RUN_DIR/results.json.
    Report(cmd::report::ReportArgs),
    /// Run methods on scenes, score them against the reference, write results.json and images.
    Run(cmd::run::RunArgs),
    /// Robustness suite: extreme but valid scenes × every method (no panic, no wgpu error, no
    /// non-finite pixel, error within the method's declared bound, or a clean "unsupported").
    #[command(mut_arg("res", |a| a.default_value("64")))]
    Stress(cmd::stress::StressArgs),
    /// Runs of one work list on different adapters → compare.html and compare.json.
    Compare(cmd::compare::CompareArgs),
    /// Per scene, the cheapest configuration under 1 % and 5 % with its time as a multiple of
    /// the floor (no-scatter), as Markdown; with --before, a before/after table.
    Frontier(cmd::frontier::FrontierArgs),
    /// Re-time a run's verdicts: per scene the few cheapest configurations under each error
    /// budget and the floor, again with more frames and paired floors, into a run of their
    /// own (what `frontier` then reads without the winner's curse).
    Confirm(cmd::confirm::ConfirmArgs),
    Tune(cmd::tune::TuneArgs),
    /// Merge run directories (e.g. the shards of `run --shard i/n`) into one run with its report.
    Merge(cmd::merge::MergeArgs),
    /// Re-create the papers' headline tables (a results run plus the paper's claim next to the
    /// measured ratio) and the equal-error table.
    #[command(
        mut_arg("res", |a| a.default_value("128")),
        mut_arg("frames", |a| a.default_value("5")),
        mut_arg("warmup", |a| a.default_value("1"))
    )]
    Reproduce(cmd::reproduce::ReproduceArgs),
    /// Frame time vs caster triangles (1k → 1M) and vs resolution (128² → 1024²) for every
    /// method at default parameters: a results run plus log–log plots with fitted slopes.
    #[command(
        mut_arg("frames", |a| a.default_value("3")),
        mut_arg("warmup", |a| a.default_value("1"))
    )]
    Scaling(cmd::scaling::ScalingArgs),
    /// Internal: serve the runner as a worker process (records over a pipe).
    #[command(name = "__worker", hide = true)]
    Worker,
}

/// Runs the command line (`std::env::args`) over `registry` and returns the exit status. Call
/// it first thing in `main`, before any other thread exists: it adds SwiftShader to the Vulkan
/// loader's search through the environment (`harness::gpu::adapters::add_known_drivers`).
pub fn main_with(registry: Registry) -> ExitCode {
    // SAFETY: main_with runs first in main, before any other thread exists (its contract).
    unsafe { harness::gpu::adapters::add_known_drivers() };
    cmd::pipe::exit_quietly_on_closed_output();
    if let Some(id) = listed_twice(registry) {
        eprintln!("error: the method registry lists '{id}' twice; method ids must be unique");
        return ExitCode::FAILURE;
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Adapters(a) => cmd::adapters::run(a),
        Command::List(a) => cmd::list::run(a, registry),
        Command::Validate(a) => cmd::validate::run(a),
        Command::Export(a) => cmd::export::run(a),
        Command::Reference(a) => cmd::reference::run(a),
        Command::References(a) => cmd::references::run(a),
        Command::Report(a) => cmd::report::run(a),
        Command::Run(a) => cmd::run::run(a, registry),
        Command::Stress(a) => cmd::stress::run(a, registry),
        Command::Merge(a) => cmd::merge::run(a),
        Command::Frontier(a) => cmd::frontier::run(a),
        Command::Confirm(a) => cmd::confirm::run(a, registry),
        Command::Tune(a) => cmd::tune::run(a, registry),
        Command::Compare(a) => cmd::compare::run(a),
        Command::Reproduce(a) => cmd::reproduce::run(a, registry),
        Command::Scaling(a) => cmd::scaling::run(a, registry),
        Command::Worker => cmd::worker::serve(registry),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            let refused = e.is::<args::Usage>() || e.is::<harness::KnobError>();
            ExitCode::from(if refused { 2 } else { 1 })
        }
    }
}

/// An id that two entries of `registry` share (the first found).
fn listed_twice(registry: Registry) -> Option<&'static str> {
    registry
        .iter()
        .enumerate()
        .find(|(i, m)| registry[..*i].iter().any(|o| o.id() == m.id()))
        .map(|(_, m)| m.id())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_registry_listing_an_id_twice_is_caught() {
        let r = methods::REGISTRY;
        assert_eq!(listed_twice(r), None);
        assert_eq!(listed_twice(&[r[0], r[1], r[0]]), Some(r[0].id()));
        assert_eq!(listed_twice(&[]), None);
    }
}
