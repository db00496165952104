//! `scatterbench merge RUN_DIR... --out DIR`: reassemble the shards of `run --shard i/n` (or
//! any runs of the same resolution and adapter) into one run with its report
//! (ARCHITECTURE §9.4).

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use harness::merge::{MergeOptions, merge};

#[derive(Args)]
pub struct MergeArgs {
    /// Run directories (each holds results.json), e.g. the shards of one split.
    #[arg(required = true)]
    pub run_dirs: Vec<PathBuf>,
    /// Output directory (must not hold a results.json yet).
    #[arg(long)]
    pub out: PathBuf,
    /// Merge runs measured on different adapters (their timings then do not compare).
    #[arg(long)]
    pub allow_mixed_adapters: bool,
    /// A record (scene, method, params) in two runs: keep the later run's in the earlier one's
    /// place instead of refusing (fold a method re-run after a fix, or a refinement sweep with
    /// `--sweep --param`, into a sweep); a warning says how many were replaced.
    #[arg(long)]
    pub replace: bool,
}

pub fn run(a: MergeArgs) -> Result<()> {
    crate::args::check_fresh(&a.out)?;
    let summary = merge(
        &a.run_dirs,
        &a.out,
        &MergeOptions {
            allow_mixed_adapters: a.allow_mixed_adapters,
            run_id: None,
            replace: a.replace,
        },
    )
    .map_err(|e| anyhow!(e))?;
    for w in &summary.warnings {
        eprintln!("warning: {w}");
    }
    println!(
        "{} records from {} runs, {} files copied → {}",
        summary.results.records.len(),
        a.run_dirs.len(),
        summary.files_copied,
        a.out.join("results.json").display()
    );
    super::write_report(&a.out);
    Ok(())
}
