//! `scatterbench report RUN_DIR`: writes `RUN_DIR/report/index.html` from results.json
//! (ARCHITECTURE §5.2).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

#[derive(Args)]
pub struct ReportArgs {
    /// A directory written by `scatterbench run` (holds results.json).
    pub run_dir: PathBuf,
}

pub fn run(a: ReportArgs) -> Result<()> {
    if !a.run_dir.join("results.json").is_file() {
        return crate::args::refuse(format!(
            "RUN_DIR: {} holds no results.json",
            a.run_dir.display()
        ));
    }
    let index = report::generate(&a.run_dir)?;
    println!("report: {}", index.display());
    Ok(())
}
