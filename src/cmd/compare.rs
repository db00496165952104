//! `scatterbench compare RUN_A RUN_B [...] [--out DIR]`: runs of the same work list on
//! different adapters → DIR/compare.html and DIR/compare.json, and a short summary
//! (ARCHITECTURE §5.3, §8.1). Runs of different work are refused (exit 2); a results.json
//! that cannot be read fails (exit 1).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use report::compare::{self, CompareError};

#[derive(Args)]
pub struct CompareArgs {
    /// Run directories (each holds results.json) of the same work list, e.g. one per adapter.
    #[arg(required = true, num_args = 2.., value_name = "RUN")]
    pub run_dirs: Vec<PathBuf>,
    /// Output directory [results/compare-<run-id>].
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn run(a: CompareArgs) -> Result<()> {
    let runs = compare::load(&a.run_dirs).map_err(|e| match e {
        CompareError::Refused(m) => crate::args::Usage(m).into(),
        CompareError::Unreadable(m) => anyhow::anyhow!(m),
    })?;
    let out = a.out.unwrap_or_else(|| {
        PathBuf::from("results").join(format!("compare-{}", harness::results::run_id_now()))
    });
    let comparison = compare::compare(&runs);
    let written = compare::write(&out, &comparison)?;
    for line in compare::summary::lines(&comparison) {
        println!("{line}");
    }
    println!("compare: {}", written.html.display());
    println!("json: {}", written.json.display());
    Ok(())
}
