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
//! - and before either, the **surrogate's proposal** ([`super::model`]): of the configurations
//!   within two axes of the method's best charged configuration under b (any values,
//!   [`Space::two_axis_ball`]), the unevaluated one of lowest predicted charged cost, where that
//!   prediction is below the method's best charged cost by more than [`MODEL_GAIN`]. It is
//!   evaluated alone (one configuration, not a neighbourhood): a product of two measured moves
//!   that the walk would reach only through middle steps that stand behind.
//!
//! An expansion leaves out the neighbours the surrogate predicts too costly to win under any
//! budget (charged cost over [`STANDING_LIMIT`] × that budget's best standing): at 512² on
//! lavapipe a 60× configuration costs seconds to time and cannot win.
//!
//! Of these proposals, the step takes the one of the method that stands best under its
//! budget: its best charged cost, cost × max(1, error / b), over the same figure of the best
//! method, times 1 + (its evaluations so far) / [`FAIR_SHARE`] so that the time is shared out
//! among methods that stand close. Methods far behind (over [`STANDING_LIMIT`]; over
//! [`FIRST_LOOK_LIMIT`] for one not yet expanded, whose defaults alone may stand far from what
//! one move gives) are not expanded. The walk from an incumbent along the budget's edge,
//! through closest misses and the surrogate's combinations, reaches combinations of knobs that
//! no one-knob sweep from the defaults contains. The margin absorbs the noise of a one-pair
//! cost. The search ends when nothing is left to expand or the evaluator says stop.

use std::collections::BTreeSet;

use std::collections::HashMap;

use super::model::Model;
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
/// Methods standing more than this many times behind a budget's best are not expanded …
pub const STANDING_LIMIT: f64 = 4.0;
/// … except once, up to this many times, a method not yet expanded.
pub const FIRST_LOOK_LIMIT: f64 = 8.0;
/// The surrogate's proposal is evaluated where it predicts a charged cost below the method's
/// best by more than this fraction.
pub const MODEL_GAIN: f64 = 0.1;

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
    /// Error and cost of one configuration; None where it failed (never retried). Where its
    /// cost comes out over `cost_cap` the evaluator may leave it unscored, error +∞: it cannot
    /// win under any budget (the cap is [`FIRST_LOOK_LIMIT`] × the best standing).
    fn evaluate(&mut self, method: usize, params: &Params, cost_cap: f64) -> Option<(f64, f64)>;
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
    /// Configurations evaluated as the surrogate's proposals.
    pub proposals: usize,
    /// Neighbours left out of expansions as predicted too costly to win.
    pub pruned: usize,
    /// Whether it ended for want of time rather than of configurations to expand.
    pub stopped: bool,
}

/// Searches `spaces` for the cheapest configuration under each of `budgets`.
pub fn search(spaces: &[Space], budgets: &[f64], eval: &mut dyn Evaluator) -> Log {
    let mut walk = Walk {
        log: Log::default(),
        seen: BTreeSet::new(),
        expanded: BTreeSet::new(),
        balls: HashMap::new(),
        budgets: budgets.to_vec(),
    };
    // Every method's defaults first: the standings need one point of each.
    for (m, s) in spaces.iter().enumerate() {
        if !walk.visit(eval, m, s.base.clone()) {
            return walk.log;
        }
    }
    loop {
        let next = match walk.next_step(spaces, budgets) {
            None => return walk.log,
            Some(Step::Try(m, p)) => {
                walk.log.proposals += 1;
                vec![(m, p)]
            }
            Some(Step::Expand(i)) => {
                let (m, p) = (walk.log.points[i].method, walk.log.points[i].params.clone());
                walk.expanded.insert(key(m, &p));
                walk.log.expansions += 1;
                // A small space is one neighbourhood: its first expansion enumerates it whole.
                let next = if spaces[m].size() <= EXHAUSTIVE_MAX {
                    spaces[m].all()
                } else {
                    spaces[m].neighbours(&p)
                };
                let (keep, pruned): (Vec<Params>, Vec<Params>) = {
                    let worth = walk.worth(&spaces[m], m, budgets);
                    next.into_iter().partition(|q| worth(q))
                };
                walk.log.pruned += pruned.len();
                keep.into_iter().map(|q| (m, q)).collect()
            }
        };
        for (m, q) in next {
            if !walk.visit(eval, m, q) {
                return walk.log;
            }
        }
    }
}

/// One step of the search: expand an evaluated point, or evaluate the surrogate's proposal.
enum Step {
    Expand(usize),
    Try(usize, Params),
}

/// The search's state.
struct Walk {
    log: Log,
    seen: BTreeSet<String>,
    expanded: BTreeSet<String>,
    /// The two-axis balls already enumerated, by their centre's key.
    balls: HashMap<String, Vec<Params>>,
    budgets: Vec<f64>,
}

impl Walk {
    /// Evaluates `p` of method `m` unless seen; false where the evaluator said stop.
    fn visit(&mut self, eval: &mut dyn Evaluator, m: usize, p: Params) -> bool {
        if eval.stop() {
            self.log.stopped = true;
            return false;
        }
        if !self.seen.insert(key(m, &p)) {
            return true;
        }
        self.log.evaluations += 1;
        let cap = FIRST_LOOK_LIMIT * self.best_standing();
        if let Some((error, cost)) = eval.evaluate(m, &p, cap) {
            self.log.points.push(Point {
                method: m,
                params: p,
                error,
                cost,
            });
        }
        true
    }

