//! `scatterbench report RUN_DIR`: writes `RUN_DIR/report/index.html` from results.json.

use std::path::Path;

use anyhow::Result;

pub fn run(run_dir: &Path) -> Result<()> {
    let index = report::generate(run_dir)?;
    println!("report: {}", index.display());
    Ok(())
}
