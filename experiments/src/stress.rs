//! The stability table of a `scatterbench stress` run as text (ARCHITECTURE §6): one line per
//! case × method with its verdict, the total's relative RMSE, the bound it was judged against
//! and the reason. The HTML report has the same table (`report::stability`).

use std::fmt::Write as _;

use harness::results::{Results, Status};
use harness::stress::{self, BOUND_COUNTER};

/// A stress record's verdict: pass, unsupported (a clean refusal) or FAIL.
pub fn verdict(s: Status) -> &'static str {
    match s {
        Status::Ok => "pass",
        Status::Skipped => "unsupported",
        Status::Failed => "FAIL",
    }
}

/// The table, then "P pass, U unsupported, F fail".
pub fn table_text(results: &Results) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<24} {:<18} {:<12} {:>12} {:>10}  reason",
        "case", "method", "verdict", "total rRMSE", "bound"
    );
    for r in &results.records {
        let bound = r
            .counters
            .get(BOUND_COUNTER)
            .map_or_else(|| "-".into(), |b| format!("{b}"));
        let e = r
            .errors
            .get("total")
            .map_or_else(|| "-".into(), |m| format!("{:.3e}", m.rel_rmse));
        let _ = writeln!(
            t,
            "{:<24} {:<18} {:<12} {:>12} {:>10}  {}",
            r.scene,
            r.method,
            verdict(r.status),
            e,
            bound,
            r.reason.as_deref().unwrap_or("")
        );
    }
    let (pass, unsupported, fail) = stress::tally(results);
    let _ = write!(t, "{pass} pass, {unsupported} unsupported, {fail} fail");
    t
}
