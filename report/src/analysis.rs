//! The numbers the report draws conclusions from: which time a record is compared on, the
//! time-vs-error Pareto front, and the cheapest configuration under an error budget.
//!
//! These are plain functions on plain data so they can be tested with hand-made points;
//! the page and the plots only display what they return.

use harness::results::{Record, Stat, Status};
pub use harness::verdict::FLOOR_METHOD;

use crate::metric::Metric;

/// Error budgets of the "cheapest method under an error budget" tables, as fractions of the
/// chosen metric (0.01 = 1 %; the verdict metric by default).
pub const BUDGETS: [f64; 3] = [0.01, 0.05, 0.10];

/// Which per-frame time a scene's records are compared on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeBasis {
    /// Median GPU time from timestamp queries (every ok record of the scene has it).
    Gpu,
    /// Median wall time of encode + submit + wait (some record lacks GPU timestamps).
    Wall,
}

impl TimeBasis {
    /// GPU time when every ok record has it, else wall time, so one scene never mixes the two.
    pub fn for_records<'a>(records: impl IntoIterator<Item = &'a Record>) -> TimeBasis {
        let all_gpu = records
            .into_iter()
            .filter(|r| r.status == Status::Ok)
            .all(|r| r.timing.as_ref().is_some_and(|t| t.gpu_ms.is_some()));
        if all_gpu {
            TimeBasis::Gpu
        } else {
            TimeBasis::Wall
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            TimeBasis::Gpu => "GPU time per frame, median (ms)",
            TimeBasis::Wall => "wall time per frame, median (ms)",
        }
    }

    /// The record's median frame time in ms on this basis, if it was timed.
    pub fn time_ms(self, r: &Record) -> Option<f64> {
        let t = r.timing.as_ref()?;
        self.median(t.wall_ms, t.gpu_ms)
    }

    /// The median of whichever of a measurement's wall and GPU times this basis reads (a
    /// record's own, or its paired floor's).
    pub fn median(self, wall_ms: Stat, gpu_ms: Option<Stat>) -> Option<f64> {
        match self {
            TimeBasis::Gpu => gpu_ms.map(|g| g.median),
            TimeBasis::Wall => Some(wall_ms.median),
        }
    }
}

/// How one scene of one run is timed (ARCHITECTURE §4.5): the time basis, and the floor every
/// ratio and, in a `--paired-floor` run, every compared time refers to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clock {
    pub basis: TimeBasis,
    /// The floor's time (ms) on `basis`, None where the run has no floor there: the median of
    /// the scene's paired floors where its records have them (`run --paired-floor`: the
    /// floor timed beside every record, so the drift-free estimate of it), else the fastest
    /// ok, timed [`FLOOR_METHOD`] record.
    pub floor_ms: Option<f64>,
    /// The fastest ok, timed floor record's time: the floor of records without a paired one.
    floor_record_ms: Option<f64>,
    /// Some record has a paired floor: compared times are drift-corrected.
    pub paired: bool,
}

impl Clock {
    /// The clock of `records` (one scene of one run) on the basis they allow.
    pub fn for_records(records: &[&Record]) -> Clock {
        Clock::on(TimeBasis::for_records(records.iter().copied()), records)
    }

    /// The clock of `records` on a basis chosen for more than them (`compare`: the basis its
    /// runs share).
    pub fn on(basis: TimeBasis, records: &[&Record]) -> Clock {
        let paired: Vec<f64> = records
            .iter()
            .filter(|r| r.status == Status::Ok)
            .filter_map(|r| paired_floor_ms(r, basis))
            .collect();
        let floor_record_ms = fastest_floor_record_ms(records, basis);
        let floor_ms = if paired.is_empty() {
            floor_record_ms
        } else {
            Some(Stat::of(&paired).median)
        };
        Clock {
            basis,
            floor_ms,
            floor_record_ms,
            paired: !paired.is_empty(),
        }
    }

    /// The axis and column label of compared times.
    pub fn label(&self) -> String {
        match self.paired {
            true => format!(
                "{}, × scene floor ÷ paired floor (drift-corrected)",
                self.basis.label()
            ),
            false => self.basis.label().to_string(),
        }
    }

    /// The floor `r`'s time is divided by: its paired floor, else the floor record's time,
    /// else the scene's floor.
    fn own_floor_ms(&self, r: &Record) -> Option<f64> {
        paired_floor_ms(r, self.basis)
            .or(self.floor_record_ms)
            .or(self.floor_ms)
    }

