//! Writes one of the report's synthetic test runs (tests/fixtures/results.json, with `stress`
//! the stress run tests/fixtures/stress-results.json, with `widest` every library scene ×
//! every method of tests/fixtures/method-ids.txt, plus generated images) to DIR and builds its
//! report: `cargo run --release -p report --example fixture -- DIR [stress|widest]`.
//! Used by scripts/report-screenshot.sh to look at the page without a GPU run.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args_os().skip(1);
    let Some(dir) = args.next().map(PathBuf::from) else {
        eprintln!("usage: fixture DIR [stress]");
        return ExitCode::from(2);
    };
    let json = match args.next().as_deref().map(|a| a.to_str()) {
        None => include_str!("../tests/fixtures/results.json").to_string(),
        Some(Some("stress")) => include_str!("../tests/fixtures/stress-results.json").to_string(),
        Some(Some("widest")) => widest(),
        Some(other) => {
            eprintln!("unknown fixture {other:?}: use `stress`, `widest` or nothing");
            return ExitCode::from(2);
        }
    };
    let built = report::fixture::write(&dir, &json).and_then(|_| report::generate(&dir));
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

/// Every library scene × every registered method (tests/fixtures/method-ids.txt).
fn widest() -> String {
    let methods: Vec<&str> = include_str!("../tests/fixtures/method-ids.txt")
        .lines()
        .collect();
    let run = report::fixture::synthetic::widest(
        "llvmpipe (LLVM 15.0.6, 256 bits)",
        &scenes::library::names(),
        &methods,
    );
    serde_json::to_string_pretty(&run).expect("serialisable")
}
