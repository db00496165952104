//! The stability table of a `scatterbench stress` run (ARCHITECTURE §5.2, §6): stress case × method,
//! each cell the verdict of the four stress criteria — no panic, no wgpu error, no non-finite
//! pixel, total-AOV error within the bound the method declares for the case — with the numbers
//! behind it, and below the table every failure's and refusal's reason in full.
//!
//! Verdicts come from `harness::stress::judge`, the function the stress command itself uses,
//! applied to the record and the bound the record carries, so the page and the command can
//! never disagree. Whether a panic, wgpu error or lost device was behind a failure is read
//! from the reason text the runner and the stress suite write ("panicked: …", "wgpu error: …",
//! "…; wgpu: …", "device lost (…)"): results.json has no separate field for it.

use harness::results::{Record, Results, STRESS_KIND};
use harness::stress::{self, BOUND_COUNTER, Verdict};
use serde::Serialize;

use crate::format::rel;

/// Characters of a reason shown inside a cell; the full text is in the tooltip and the
/// details table.
const CELL_REASON: usize = 90;

#[derive(Serialize)]
pub struct Stability {
    pub methods: Vec<String>,
    pub rows: Vec<CaseRow>,
    /// Every fail and unsupported cell, with its full reason.
    pub details: Vec<Detail>,
    pub pass: usize,
    pub unsupported: usize,
    pub fail: usize,
}

#[derive(Serialize)]
pub struct CaseRow {
    pub case: String,
    /// What the case stresses (empty for a scene that is not a known case).
    pub about: String,
    pub cells: Vec<Cell>,
}

#[derive(Serialize)]
pub struct Cell {
    /// "pass", "fail", "unsupported" or "absent" (not run).
    pub verdict: String,
    /// Total-AOV relative RMSE against the bound: "0.0123 ≤ 0.15", "0.2 > 0.15",
    /// "0.0123 (no bound)", or "—" when the record was not scored.
    pub error: String,
    /// Non-finite pixels in the worst AOV, "—" when not scored.
    pub nonfinite: String,
    /// "panic", "wgpu error", "device lost" or "" (none seen).
    pub fault: String,
    /// The reason, shortened for the cell.
    pub short: String,
    /// The full reason (tooltip).
    pub reason: String,
    /// Records in the cell when more than one (the worst verdict is shown).
    pub records: usize,
}

#[derive(Serialize)]
pub struct Detail {
    pub case: String,
    pub method: String,
    pub verdict: String,
    pub fault: String,
    pub reason: String,
}

/// Whether `results` came from `scatterbench stress`: marked so by the run, or (files written
/// before the marker) every scene is a stress case name.
pub fn is_stress(results: &Results) -> bool {
    results.run.kind.as_deref() == Some(STRESS_KIND)
        || (!results.records.is_empty()
            && results
                .records
                .iter()
                .all(|r| stress::find(&r.scene).is_some()))
}

/// The kind of fault a failure reason reports, if any.
pub fn fault(reason: &str) -> &'static str {
    if reason.contains("panicked") {
        "panic"
    } else if reason.contains("device lost") {
        "device lost"
    } else if reason.contains("wgpu error") || reason.contains("wgpu: ") {
        "wgpu error"
    } else {
        ""
    }
}

/// Name of a verdict as the page shows it.
pub fn verdict_text(v: &Verdict) -> &'static str {
    match v {
        Verdict::Pass => "pass",
        Verdict::Unsupported(_) => "unsupported",
        Verdict::Fail(_) => "fail",
    }
}

/// The record's verdict, judged against the bound it carries.
pub fn verdict(r: &Record) -> Verdict {
    stress::judge(r, r.counters.get(BOUND_COUNTER).copied())
}

fn severity(v: &Verdict) -> u8 {
    match v {
        Verdict::Pass => 0,
        Verdict::Unsupported(_) => 1,
        Verdict::Fail(_) => 2,
    }
}

fn shorten(s: &str) -> String {
    if s.chars().count() <= CELL_REASON {
        s.to_string()
    } else {
        let cut: String = s.chars().take(CELL_REASON).collect();
        format!("{cut}…")
    }
}

