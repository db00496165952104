//! The one progress printer of every command that runs records (`run`, `reproduce`,
//! `scaling`, `stress`): a line per reference and per record on stderr, and the tally.

use harness::results::{Record, Status};
use harness::runner::Event;

use crate::registry::Registry;

/// Prints runner events as they come and counts records by status.
pub struct Progress<'r> {
    /// Records expected, when known: lines are numbered `[k/N]`.
    total: Option<usize>,
    done: usize,
    counts: [usize; 3],
    /// The word for a status (`ok`, or `pass` in a stress run).
    verdict: fn(Status) -> &'static str,
    /// The error an ok line shows: its label and value.
    error: fn(&Record) -> Option<(&'static str, f64)>,
    /// Where a record's method's default knobs come from (a line shows the others).
    registry: Registry<'r>,
}

/// The verdict metric of the in-scatter (what the report ranks by).
fn inscatter_headline(r: &Record) -> Option<(&'static str, f64)> {
    harness::verdict::headline(r, "inscatter").map(|e| ("inscatter headline", e))
}

/// The error a stress bound judges: the total's relative RMSE (ARCHITECTURE §6).
fn total_rel_rmse(r: &Record) -> Option<(&'static str, f64)> {
    r.errors
        .get("total")
        .map(|m| ("total rel RMSE", m.rel_rmse))
}

fn status_word(s: Status) -> &'static str {
    match s {
        Status::Ok => "ok",
        Status::Skipped => "skipped",
        Status::Failed => "failed",
    }
}

impl<'r> Progress<'r> {
    /// A benchmark run: ok / skipped / failed, with the in-scatter headline error.
    pub fn new(total: Option<usize>, registry: Registry<'r>) -> Progress<'r> {
        Progress {
            total,
            done: 0,
            counts: [0; 3],
            verdict: status_word,
            error: inscatter_headline,
            registry,
        }
    }

    /// A stress run: pass / unsupported / FAIL, with the error its bounds judge.
    pub fn stress(registry: Registry<'r>) -> Progress<'r> {
        Progress {
            verdict: experiments::stress::verdict,
            error: total_rel_rmse,
            ..Progress::new(None, registry)
        }
    }

    pub fn event(&mut self, ev: Event) {
        match ev {
            Event::Reference {
                scene,
                cached,
                seconds,
            } => eprintln!(
                "reference {scene}: {}",
                if cached {
                    "cached".to_string()
                } else {
                    format!("{seconds:.1} s")
                }
            ),
            Event::Resumed(key) => eprintln!("resume: kept {key}"),
            Event::Record(r) => self.record(r),
        }
    }

    fn record(&mut self, r: &Record) {
        self.done += 1;
        self.counts[r.status as usize] += 1;
        let number = self
            .total
            .map(|n| format!("[{}/{n}] ", self.done))
            .unwrap_or_default();
        eprintln!(
            "  {number}{:<11} {:<24} {:<26} {}  {}",
            (self.verdict)(r.status),
            r.scene,
            r.method,
            experiments::params_text(self.registry, &r.method, &r.params),
            self.detail(r)
        );
    }

    /// Times and error of an ok record; the reason of any other.
    fn detail(&self, r: &Record) -> String {
        if let Some(why) = &r.reason {
            return why.clone();
        }
        let mut parts = Vec::new();
        if let Some(t) = &r.timing {
            parts.push(format!("wall {:.2} ms", t.wall_ms.median));
            if let Some(g) = t.gpu_ms {
                parts.push(format!("gpu {:.2} ms", g.median));
            }
        }
        if let Some((label, e)) = (self.error)(r) {
            parts.push(format!("{label} {}", short(e)));
        }
        parts.join(", ")
    }

    /// Records seen by status: [ok, skipped, failed] (resumed ones not counted).
    pub fn counts(&self) -> [usize; 3] {
        self.counts
    }
}

/// A relative error readable at a glance: 4 decimals, or 3 significant digits when tiny.
fn short(e: f64) -> String {
    if e == 0.0 || e.abs() >= 1e-3 {
        format!("{e:.4}")
    } else {
        format!("{e:.3e}")
    }
}