    /// The lowest standing (best charged cost) of any method under any budget; +∞ before one.
    fn best_standing(&self) -> f64 {
        let points = &self.log.points;
        let fold = |b: f64| points.iter().map(|p| charged(p, b)).fold(f64::INFINITY, f64::min);
        self.budgets.iter().map(|&b| fold(b)).fold(f64::INFINITY, f64::min)
    }

    /// Whether a configuration of method `m` may still win: its predicted charged cost under
    /// some budget is within [`STANDING_LIMIT`] of that budget's best standing (always, before
    /// the method has a surrogate).
    fn worth(&self, space: &Space, m: usize, budgets: &[f64]) -> impl Fn(&Params) -> bool {
        let points = &self.log.points;
        let methods: BTreeSet<usize> = points.iter().map(|p| p.method).collect();
        let tops: Vec<(f64, f64)> = budgets
            .iter()
            .map(|&b| {
                let top = methods.iter().map(|&k| standing(points, k, b));
                (b, top.fold(f64::INFINITY, f64::min))
            })
            .collect();
        let model = fit(space, points, m);
        move |q: &Params| {
            let Some(model) = &model else { return true };
            let (error, cost) = model.predict(q);
            tops.iter()
                .any(|&(b, top)| cost * (error / b).max(1.0) <= STANDING_LIMIT * top)
        }
    }

    /// The next step (module doc), if any.
    fn next_step(&mut self, spaces: &[Space], budgets: &[f64]) -> Option<Step> {
        let Walk {
            log,
            seen,
            expanded,
            balls,
            ..
        } = self;
        let points = &log.points;
        let methods: BTreeSet<usize> = points.iter().map(|p| p.method).collect();
        let models: HashMap<usize, Model> = methods
            .iter()
            .filter_map(|&m| Some((m, fit(&spaces[m], points, m)?)))
            .collect();
        let mut best: Option<(f64, usize, Step)> = None;
        for &b in budgets {
            let stand: Vec<(usize, f64)> = methods
                .iter()
                .map(|&m| (m, standing(points, m, b)))
                .collect();
            let top = stand.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
            for &(m, raw) in &stand {
                let looked = points
                    .iter()
                    .any(|p| p.method == m && expanded.contains(&key(m, &p.params)));
                let limit = if looked { STANDING_LIMIT } else { FIRST_LOOK_LIMIT };
                if raw / top > limit {
                    continue;
                }
                // Shared out: each FAIR_SHARE evaluations a method has had count as one more
                // standing, so noise on a plateau cannot keep the best method's walk going.
                let spent = points.iter().filter(|p| p.method == m).count() as f64;
                let s = raw / top * (1.0 + spent / FAIR_SHARE);
                if best.as_ref().is_some_and(|(bs, bside, _)| (*bs, *bside) <= (s, 0)) {
                    continue;
                }
                let tried = models.get(&m).and_then(|model| {
                    let ball = |p: &Params| spaces[m].two_axis_ball(p);
                    surrogate(points, seen, balls, &ball, (m, b), model)
                });
                let step = match tried {
                    Some(p) => Some((0, Step::Try(m, p))),
                    None => {
                        let open =
                            |&i: &usize| !expanded.contains(&key(points[i].method, &points[i].params));
                        proposal(points, m, b, &open).map(|(side, i)| (side + 1, Step::Expand(i)))
                    }
                };
                if let Some((side, step)) = step
                    && best.as_ref().is_none_or(|(bs, bside, _)| (s, side) < (*bs, *bside))
                {
                    best = Some((s, side, step));
                }
            }
        }
        best.map(|(_, _, step)| step)
    }

}

/// The surrogate's proposal for method `m` under `b` (module doc), if it promises enough:
/// drawn from `ball` of the method's best charged point (cached in `balls` by its key).
fn surrogate(
    points: &[Point],
    seen: &BTreeSet<String>,
    balls: &mut HashMap<String, Vec<Params>>,
    ball: &dyn Fn(&Params) -> Vec<Params>,
    (m, b): (usize, f64),
    model: &Model,
) -> Option<Params> {
    let centre = (0..points.len())
        .filter(|&i| points[i].method == m)
        .min_by(|&x, &y| charged(&points[x], b).total_cmp(&charged(&points[y], b)))?;
    let goal = charged(&points[centre], b) / (1.0 + MODEL_GAIN);
    let around = balls
        .entry(key(m, &points[centre].params))
        .or_insert_with(|| ball(&points[centre].params));
    let predicted = |p: &Params| {
        let (error, cost) = model.predict_measured(p)?;
        Some(cost * (error / b).max(1.0))
    };
    around
        .iter()
        .filter(|p| !seen.contains(&key(m, p)))
        .filter_map(|p| Some((predicted(p)?, p)))
        .filter(|(c, _)| *c < goal)
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, p)| p.clone())
}

/// Method `m`'s surrogate fitted on its points.
fn fit(space: &Space, points: &[Point], m: usize) -> Option<Model> {
    // Unscored points (error +∞, cost over the cap) say nothing of the error.
    let mine: Vec<(&Params, f64, f64)> = points
        .iter()
        .filter(|p| p.method == m && p.error.is_finite())
        .map(|p| (&p.params, p.error, p.cost))
        .collect();
    Model::fit(space, &mine)
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
