//! The screening search (ARCHITECTURE §4.6): a local search over every method's joint knob
//! space, for every budget at once, on the exact error and a cheap estimate of cost.
//!
//! Each method starts at its defaults. Then, step by step, one evaluated configuration is
//! *expanded*: all its neighbours ([`Space::neighbours`]: one knob one step; in a space of at
//! most [`EXHAUSTIVE_MAX`] configurations, all of them) are evaluated. Per method and budget b, the configuration to expand is
//! - the method's **incumbent** under b (its cheapest configuration under b), or one within
//!   [`MARGIN`] of its cost among its [`PLATEAU`] cheapest under b, not yet expanded: a
//!   neighbour may be cheaper and still under b;
//! - else the **closest miss**: of its configurations over b whose *charged cost*,
//!   cost × error / b, is within the same margin of the incumbent's cost (all of them before it
//!   has one), the one of lowest charged cost: a neighbour may cross the budget cheaply.
//!
//! Of these proposals, the step takes the one of the method that stands best under its budget:
//! its best charged cost, cost × max(1, error / b), over the same figure of the best method, times 1 + (its evaluations so far) / [`FAIR_SHARE`] so that the time is
//! shared out among methods that stand close. Methods far behind (over [`STANDING_LIMIT`]) are
//! not expanded. The walk
//! from an incumbent along the budget's edge, through closest misses, reaches combinations of
//! knobs that no one-knob sweep from the defaults contains. The margin absorbs the noise of a
//! one-pair cost. The search ends when nothing is left to expand or the evaluator says stop.

use std::collections::BTreeSet;

use super::space::{EXHAUSTIVE_MAX, Space};
use crate::knobs::Params;

/// Configurations within this fraction of an incumbent's cost count as tied with it (the
/// one-pair estimate's noise).
pub const MARGIN: f64 = 0.2;
/// A method's standing is charged one more for every this many of its evaluations.
pub const FAIR_SHARE: f64 = 4.0;
/// Of a method's points under a budget, only its this many cheapest are expanded as near
/// the incumbent.
pub const PLATEAU: usize = 3;
/// Methods standing more than this many times behind a budget's best are not expanded.
pub const STANDING_LIMIT: f64 = 4.0;

/// An evaluated configuration of method `method` (an index into the spaces).
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub method: usize,
    pub params: Params,
    /// The verdict error (a fraction), exact.
    pub error: f64,
    /// The cheap cost estimate (a floor ratio), noisy.
    pub cost: f64,
}

/// What the search asks of the benchmark.
pub trait Evaluator {
    /// Error and cost of one configuration; None where it failed (never retried).
    fn evaluate(&mut self, method: usize, params: &Params) -> Option<(f64, f64)>;
    /// Whether to stop now (a time limit).
    fn stop(&mut self) -> bool;
}

/// What a search did.
#[derive(Debug, Default)]
pub struct Log {
    pub points: Vec<Point>,
    /// Evaluations asked for, failed ones included.
    pub evaluations: usize,
    pub expansions: usize,
    /// Whether it ended for want of time rather than of configurations to expand.
    pub stopped: bool,
}

/// Searches `spaces` for the cheapest configuration under each of `budgets`.
pub fn search(spaces: &[Space], budgets: &[f64], eval: &mut dyn Evaluator) -> Log {
    let mut log = Log::default();
    let mut seen: BTreeSet<String> = BTreeSet::new();
    let mut expanded: BTreeSet<String> = BTreeSet::new();
    let mut visit = |log: &mut Log, eval: &mut dyn Evaluator, m: usize, p: Params| {
        if !seen.insert(key(m, &p)) {
            return;
        }
        log.evaluations += 1;
        if let Some((error, cost)) = eval.evaluate(m, &p) {
            log.points.push(Point {
                method: m,
                params: p,
                error,
                cost,
            });
        }
    };
    // Every method's defaults first: the standings need one point of each.
    for (m, s) in spaces.iter().enumerate() {
        if eval.stop() {
            log.stopped = true;
            return log;
        }
        visit(&mut log, eval, m, s.base.clone());
    }
    loop {
        let Some(next) = most_promising(&log.points, &expanded, budgets) else {
            return log;
        };
        let (m, p) = (log.points[next].method, log.points[next].params.clone());
        expanded.insert(key(m, &p));
        log.expansions += 1;
        // A small space is one neighbourhood: its first expansion enumerates it whole.
        let next = if spaces[m].size() <= EXHAUSTIVE_MAX {
            spaces[m].all()
        } else {
            spaces[m].neighbours(&p)
        };
        for q in next {
            if eval.stop() {
                log.stopped = true;
                return log;
            }
            visit(&mut log, eval, m, q);
        }
    }
}

