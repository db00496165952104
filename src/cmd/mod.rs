//! One module per subcommand: its arguments (clap) and a `run` that checks them and calls
//! library code (ARCHITECTURE §8).

pub mod adapters;
pub mod compare;
pub mod confirm;
pub mod export;
pub mod frontier;
pub mod list;
pub mod merge;
pub mod pipe;
pub mod reference;
pub mod references;
pub mod report;
pub mod reproduce;
pub mod run;
pub mod scaling;
pub mod stress;
pub mod tune;
pub mod validate;
pub mod worker;

/// Writes OUT/report/index.html after a command wrote OUT/results.json. The report is a view
/// of results.json, which is already written: a report problem is a warning, never a failed
/// run.
pub fn write_report(out: &std::path::Path) {
    match ::report::generate(out) {
        Ok(index) => println!("report: {}", index.display()),
        Err(e) => eprintln!("warning: the report was not written: {e:#}"),
    }
}
