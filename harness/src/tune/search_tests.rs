use super::*;
use crate::knobs::{Knob, ParamValue};

const VALUES: &[i64] = &[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16];
/// The grid's size.
const GRID: usize = VALUES.len() * VALUES.len();

/// A synthetic method of two knobs x, y in 1..=16 (defaults 4, 4): error 1.5 / (x·y), cost
/// x + 2y. More of either knob lowers the error; y costs twice as much as x.
fn space() -> Space {
    let knob =
        |name| Knob::int_of(name, 4, VALUES).sweep(VALUES.iter().copied().filter(|&v| v != 4));
    Space::new("synthetic", vec![knob("x"), knob("y")], &Params::new(), &[]).unwrap()
}

fn xy(p: &Params) -> (i64, i64) {
    (p["x"].as_i64().unwrap(), p["y"].as_i64().unwrap())
}

fn error(x: i64, y: i64) -> f64 {
    1.5 / (x * y) as f64
}

fn cost(x: i64, y: i64) -> f64 {
    (x + 2 * y) as f64
}

struct Synthetic {
    calls: usize,
}

impl Evaluator for Synthetic {
    fn evaluate(&mut self, _: usize, p: &Params, _: f64) -> Option<(f64, f64)> {
        self.calls += 1;
        let (x, y) = xy(p);
        Some((error(x, y), cost(x, y)))
    }
    fn stop(&mut self) -> bool {
        false
    }
}

/// The cheapest (x, y) under `budget`, by enumerating the grid (independent of the search).
fn exhaustive_best(budget: f64) -> (i64, i64) {
    let all = VALUES
        .iter()
        .flat_map(|&x| VALUES.iter().map(move |&y| (x, y)));
    all.filter(|&(x, y)| error(x, y) <= budget)
        .min_by(|a, b| cost(a.0, a.1).total_cmp(&cost(b.0, b.1)))
        .unwrap()
}

/// The tune's search finds each budget's best configuration although it lies off both
/// single-knob lines through the defaults, in fewer evaluations than the grid has points.
#[test]
fn finds_the_best_configuration_off_every_single_knob_line() {
    let budgets = [0.01, 0.03];
    // Independent check of the premise: neither best is on x = 4 or y = 4.
    let best: Vec<(i64, i64)> = budgets.iter().map(|&b| exhaustive_best(b)).collect();
    assert_eq!(best, vec![(15, 10), (10, 5)]);
    for &(x, y) in &best {
        assert!(x != 4 && y != 4, "({x}, {y}) is on a single-knob line");
    }
    let mut eval = Synthetic { calls: 0 };
    let log = search(&[space()], &budgets, &mut eval);
    for (&b, &want) in budgets.iter().zip(&best) {
        let found = log
            .points
            .iter()
            .filter(|p| p.error <= b)
            .min_by(|p, q| p.cost.total_cmp(&q.cost))
            .map(|p| xy(&p.params));
        assert_eq!(found, Some(want), "budget {b}");
    }
    // The number of evaluations it used: stated, and below the grid's 64.
    eprintln!(
        "search: {} evaluations, {} expansions, {} surrogate proposals (grid: {GRID})",
        log.evaluations, log.expansions, log.proposals
    );
    assert_eq!(log.evaluations, eval.calls);
    // 93 of the 256 at this commit: the walk along the 1 % edge of this flat trade-off (cost
    // x + 2y, error 1.5 / xy) is long; a fifth more is taken as a regression.
    assert!(log.evaluations <= 110, "{} evaluations", log.evaluations);
}

