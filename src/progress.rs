//! The one progress printer of every command that runs records (`run`, `reproduce`,
//! `scaling`, `stress`, `confirm`): a line per reference and per record on stderr, numbered
//! `[k/N]` once the work list's size is known, and the tally. On a terminal the lines scroll
//! above a progress bar: records done of the total, the record being measured, elapsed time and
//! an ETA from the records so far (indicatif's rate estimate, which weights recent records
//! more). In a pipe or a log file there is no bar, only the numbered lines.

use std::io::IsTerminal;
use std::time::Duration;

use harness::method::Params;
use harness::results::{Record, Status};
use harness::runner::Event;
use indicatif::{ProgressBar, ProgressStyle};

use crate::registry::Registry;

/// Prints runner events as they come and counts records by status.
pub struct Progress<'r> {
    /// Records expected, when known: lines are numbered `[k/N]`.
    total: Option<usize>,
    /// Whether the caller fixed the total (else each work list's `Planned` adds to it).
    total_given: bool,
    /// Records done, resumed ones included (the `k` of `[k/N]`).
    done: usize,
    counts: [usize; 3],
    /// The word for a status (`ok`, or `pass` in a stress run).
    verdict: fn(Status) -> &'static str,
    /// The error an ok line shows: its label and value.
    error: fn(&Record) -> Option<(&'static str, f64)>,
    /// Where a record's method's default knobs come from (a line shows the others).
    registry: Registry<'r>,
    /// The bar, on a terminal once the total is known.
    bar: Option<ProgressBar>,
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
            total_given: total.is_some(),
            done: 0,
            counts: [0; 3],
            verdict: status_word,
            error: inscatter_headline,
            registry,
            bar: None,
        }
    }

    /// A stress run: pass / unsupported / FAIL, with the error its bounds judge.
    pub fn stress(registry: Registry<'r>) -> Progress<'r> {
        let mut p = Progress::new(None, registry);
        p.verdict = experiments::stress::verdict;
        p.error = total_rel_rmse;
        p
    }

    pub fn event(&mut self, ev: Event) {
        match ev {
            Event::Planned(n) => self.planned(n),
            Event::Starting {
                scene,
                method,
                params,
            } => self.starting(scene, method, params),
            Event::Reference {
                scene,
                cached,
                seconds,
            } => self.say(format!(
                "reference {scene}: {}",
                if cached {
                    "cached".to_string()
                } else {
                    format!("{seconds:.1} s")
                }
            )),
            Event::Resumed(key) => {
                self.advance();
                self.say(format!("  {}resume: kept {key}", self.number()));
            }
            Event::Record(r) => self.record(r),
        }
    }

    /// A work list of `n` records: the total, unless the caller gave it.
    fn planned(&mut self, n: usize) {
        if self.total_given {
            return;
        }
        let total = self.total.unwrap_or(0) + n;
        self.total = Some(total);
        match &self.bar {
            Some(bar) => bar.set_length(total as u64),
            None if std::io::stderr().is_terminal() => self.bar = Some(bar(total, self.done)),
            None => {}
        }
    }

    fn starting(&mut self, scene: &str, method: &str, params: &Params) {
        if self.bar.is_none() && self.total.is_some() && std::io::stderr().is_terminal() {
            self.bar = Some(bar(self.total.unwrap_or(0), self.done));
        }
        if let Some(bar) = &self.bar {
            let knobs = experiments::params_text(self.registry, method, params);
            bar.set_message(format!("{scene} {method} {knobs}"));
        }
    }

    /// One line: above the bar on a terminal, else on stderr as it is.
    fn say(&self, line: String) {
        match &self.bar {
            Some(bar) => bar.println(line),
            None => eprintln!("{line}"),
        }
    }

    fn advance(&mut self) {
        self.done += 1;
        if let Some(bar) = &self.bar {
            bar.set_position(self.done as u64);
        }
    }

    /// `[k/N] ` once the total is known.
    fn number(&self) -> String {
        self.total
            .map(|n| format!("[{}/{n}] ", self.done))
            .unwrap_or_default()
    }

    fn record(&mut self, r: &Record) {
        self.advance();
        self.counts[r.status as usize] += 1;
        self.say(format!(
            "  {}{:<11} {:<24} {:<26} {}  {}",
            self.number(),
            (self.verdict)(r.status),
            r.scene,
            r.method,
            experiments::params_text(self.registry, &r.method, &r.params),
            self.detail(r)
        ));
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

    /// Records seen by status: [ok, skipped, failed] (resumed ones not counted). The work is
    /// over when the tally is asked for: the bar goes, so that the tally prints on a clean line.
    pub fn counts(&self) -> [usize; 3] {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        self.counts
    }
}

impl Drop for Progress<'_> {
    /// The bar goes when the command's work does, so that its tally prints on a clean line.
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// A bar of `total` records, `done` of them done: done/total, elapsed, ETA, the current record.
fn bar(total: usize, done: usize) -> ProgressBar {
    let bar = ProgressBar::new(total as u64).with_position(done as u64);
    let style = ProgressStyle::with_template(
        "[{pos}/{len}] [{bar:28}] {elapsed_precise} elapsed, ETA {eta_precise}  {wide_msg}",
    )
    .unwrap_or_else(|_| ProgressStyle::default_bar())
    .progress_chars("=> ");
    bar.set_style(style);
    // Redraw each second, so elapsed time moves during a long record.
    bar.enable_steady_tick(Duration::from_secs(1));
    bar
}

/// A relative error readable at a glance: 4 decimals, or 3 significant digits when tiny.
fn short(e: f64) -> String {
    if e == 0.0 || e.abs() >= 1e-3 {
        format!("{e:.4}")
    } else {
        format!("{e:.3e}")
    }
}