    /// The time `r` is compared on: its median frame time on the basis × the scene's floor ÷
    /// its own floor ([`Clock::floor_ratio`] × [`Clock::floor_ms`]), or the median alone where
    /// there is no floor. Without paired floors the two floors are one and the time is the
    /// median. A paired run's records are timed minutes apart while the machine's speed
    /// drifts (identical floor work spread 1.5–2.2× p10–p90 over one lavapipe run); the
    /// paired floor measures the machine beside each record, and ranking raw times would
    /// rank that drift.
    pub fn time_ms(&self, r: &Record) -> Option<f64> {
        let t = self.basis.time_ms(r)?;
        Some(match (self.own_floor_ms(r), self.floor_ms) {
            (Some(own), Some(scene)) => t * scene / own,
            _ => t,
        })
    }

    /// `r`'s floor ratio: its median frame time ÷ its paired floor where it has one, else ÷
    /// the scene's floor record; None where there is no floor or `r` was not timed.
    pub fn floor_ratio(&self, r: &Record) -> Option<f64> {
        Some(self.basis.time_ms(r)? / self.own_floor_ms(r)?)
    }
}

/// The fastest ok, timed [`FLOOR_METHOD`] record's time on `basis`.
fn fastest_floor_record_ms(records: &[&Record], basis: TimeBasis) -> Option<f64> {
    records
        .iter()
        .filter(|r| r.method == FLOOR_METHOD && r.status == Status::Ok)
        .filter_map(|r| basis.time_ms(r))
        .filter(|t| t.is_finite() && *t > 0.0)
        .min_by(f64::total_cmp)
}

/// The records that compete in a verdict: every one but the floor's.
pub fn contenders<'a>(records: &[&'a Record]) -> Vec<&'a Record> {
    records
        .iter()
        .copied()
        .filter(|r| r.method != FLOOR_METHOD)
        .collect()
}

/// `r`'s paired floor on `basis` (`run --paired-floor`), if it has a usable one.
pub fn paired_floor_ms(r: &Record, basis: TimeBasis) -> Option<f64> {
    r.timing
        .as_ref()
        .and_then(|t| t.floor.as_ref())
        .and_then(|f| basis.median(f.wall_ms, f.gpu_ms))
        .filter(|t| t.is_finite() && *t > 0.0)
}

/// One configuration's cost and error; `index` points back into the caller's list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    pub index: usize,
    /// Frame time (ms) as its scene's [`Clock`] compares it.
    pub time: f64,
    /// The metric the points were made for (a fraction).
    pub error: f64,
}

/// In-scatter relative RMSE of a record, if it was scored (kept for the CLI's `reproduce`
/// tables, which print that column by name; verdicts use [`crate::metric::verdict_error`]).
pub fn inscatter_error(r: &Record) -> Option<f64> {
    Metric::RelRmse.of(r)
}

/// [`points_by`] under the verdict metric ([`crate::metric::verdict_error`]).
pub fn points(records: &[&Record], clock: Clock) -> Vec<Point> {
    points_by(records, clock, Metric::Verdict)
}

/// The (time, error) point of every ok record with finite time and `metric`, indexed into
/// `records`, its time the one `clock` compares it on ([`Clock::time_ms`]). Skipped and
/// failed records have no meaningful cost or error and are left out.
pub fn points_by(records: &[&Record], clock: Clock, metric: Metric) -> Vec<Point> {
    records
        .iter()
        .enumerate()
        .filter(|(_, r)| r.status == Status::Ok)
        .filter_map(|(index, r)| {
            let time = clock.time_ms(r)?;
            let error = metric.of(r)?;
            (time.is_finite() && error.is_finite()).then_some(Point { index, time, error })
        })
        .collect()
}

