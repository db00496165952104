//! The tune's verdicts (ARCHITECTURE §4.6): per scene and budget, the winner (the timed
//! candidate under the budget of lowest ratio), the runner-up (the best of another method),
//! whether the two are separable at 95 %, and the tie (every other method's candidate whose
//! interval overlaps the winner's); which candidates still need timing; the summary count with
//! the range the intervals allow.

use serde::{Deserialize, Serialize};

use super::interval::Interval;
use crate::knobs::Params;

/// Careful timing stops for a candidate once its interval is within ±5 %.
pub const TARGET_HALF_WIDTH: f64 = 0.05;

/// A carefully timed configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Timed {
    pub method: String,
    pub params: Params,
    /// In-scatter headline (the verdict metric), total headline, mean ratio.
    pub error: f64,
    pub total_error: f64,
    pub mean_ratio: Option<f64>,
    /// The floor ratio and its interval; None until it has pairs.
    pub ratio: Option<Interval>,
    /// The configuration's knobs off its method's defaults (`knob=value …`, or `defaults`).
    pub knobs: String,
    /// Why it could not be timed, if it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

/// One scene's verdict under one budget. Indices are into the scene's candidates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BudgetVerdict {
    pub budget: f64,
    pub winner: Option<usize>,
    pub runner_up: Option<usize>,
    /// The winner's and runner-up's intervals do not overlap (true with no runner-up).
    pub separable: bool,
    /// Candidates of other methods inseparable from the winner (empty: a clear winner).
    pub tie: Vec<usize>,
}

fn eligible(c: &Timed, budget: f64) -> Option<Interval> {
    c.ratio.filter(|_| c.failed.is_none() && c.error <= budget)
}

/// The verdict of `candidates` under `budget`.
pub fn decide(candidates: &[Timed], budget: f64) -> BudgetVerdict {
    let mut order: Vec<(usize, Interval)> = candidates
        .iter()
        .enumerate()
        .filter_map(|(i, c)| Some((i, eligible(c, budget)?)))
        .collect();
    order.sort_by(|a, b| a.1.estimate.total_cmp(&b.1.estimate));
    let Some(&(w, wi)) = order.first() else {
        return BudgetVerdict {
            budget,
            winner: None,
            runner_up: None,
            separable: true,
            tie: Vec::new(),
        };
    };
    let others = || {
        order
            .iter()
            .filter(|(i, _)| candidates[*i].method != candidates[w].method)
    };
    let runner_up = others().next().copied();
    BudgetVerdict {
        budget,
        winner: Some(w),
        runner_up: runner_up.map(|r| r.0),
        separable: runner_up.is_none_or(|(_, ri)| wi.separates(&ri)),
        tie: others()
            .filter(|(_, ri)| !wi.separates(ri))
            .map(|r| r.0)
            .collect(),
    }
}

/// Which candidates need more timing: those under some budget whose interval is wider than
/// [`TARGET_HALF_WIDTH`] and overlaps that budget's current winner's (the winner included).
/// A candidate beaten with 95 % confidence, or over every budget, is settled.
pub fn open(candidates: &[Timed], budgets: &[f64]) -> Vec<bool> {
    let mut out = vec![false; candidates.len()];
    for &b in budgets {
        let v = decide(candidates, b);
        let Some(w) = v.winner else { continue };
        let wi = candidates[w].ratio.expect("a winner is timed");
        for (i, c) in candidates.iter().enumerate() {
            let Some(ci) = eligible(c, b) else { continue };
            let wide = ci.half_width() > TARGET_HALF_WIDTH || wi.half_width() > TARGET_HALF_WIDTH;
            if !ci.separates(&wi) && wide && (i == w || ci.half_width() > TARGET_HALF_WIDTH) {
                out[i] = true;
            }
        }
    }
    out
}