/// The point the next step expands (module doc), if any.
fn most_promising(points: &[Point], expanded: &BTreeSet<String>, budgets: &[f64]) -> Option<usize> {
    let open = |&i: &usize| !expanded.contains(&key(points[i].method, &points[i].params));
    let methods: BTreeSet<usize> = points.iter().map(|p| p.method).collect();
    let mut best: Option<(f64, usize, usize)> = None;
    for &b in budgets {
        let stand: Vec<(usize, f64)> = methods
            .iter()
            .map(|&m| (m, standing(points, m, b)))
            .collect();
        let top = stand.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
        for &(m, s) in &stand {
            let s = s / top;
            if s > STANDING_LIMIT {
                continue;
            }
            // Shared out: each FAIR_SHARE evaluations a method has had count as one more
            // standing, so noise on a plateau cannot keep the best method's walk going forever.
            let spent = points.iter().filter(|p| p.method == m).count() as f64;
            let s = s * (1.0 + spent / FAIR_SHARE);
            let Some((side, i)) = proposal(points, m, b, &open) else {
                continue;
            };
            if best.is_none_or(|(bs, bside, _)| (s, side) < (bs, bside)) {
                best = Some((s, side, i));
            }
        }
    }
    best.map(|(_, _, i)| i)
}

/// How method `m` stands under budget `b`: its best charged cost, cost × max(1, error / b)
/// (under b, the cost itself).
fn standing(points: &[Point], m: usize, b: f64) -> f64 {
    points
        .iter()
        .filter(|p| p.method == m)
        .map(|p| charged(p, b))
        .fold(f64::INFINITY, f64::min)
}

fn charged(p: &Point, b: f64) -> f64 {
    p.cost * (p.error / b).max(1.0)
}

/// Method `m`'s cheapest point under `b`.
fn incumbent(points: &[Point], m: usize, b: f64) -> Option<usize> {
    (0..points.len())
        .filter(|&i| points[i].method == m && points[i].error <= b)
        .min_by(|&x, &y| points[x].cost.total_cmp(&points[y].cost))
}

/// Method `m`'s proposal under `b`: (0, an open point near the incumbent's cost), or (1, the
/// open closest miss).
fn proposal(
    points: &[Point],
    m: usize,
    b: f64,
    open: &dyn Fn(&usize) -> bool,
) -> Option<(usize, usize)> {
    let mine = || {
        (0..points.len())
            .filter(move |&i| points[i].method == m)
            .filter(open)
    };
    let by_cost = |x: &usize, y: &usize| points[*x].cost.total_cmp(&points[*y].cost);
    let cap = incumbent(points, m, b).map_or(f64::INFINITY, |i| points[i].cost * (1.0 + MARGIN));
    // Near the incumbent: among the method's PLATEAU cheapest points under b, so that a plateau
    // of equally good configurations is not walked to its end.
    let mut under: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].method == m && points[i].error <= b)
        .collect();
    under.sort_by(by_cost);
    let near = under
        .into_iter()
        .take(PLATEAU)
        .filter(|i| open(i) && points[*i].cost <= cap)
        .min_by(by_cost);
    if let Some(i) = near {
        return Some((0, i));
    }
    mine()
        .filter(|&i| points[i].error > b && charged(&points[i], b) <= cap)
        .min_by(|x, y| charged(&points[*x], b).total_cmp(&charged(&points[*y], b)))
        .map(|i| (1, i))
}

/// A configuration's identity in the search's sets (knob values are not `Ord`).
fn key(method: usize, p: &Params) -> String {
    format!("{method}:{p:?}")
}

#[cfg(test)]
#[path = "search_tests.rs"]
mod tests;