/// The Pareto front of `points` (minimising both time and error), sorted by increasing time
/// (and so by decreasing error). A point is on the front when no other point is at least
/// as good in both and strictly better in one. Of exact duplicates only the first is kept,
/// so the front has no repeated positions. Non-finite points are ignored.
pub fn pareto_front(points: &[Point]) -> Vec<Point> {
    let mut sorted: Vec<Point> = points
        .iter()
        .copied()
        .filter(|p| p.time.is_finite() && p.error.is_finite())
        .collect();
    // By time, then by error, then by input order (stable), so the sweep below sees the
    // cheapest of equally fast points first.
    sorted.sort_by(|a, b| a.time.total_cmp(&b.time).then(a.error.total_cmp(&b.error)));
    let mut front: Vec<Point> = Vec::new();
    for p in sorted {
        // Everything before `p` is at most as fast; `p` survives only if it is strictly
        // more accurate than the best of them (equally fast points arrive most accurate
        // first, so a later one with the same time never gets in).
        if front.last().is_none_or(|best| p.error < best.error) {
            front.push(p);
        }
    }
    front
}

/// The fastest point whose error is within `budget` (ties on time go to the lower error,
/// then to the earlier point); `None` when no point meets it.
pub fn cheapest_under_budget(points: &[Point], budget: f64) -> Option<Point> {
    points
        .iter()
        .copied()
        .filter(|p| p.error <= budget && p.time.is_finite())
        .min_by(|a, b| {
            a.time
                .total_cmp(&b.time)
                .then(a.error.total_cmp(&b.error))
                .then(a.index.cmp(&b.index))
        })
}

/// Items in order of first appearance, without repeats.
pub fn ordered<'a>(items: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in items {
        if !out.iter().any(|o| o == s) {
            out.push(s.to_string());
        }
    }
    out
}

/// The run's records of `scene`, in the run's order.
pub fn scene_records<'a>(results: &'a harness::results::Results, scene: &str) -> Vec<&'a Record> {
    results
        .records
        .iter()
        .filter(|r| r.scene == scene)
        .collect()
}