/// "Within `limit`× the floor under a budget on k of n scenes", with the range the
/// intervals allow.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Count {
    pub budget: f64,
    pub limit: f64,
    /// Scenes whose winner's ratio is within the limit.
    pub k: usize,
    /// Scenes where the winner's whole interval is within it (the count's lower end).
    pub low: usize,
    /// Scenes where some candidate's interval under the budget reaches below it (upper end).
    pub high: usize,
    /// Scenes tuned.
    pub n: usize,
}

/// The count over scenes, each given as its candidates.
pub fn count(scenes: &[&[Timed]], budget: f64, limit: f64) -> Count {
    let mut c = Count {
        budget,
        limit,
        k: 0,
        low: 0,
        high: 0,
        n: scenes.len(),
    };
    for cands in scenes {
        let v = decide(cands, budget);
        let Some(w) = v.winner.and_then(|w| cands[w].ratio) else {
            continue;
        };
        c.k += usize::from(w.estimate <= limit);
        c.low += usize::from(w.high <= limit);
        let reach = cands.iter().filter_map(|x| eligible(x, budget));
        c.high += usize::from(reach.into_iter().any(|i| i.low <= limit));
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timed(method: &str, error: f64, est: f64, half: f64) -> Timed {
        Timed {
            method: method.into(),
            params: Params::new(),
            error,
            total_error: error,
            mean_ratio: Some(1.0),
            ratio: Some(Interval {
                estimate: est,
                low: est * (1.0 - half),
                high: est * (1.0 + half),
                n: 20,
                rounds: 5,
            }),
            knobs: "defaults".into(),
            failed: None,
        }
    }

    #[test]
    fn a_clear_winner_an_inseparable_tie_and_none_under_the_budget() {
        let c = vec![
            timed("a", 0.005, 1.5, 0.03),
            timed("b", 0.008, 1.8, 0.03),
            timed("a", 0.002, 1.55, 0.03),
            timed("c", 0.03, 1.1, 0.03),
        ];
        let v = decide(&c, 0.01);
        assert_eq!(
            (v.winner, v.runner_up, v.separable),
            (Some(0), Some(1), true)
        );
        assert!(v.tie.is_empty());
        // Under 5 %: c is cheapest; a's interval does not overlap it.
        let v = decide(&c, 0.05);
        assert_eq!((v.winner, v.runner_up), (Some(3), Some(0)));
        let tied = vec![timed("a", 0.005, 1.5, 0.05), timed("b", 0.005, 1.52, 0.05)];
        let v = decide(&tied, 0.01);
        assert!(!v.separable);
        assert_eq!(v.tie, vec![1]);
        let v = decide(&c, 0.001);
        assert_eq!((v.winner, v.separable), (None, true));
    }

    #[test]
    fn open_keeps_timing_only_where_the_verdict_is_open() {
        // a and b overlap and are wide: both open; d is beaten for sure; e is over budget.
        let c = vec![
            timed("a", 0.005, 1.5, 0.10),
            timed("b", 0.005, 1.6, 0.10),
            timed("d", 0.005, 3.0, 0.10),
            timed("e", 0.5, 0.9, 0.30),
        ];
        assert_eq!(open(&c, &[0.01]), vec![true, true, false, false]);
        // Narrow overlapping intervals are a tie: settled.
        let t = vec![timed("a", 0.005, 1.5, 0.02), timed("b", 0.005, 1.52, 0.02)];
        assert_eq!(open(&t, &[0.01]), vec![false, false]);
    }

    #[test]
    fn the_count_and_its_range() {
        let s1 = vec![timed("a", 0.005, 1.5, 0.05)]; // within 2× for sure
        let s2 = vec![timed("a", 0.005, 1.95, 0.05)]; // estimate in, interval straddles
        let s3 = vec![timed("a", 0.005, 2.05, 0.05), timed("b", 0.005, 2.2, 0.2)]; // out, could be in
        let s4 = vec![timed("a", 0.02, 1.0, 0.05)]; // nothing under 1 %
        let c = count(&[&s1, &s2, &s3, &s4], 0.01, 2.0);
        assert_eq!((c.k, c.low, c.high, c.n), (2, 1, 3, 4));
    }
}
