//! `scatterbench frontier RUN_DIR [--before RUN_DIR] [--out FILE]`: per scene, the cheapest
//! configuration under 1 % and 5 % with its floor ratio, as Markdown (`report::frontier`,
//! ARCHITECTURE §4.5) — the before/after table of a change to what accuracy costs.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow};
use clap::Args;
use harness::results::Results;

#[derive(Args)]
pub struct FrontierArgs {
    /// A run directory (holds results.json): the "after" column, or the only one.
    pub run_dir: PathBuf,
    /// A run directory to show as "before", to the left of each RUN_DIR column.
    #[arg(long)]
    pub before: Option<PathBuf>,
    /// Write the table to this file (atomically) instead of standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn run(a: FrontierArgs) -> Result<()> {
    let after = load("RUN_DIR", &a.run_dir)?;
    let before = match &a.before {
        Some(dir) => Some(load("--before", dir)?),
        None => None,
    };
    let table = report::frontier::markdown(&after, before.as_ref());
    match &a.out {
        Some(path) => {
            harness::fsutil::write_atomic(path, table.as_bytes()).map_err(|e| anyhow!(e))?;
            println!("frontier: {}", path.display());
        }
        None => print!("{table}"),
    }
    Ok(())
}

/// The run in `dir`, refused (exit 2) where `dir` holds no results.json.
pub fn load(arg: &str, dir: &Path) -> Result<Results> {
    let path = dir.join("results.json");
    if !path.is_file() {
        return crate::args::refuse(format!("{arg}: {} holds no results.json", dir.display()));
    }
    Results::load(&path).map_err(|e| anyhow!("{}: {e}", path.display()))
}