/// The run's scenes in order of first appearance.
pub fn scene_names(results: &harness::results::Results) -> Vec<String> {
    ordered(results.records.iter().map(|r| r.scene.as_str()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[(f64, f64)]) -> Vec<Point> {
        v.iter()
            .enumerate()
            .map(|(index, &(time, error))| Point { index, time, error })
            .collect()
    }

    fn indices(v: &[Point]) -> Vec<usize> {
        v.iter().map(|p| p.index).collect()
    }

    /// Brute force: a point is on the front iff nothing dominates it.
    fn dominated(p: &Point, all: &[Point]) -> bool {
        all.iter().any(|q| {
            q.time <= p.time && q.error <= p.error && (q.time < p.time || q.error < p.error)
        })
    }

    #[test]
    fn front_of_a_hand_made_set() {
        // 0 (1, 0.5) fast and rough; 1 (2, 0.6) is slower AND worse than 0 → dominated;
        // 2 (3, 0.1) on the front; 3 (3, 0.2) ties 2 on time but is worse → dominated;
        // 4 (10, 0.01) on the front; 5 (20, 0.01) same error, slower → dominated;
        // 6 (0.5, 2.0) the fastest → on the front.
        let p = pts(&[
            (1.0, 0.5),
            (2.0, 0.6),
            (3.0, 0.1),
            (3.0, 0.2),
            (10.0, 0.01),
            (20.0, 0.01),
            (0.5, 2.0),
        ]);
        let front = pareto_front(&p);
        assert_eq!(indices(&front), vec![6, 0, 2, 4]);
        // Agrees with the brute-force definition.
        let expected: Vec<usize> = p
            .iter()
            .filter(|q| !dominated(q, &p))
            .map(|q| q.index)
            .collect();
        let mut got = indices(&front);
        got.sort();
        assert_eq!(got, expected);
        // Sorted by time, errors strictly decreasing.
        for w in front.windows(2) {
            assert!(w[0].time < w[1].time && w[0].error > w[1].error);
        }
    }

    #[test]
    fn front_matches_brute_force_on_a_grid() {
        // A deterministic scatter (LCG) with many ties, compared with the O(n²) definition.
        let mut s: u64 = 12345;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 33) % 8) as f64 + 1.0
        };
        let raw: Vec<(f64, f64)> = (0..200).map(|_| (next(), next())).collect();
        let p = pts(&raw);
        let front = pareto_front(&p);
        for q in &p {
            let on = front.iter().any(|f| f.time == q.time && f.error == q.error);
            assert_eq!(on, !dominated(q, &p), "point {q:?}");
        }
        // No duplicate positions.
        for (i, a) in front.iter().enumerate() {
            for b in &front[i + 1..] {
                assert!(a.time != b.time || a.error != b.error);
            }
        }
    }

    #[test]
    fn front_ignores_non_finite_and_handles_empty() {
        assert!(pareto_front(&[]).is_empty());
        let p = pts(&[(f64::NAN, 0.1), (1.0, f64::INFINITY), (2.0, 0.3)]);
        assert_eq!(indices(&pareto_front(&p)), vec![2]);
    }

    #[test]
    fn cheapest_under_each_budget() {
        let p = pts(&[
            (1.0, 0.5),   // never within budget
            (4.0, 0.08),  // cheapest under 10 %
            (6.0, 0.04),  // cheapest under 5 %
            (5.0, 0.09),  // within 10 % but slower than index 1
            (30.0, 0.01), // exactly at 1 %: counts
            (50.0, 0.005),
        ]);
        let pick = |b| cheapest_under_budget(&p, b).map(|q| q.index);
        assert_eq!(pick(0.10), Some(1));
        assert_eq!(pick(0.05), Some(2));
        assert_eq!(pick(0.01), Some(4));
        assert_eq!(pick(0.001), None);
        assert_eq!(cheapest_under_budget(&[], 1.0), None);
        // The answer is always a front point (nothing faster is also within budget).
        let front = pareto_front(&p);
        for b in BUDGETS {
            if let Some(c) = cheapest_under_budget(&p, b) {
                assert!(front.iter().any(|f| f.index == c.index), "budget {b}");
            }
        }
    }

    /// A paired run's clock, by hand: paired floors 2, 4, 8 and 6 ms (median 5 ms) beside
    /// records of 4, 4, 24 and 6 ms; the floor record (3 ms) has none, and one record (9 ms)
    /// was timed without a pair, so it divides by the floor record: 3.00×, 15 ms on the
    /// paired scale.
    #[test]
    fn a_paired_clock_divides_each_record_by_its_own_floor() {
        use crate::fixture::synthetic::{Measured, paired_floor, record};
        let none = harness::method::Params::new();
        let rec = |method: &str, time_ms: f64, floor: Option<f64>| {
            let mut r = record(
                "s",
                method,
                &none,
                Some(Measured {
                    time_ms,
                    headline: 0.1,
                }),
            );
            r.timing.as_mut().expect("timed").floor = floor.map(paired_floor);
            r
        };
        let records = [
            rec(FLOOR_METHOD, 3.0, None),
            rec("a", 4.0, Some(2.0)),
            rec("b", 4.0, Some(4.0)),
            rec("c", 24.0, Some(8.0)),
            rec("d", 6.0, Some(6.0)),
            rec("alone", 9.0, None),
        ];
        let refs: Vec<&Record> = records.iter().collect();
        let clock = Clock::for_records(&refs);
        assert_eq!(clock.floor_ms, Some(5.0));
        assert!(clock.paired);
        let at = |i: usize| (clock.time_ms(refs[i]), clock.floor_ratio(refs[i]));
        assert_eq!(at(1), (Some(10.0), Some(2.0)));
        assert_eq!(at(2), (Some(5.0), Some(1.0)));
        assert_eq!(at(3), (Some(15.0), Some(3.0)));
        assert_eq!(at(5), (Some(15.0), Some(3.0)));
        // The ratio is the compared time over the scene's floor, for every record.
        for r in &refs[1..] {
            let (t, x) = (clock.time_ms(r).unwrap(), clock.floor_ratio(r).unwrap());
            assert!((t / 5.0 - x).abs() < 1e-12, "{}", r.method);
        }
        // Without paired floors nothing is corrected: the floor record is the floor.
        let plain: Vec<Record> = [(FLOOR_METHOD, 3.0), ("a", 4.0), ("b", 9.0)]
            .iter()
            .map(|&(m, t)| rec(m, t, None))
            .collect();
        let refs: Vec<&Record> = plain.iter().collect();
        let clock = Clock::for_records(&refs);
        assert_eq!((clock.floor_ms, clock.paired), (Some(3.0), false));
        assert_eq!(clock.time_ms(refs[2]), Some(9.0));
        assert_eq!(clock.floor_ratio(refs[2]), Some(3.0));
    }

    #[test]
    fn cheapest_breaks_time_ties_by_error() {
        let p = pts(&[(2.0, 0.04), (2.0, 0.02)]);
        assert_eq!(cheapest_under_budget(&p, 0.05).map(|q| q.index), Some(1));
    }
}
