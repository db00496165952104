//! `scatterbench`: the command line (ARCHITECTURE §8). Each subcommand lives in `src/cmd/`.

mod cmd;

use std::path::PathBuf;
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
    List {
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Validate scene files: exit 0, or exit 2 listing every problem.
    Validate {
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Render the CPU ground truth of a scene (EXR + PNG + a JSON with time and convergence).
    Reference {
        /// Library name or path to a scene .json.
        #[arg(long)]
        scene: String,
        /// N (square) or WxH.
        #[arg(long, default_value = "512")]
        res: String,
        /// Frame to render (default 0).
        #[arg(long, default_value_t = 0)]
        frame: u32,
        /// Output directory (default results/reference/<scene>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Convergence check on every Nth pixel in each direction (1 = every pixel).
        #[arg(long, default_value_t = 4)]
        convergence_stride: u32,
    },
    /// Write RUN_DIR/report/index.html (images, tables, Pareto plots) from RUN_DIR/results.json.
    Report {
        /// A directory written by `scatterbench run` (holds results.json).
        run_dir: PathBuf,
    },
    #[command(flatten)]
    Bench(cmd::run::BenchCommand),
    /// Robustness suite: extreme but valid scenes × every method (no panic, no wgpu error, no
    /// non-finite pixel, error within the method's declared bound, or a clean "unsupported").
    Stress(cmd::stress::StressArgs),
    /// Merge run directories (e.g. the shards of `run --shard i/n`) into one run with its report.
    Merge(cmd::merge::MergeArgs),
    /// Re-create the papers' headline tables (a results run plus the paper's claim next to the
    /// measured ratio) and the equal-error table.
    Reproduce(cmd::reproduce::ReproduceArgs),
    /// Frame time vs caster triangles (1k → 1M) and vs resolution (128² → 1024²) for every
    /// method at default parameters: a results run plus log–log plots with fitted slopes.
    Scaling(cmd::scaling::ScalingArgs),
    /// Internal: serve the runner as a worker process (records over a pipe).
    #[command(name = "__worker", hide = true)]
    Worker,
}

fn main() -> ExitCode {
    cmd::pipe::exit_quietly_on_closed_output();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::List { json } => cmd::list::run(json),
        Command::Validate { files } => return cmd::validate::run(&files),
        Command::Reference {
            scene,
            res,
            frame,
            out,
            convergence_stride,
        } => cmd::reference::run(&scene, &res, frame, out, convergence_stride),
        Command::Report { run_dir } => cmd::report::run(&run_dir),
        Command::Bench(b) => cmd::run::dispatch(b),
        Command::Stress(a) => cmd::stress::run(a),
        Command::Merge(a) => cmd::merge::run(a),
        Command::Reproduce(a) => cmd::reproduce::run(a),
        Command::Scaling(a) => cmd::scaling::run(a),
        Command::Worker => cmd::worker::serve(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
