//! The one progress printer of every command that runs records (`run`, `reproduce`,
//! `scaling`, `stress`): a line per reference and per record on stderr, and the tally.

use harness::results::{Record, Status};
use harness::runner::Event;

/// Prints runner events as they come and counts records by status.
pub struct Progress {
    /// Records expected, when known: lines are numbered `[k/N]`.
    total: Option<usize>,
    done: usize,
    counts: [usize; 3],
    /// The word for a status (`ok`, or `pass` in a stress run).
    verdict: fn(Status) -> &'static str,
    /// The AOV whose relative RMSE an ok line shows.
    aov: &'static str,
}

fn status_word(s: Status) -> &'static str {
    match s {
        Status::Ok => "ok",
        Status::Skipped => "skipped",
        Status::Failed => "failed",
    }
}

impl Progress {
    /// A benchmark run: ok / skipped / failed, with the in-scatter error.
    pub fn new(total: Option<usize>) -> Progress {
        Progress {
            total,
            done: 0,
            counts: [0; 3],
            verdict: status_word,
            aov: "inscatter",
        }
    }

    /// A stress run: pass / unsupported / FAIL, with the total's error (ARCHITECTURE §6).
    pub fn stress() -> Progress {
        Progress {
            verdict: experiments::stress::verdict,
            aov: "total",
            ..Progress::new(None)
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
            experiments::params_text(&r.method, &r.params),
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
        if let Some(m) = r.errors.get(self.aov) {
            parts.push(format!("{} rel RMSE {}", self.aov, short(m.rel_rmse)));
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
