//! Writes the report's synthetic test run (tests/fixtures/results.json plus generated images)
//! to DIR and builds its report: `cargo run --release -p report --example fixture -- DIR`.
//! Used by scripts/report-screenshot.sh to look at the page without a GPU run.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let Some(dir) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: fixture DIR");
        return ExitCode::from(2);
    };
    let built = report::fixture::write(&dir, include_str!("../tests/fixtures/results.json"))
        .and_then(|_| report::generate(&dir));
    match built {
        Ok(index) => {
            println!("{}", index.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
