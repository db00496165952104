//! `scatterbench`: the command line (ARCHITECTURE §8). `src/` parses and checks arguments
//! (`args.rs`, shared arguments declared once), prints progress (`progress.rs`) and calls
//! library code: `harness` (runner, reference, stress, merge), `experiments` (reproduce,
//! scaling), `report`. One module per subcommand in `src/cmd/`.
//!
//! Exit codes (ARCHITECTURE §8.3): 0 success; 1 the work ran and failed; 2 bad input refused
//! before any work (clap's usage errors, and [`args::Usage`]).

mod args;
mod cmd;
mod progress;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

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
    /// Scenes with their features; methods with their params and support.
    List(cmd::list::ListArgs),
    /// Validate scene files: exit 0, or exit 2 listing every problem.
    Validate(cmd::validate::ValidateArgs),
    /// Render the CPU ground truth of a scene (EXR + PNG + a JSON with time and convergence).
    Reference(cmd::reference::ReferenceArgs),
    /// Write RUN_DIR/report/index.html (images, tables, Pareto plots) from RUN_DIR/results.json.
    Report(cmd::report::ReportArgs),
    /// Run methods on scenes, score them against the reference, write results.json and images.
    Run(cmd::run::RunArgs),
    /// Robustness suite: extreme but valid scenes × every method (no panic, no wgpu error, no
    /// non-finite pixel, error within the method's declared bound, or a clean "unsupported").
    #[command(mut_arg("res", |a| a.default_value("64")))]
    Stress(cmd::stress::StressArgs),
    /// Merge run directories (e.g. the shards of `run --shard i/n`) into one run with its report.
    Merge(cmd::merge::MergeArgs),
    /// Runs of one work list on different adapters → compare.html and compare.json.
    Compare(cmd::compare::CompareArgs),
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

fn main() -> ExitCode {
    cmd::pipe::exit_quietly_on_closed_output();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::List(a) => cmd::list::run(a),
        Command::Validate(a) => cmd::validate::run(a),
        Command::Reference(a) => cmd::reference::run(a),
        Command::Report(a) => cmd::report::run(a),
        Command::Run(a) => cmd::run::run(a),
        Command::Stress(a) => cmd::stress::run(a),
        Command::Merge(a) => cmd::merge::run(a),
        Command::Compare(a) => cmd::compare::run(a),
        Command::Reproduce(a) => cmd::reproduce::run(a),
        Command::Scaling(a) => cmd::scaling::run(a),
        Command::Worker => cmd::worker::serve(),
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