/// A small joint space is enumerated whole at its first expansion; a stop stops at once.
#[test]
fn small_spaces_are_enumerated_and_stop_is_obeyed() {
    let knob = |name| Knob::int_of(name, 1, &[1, 2, 3]).sweep([2, 3]);
    let s = Space::new("small", vec![knob("a"), knob("b")], &Params::new(), &[]).unwrap();
    assert_eq!(s.size(), 9);
    assert_eq!(s.all().len(), 9);
    let mut eval = Synthetic { calls: 0 };
    struct Xy<'a>(&'a mut Synthetic);
    impl Evaluator for Xy<'_> {
        fn evaluate(&mut self, _: usize, p: &Params, _: f64) -> Option<(f64, f64)> {
            self.0.calls += 1;
            let (a, b) = (p["a"].as_i64().unwrap(), p["b"].as_i64().unwrap());
            Some((error(a, b), cost(a, b)))
        }
        fn stop(&mut self) -> bool {
            false
        }
    }
    let log = search(&[s], &[0.05], &mut Xy(&mut eval));
    assert_eq!(log.evaluations, 9);
    struct Stopped;
    impl Evaluator for Stopped {
        fn evaluate(&mut self, _: usize, _: &Params, _: f64) -> Option<(f64, f64)> {
            panic!("evaluated after stop")
        }
        fn stop(&mut self) -> bool {
            true
        }
    }
    let log = search(&[space()], &[0.05], &mut Stopped);
    assert!(log.stopped && log.points.is_empty());
}

/// Neighbours move one knob one step, and a value's requirement comes with it.
#[test]
fn neighbours_take_one_step_and_bring_what_a_value_requires() {
    let s = space();
    let n: Vec<(i64, i64)> = s.neighbours(&s.base).iter().map(xy).collect();
    assert_eq!(n, vec![(3, 4), (5, 4), (4, 3), (4, 5)]);
    let knobs = vec![
        Knob::choice("accumulate", "float", &["float", "unorm8"])
            .sweep(["unorm8"])
            .requires("unorm8", "resolve", "stencil"),
        Knob::choice("resolve", "per-pixel", &["per-pixel", "stencil"]).sweep(["stencil"]),
    ];
    let s = Space::new("r", knobs, &Params::new(), &[]).unwrap();
    let n = s.neighbours(&s.base);
    let unorm8 = n
        .iter()
        .find(|p| p["accumulate"] == ParamValue::from("unorm8"))
        .expect("the requirement is met by moving resolve too");
    assert_eq!(unorm8["resolve"], ParamValue::from("stencil"));
    // Excluded knobs stay at their defaults.
    let s = Space::new("r", s_knobs(), &Params::new(), &["resolve"]).unwrap();
    assert!(s.neighbours(&s.base).is_empty());
}

fn s_knobs() -> Vec<Knob> {
    vec![
        Knob::choice("accumulate", "float", &["float", "unorm8"])
            .sweep(["unorm8"])
            .requires("unorm8", "resolve", "stencil"),
        Knob::choice("resolve", "per-pixel", &["per-pixel", "stencil"]).sweep(["stencil"]),
    ]
}

/// The cost cap: the first configuration is evaluated with no cap (+∞); once one is under a
/// budget, every later call gets FIRST_LOOK_LIMIT × the best standing. A configuration left
/// unscored (error +∞) is never an incumbent, never expanded, and does not break the
/// surrogate's fit.
#[test]
fn the_cost_cap_follows_the_best_standing_and_unscored_points_are_inert() {
    struct Capped {
        caps: Vec<f64>,
    }
    impl Evaluator for Capped {
        fn evaluate(&mut self, m: usize, p: &Params, cap: f64) -> Option<(f64, f64)> {
            self.caps.push(cap);
            let (x, y) = xy(p);
            // Method 1 costs 100× method 0: over every cap, left unscored as an evaluator may.
            let cost = cost(x, y) * if m == 1 { 100.0 } else { 1.0 };
            Some((if cost > cap { f64::INFINITY } else { error(x, y) }, cost))
        }
        fn stop(&mut self) -> bool {
            self.caps.len() >= 60
        }
    }
    let mut eval = Capped { caps: Vec::new() };
    let log = search(&[space(), space()], &[0.1], &mut eval);
    assert_eq!(eval.caps[0], f64::INFINITY);
    // The defaults (4, 4) of method 0: cost 12, error 0.094 ≤ 0.1, so the cap is 8 × 12.
    assert_eq!(eval.caps[1], FIRST_LOOK_LIMIT * 12.0);
    let unscored: Vec<&Point> = log.points.iter().filter(|p| p.method == 1).collect();
    assert_eq!(unscored.len(), 1, "method 1's defaults only: never expanded");
    assert!(unscored[0].error.is_infinite());
    assert!(log.points.iter().any(|p| p.method == 0 && p.error <= 0.1 && p.cost < 12.0));
}