fn cell(recs: &[&Record]) -> (Cell, Option<String>) {
    let Some((r, v)) = recs
        .iter()
        .map(|r| (*r, verdict(r)))
        .max_by_key(|(_, v)| severity(v))
    else {
        let absent = Cell {
            verdict: "absent".into(),
            error: "—".into(),
            nonfinite: "—".into(),
            fault: String::new(),
            short: "not run".into(),
            reason: String::new(),
            records: 0,
        };
        return (absent, None);
    };
    let bound = r.counters.get(BOUND_COUNTER).copied();
    let error = match (r.errors.get("total"), bound) {
        (None, _) => "—".into(),
        (Some(m), Some(b)) => {
            let op = if m.rel_rmse <= b { "≤" } else { ">" };
            format!("{} {op} {b}", rel(m.rel_rmse))
        }
        (Some(m), None) => format!("{} (no bound)", rel(m.rel_rmse)),
    };
    let reason = match &v {
        Verdict::Pass => String::new(),
        Verdict::Unsupported(why) | Verdict::Fail(why) => why.clone(),
    };
    let c = Cell {
        verdict: verdict_text(&v).into(),
        error,
        nonfinite: r
            .errors
            .values()
            .map(|m| m.nonfinite)
            .max()
            .map(|n| n.to_string())
            .unwrap_or_else(|| "—".into()),
        fault: fault(&reason).into(),
        short: shorten(&reason),
        reason: reason.clone(),
        records: if recs.len() > 1 { recs.len() } else { 0 },
    };
    let detail = (!matches!(v, Verdict::Pass)).then_some(reason);
    (c, detail)
}

/// The stability table of a stress run: cases in the suite's order (unknown scene names after
/// them, in order of appearance), methods in order of appearance.
pub fn table(results: &Results) -> Stability {
    let mut cases: Vec<&str> = Vec::new();
    let mut methods: Vec<&str> = Vec::new();
    for r in &results.records {
        if !cases.contains(&r.scene.as_str()) {
            cases.push(&r.scene);
        }
        if !methods.contains(&r.method.as_str()) {
            methods.push(&r.method);
        }
    }
    let order = |c: &str| {
        stress::CASES
            .iter()
            .position(|k| k.name == c)
            .unwrap_or(usize::MAX)
    };
    // Stable: unknown names keep their order of appearance.
    cases.sort_by_key(|c| order(c));

    let mut t = Stability {
        methods: methods.iter().map(|m| m.to_string()).collect(),
        rows: Vec::new(),
        details: Vec::new(),
        pass: 0,
        unsupported: 0,
        fail: 0,
    };
    for case in &cases {
        let mut cells = Vec::new();
        for m in &methods {
            let recs: Vec<&Record> = results
                .records
                .iter()
                .filter(|r| r.scene == *case && r.method == *m)
                .collect();
            let (c, detail) = cell(&recs);
            match c.verdict.as_str() {
                "pass" => t.pass += 1,
                "unsupported" => t.unsupported += 1,
                "fail" => t.fail += 1,
                _ => {}
            }
            if let Some(reason) = detail {
                t.details.push(Detail {
                    case: case.to_string(),
                    method: m.to_string(),
                    verdict: c.verdict.clone(),
                    fault: c.fault.clone(),
                    reason,
                });
            }
            cells.push(c);
        }
        t.rows.push(CaseRow {
            case: case.to_string(),
            about: stress::find(case)
                .map(|c| c.about.to_string())
                .unwrap_or_default(),
            cells,
        });
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faults_are_read_from_the_reasons_the_runner_writes() {
        assert_eq!(fault("panicked: index out of bounds"), "panic");
        assert_eq!(
            fault("no record (reference or harness): panicked: boom"),
            "panic"
        );
        assert_eq!(fault("wgpu error: Validation Error"), "wgpu error");
        assert_eq!(
            fault("prepare failed: x; wgpu: Validation Error"),
            "wgpu error"
        );
        assert_eq!(fault("device lost (Unknown): gone"), "device lost");
        assert_eq!(fault("12 non-finite pixels in the output"), "");
        assert_eq!(fault(""), "");
    }

    #[test]
    fn long_reasons_are_shortened_on_a_char_boundary() {
        let s = "é".repeat(CELL_REASON + 5);
        let short = shorten(&s);
        assert_eq!(short.chars().count(), CELL_REASON + 1);
        assert!(short.ends_with('…'));
        assert_eq!(shorten("short"), "short");
    }
}
