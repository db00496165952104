//! A separable surrogate of one method's cost and error over its knob space (ARCHITECTURE
//! §4.6): ln cost and ln error, each fitted as an intercept plus one term per knob value off
//! the defaults, by ridge-regularised least squares over the configurations evaluated so far.
//!
//! Why: the knobs of a method mostly act as factors. `scale=4` divides the cost by about the
//! same amount whatever `samples` is, and `samples=100` halves the error at about the same
//! `scale`. A one-knob move from the defaults measures each factor once, and their product
//! predicts a combination of two moves that a walk one step at a time would reach only through
//! a chain of expansions whose middle steps stand behind. The search evaluates the
//! surrogate's best prediction, one configuration at a time, where it promises less than the
//! method's best so far; every evaluation refits it, so a wrong prediction corrects itself.
//!
//! A value no evaluated configuration has gets its term from its neighbours on an ordered
//! (numeric) axis: interpolated between the nearest measured values on either side, or
//! extrapolated along the line through the two nearest on one side (one only: its term), by
//! position in the axis's sorted values (sweeps are about geometric: a power law in the value).
//! A word's unmeasured value keeps the ridge's 0 (predicted as the default). The search
//! proposes only combinations of measured values ([`Model::predict_measured`]), and uses the
//! filled terms to leave out of an expansion the neighbours predicted far too costly to win.
//!
//! Limits: interactions (a knob that matters only at some value of another) are not modelled.

use super::space::Space;
use crate::knobs::Params;

/// Ridge on the value terms (not the intercept), in units of squared log: small enough that a
/// term seen once is taken almost at its measured size.
pub const RIDGE: f64 = 1e-3;
/// Errors are floored here before the log (exact methods score 0).
pub const ERROR_FLOOR: f64 = 1e-7;

/// The fitted surrogate of one method.
#[derive(Clone, Debug)]
pub struct Model {
    /// Per axis: its name and values, as in the space.
    axes: Vec<(String, Vec<crate::knobs::ParamValue>)>,
    /// Per axis and value: the term filled from its neighbours (module doc), where no
    /// evaluated configuration has the value; None where it was fitted (or is the default's).
    filled: Vec<Vec<Option<(f64, f64)>>>,
    /// Per axis and value: the column of its term, None for the default's value.
    columns: Vec<Vec<Option<usize>>>,
    ln_cost: Vec<f64>,
    ln_error: Vec<f64>,
}

impl Model {
    /// Fits `points`, (params, error, cost) of `space`'s method; None with fewer than two.
    pub fn fit(space: &Space, points: &[(&Params, f64, f64)]) -> Option<Model> {
        if points.len() < 2 {
            return None;
        }
        let axes: Vec<_> = space
            .axes
            .iter()
            .map(|a| (a.name.to_string(), a.values.clone()))
            .collect();
        let mut width = 1;
        let columns: Vec<Vec<Option<usize>>> = space
            .axes
            .iter()
            .map(|a| {
                let base = space.base.get(a.name);
                a.values
                    .iter()
                    .map(|v| {
                        (Some(v) != base).then(|| {
                            width += 1;
                            width - 1
                        })
                    })
                    .collect()
            })
            .collect();
        let filled = columns.iter().map(|c| vec![None; c.len()]).collect();
        let mut m = Model {
            axes,
            filled,
            columns,
            ln_cost: Vec::new(),
            ln_error: Vec::new(),
        };
        let rows: Vec<Vec<usize>> = points.iter().map(|(p, _, _)| m.active(p)).collect();
        let cost: Vec<f64> = points.iter().map(|p| p.2.max(1e-12).ln()).collect();
        let error: Vec<f64> = points.iter().map(|p| p.1.max(ERROR_FLOOR).ln()).collect();
        m.ln_cost = ridge(&rows, &cost, width)?;
        m.ln_error = ridge(&rows, &error, width)?;
        let measured: std::collections::BTreeSet<usize> = rows.iter().flatten().copied().collect();
        for (a, axis) in space.axes.iter().enumerate().filter(|(_, a)| a.ordered) {
            m.fill(a, axis.values.len(), &measured);
        }
        Some(m)
    }

    /// Fills axis `a`'s unmeasured values from its measured ones (module doc).
    fn fill(&mut self, a: usize, levels: usize, measured: &std::collections::BTreeSet<usize>) {
        // (position, (ln error term, ln cost term)) of the measured values and the default's.
        let known: Vec<(usize, (f64, f64))> = (0..levels)
            .filter_map(|i| match self.columns[a][i] {
                None => Some((i, (0.0, 0.0))),
                Some(c) if measured.contains(&c) => Some((i, (self.ln_error[c], self.ln_cost[c]))),
                Some(_) => None,
            })
            .collect();
        for i in 0..levels {
            if known.iter().any(|k| k.0 == i) {
                continue;
            }
            let below: Vec<_> = known.iter().filter(|k| k.0 < i).rev().take(2).collect();
            let above: Vec<_> = known.iter().filter(|k| k.0 > i).take(2).collect();
            let line = |p: &(usize, (f64, f64)), q: &(usize, (f64, f64))| {
                let t = (i as f64 - p.0 as f64) / (q.0 as f64 - p.0 as f64);
                (p.1.0 + t * (q.1.0 - p.1.0), p.1.1 + t * (q.1.1 - p.1.1))
            };
            self.filled[a][i] = match (below.as_slice(), above.as_slice()) {
                ([b, ..], [c, ..]) => Some(line(b, c)),
                ([b, b2], []) => Some(line(b2, b)),
                ([], [c, c2]) => Some(line(c, c2)),
                ([b], []) | ([], [b]) => Some(b.1),
                _ => None,
            };
        }
    }

    /// Predicted (error, cost) of `p`.
    pub fn predict(&self, p: &Params) -> (f64, f64) {
        let (mut e, mut c) = (self.ln_error[0], self.ln_cost[0]);
        for (a, i) in self.levels(p) {
            match (self.filled[a][i], self.columns[a][i]) {
                (Some((fe, fc)), _) => (e, c) = (e + fe, c + fc),
                (None, Some(col)) => (e, c) = (e + self.ln_error[col], c + self.ln_cost[col]),
                (None, None) => {}
            }
        }
        (e.exp(), c.exp())
    }

    /// Predicted (error, cost) of `p` where every value of it was measured (or is a default);
    /// None where one was filled from its neighbours.
    pub fn predict_measured(&self, p: &Params) -> Option<(f64, f64)> {
        let filled = self.levels(p).any(|(a, i)| self.filled[a][i].is_some());
        (!filled).then(|| self.predict(p))
    }

    /// (axis, value position) of `p` on each axis where its value is one of the axis's.
    fn levels<'a>(&'a self, p: &'a Params) -> impl Iterator<Item = (usize, usize)> + 'a {
        self.axes.iter().enumerate().filter_map(|(a, (name, values))| {
            let v = p.get(name)?;
            Some((a, values.iter().position(|x| x == v)?))
        })
    }

    /// The columns active for `p`: the intercept (0) and one per axis off its default.
    fn active(&self, p: &Params) -> Vec<usize> {
        let mut out = vec![0];
        out.extend(self.levels(p).filter_map(|(a, i)| self.columns[a][i]));
        out
    }
}

/// Least squares of `y` on the 0/1 design whose row i has ones at `rows[i]`, with [`RIDGE`] on
/// every column but the intercept (0): the normal equations by Gaussian elimination with
/// partial pivoting. None where they are singular (they are not, with the ridge).
fn ridge(rows: &[Vec<usize>], y: &[f64], width: usize) -> Option<Vec<f64>> {
    let mut a = vec![vec![0.0; width + 1]; width];
    for (r, &yi) in rows.iter().zip(y) {
        for &i in r {
            for &j in r {
                a[i][j] += 1.0;
            }
            a[i][width] += yi;
        }
    }
    for (i, row) in a.iter_mut().enumerate().skip(1) {
        row[i] += RIDGE;
    }
    for col in 0..width {
        let pivot = (col..width).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[pivot][col].abs() < 1e-12 {
            return None;
        }
        a.swap(col, pivot);
        for r in 0..width {
            if r != col {
                let f = a[r][col] / a[col][col];
                let pivot_row = a[col].clone();
                for (x, p) in a[r].iter_mut().zip(&pivot_row).skip(col) {
                    *x -= f * p;
                }
            }
        }
    }
    Some((0..width).map(|i| a[i][width] / a[i][i]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knobs::Knob;

    fn space() -> Space {
        let knob = |name| Knob::int_of(name, 4, &[1, 2, 4, 8, 16]).sweep([1, 2, 8, 16]);
        Space::new("m", vec![knob("x"), knob("y")], &Params::new(), &[]).unwrap()
    }

    fn at(s: &Space, x: i64, y: i64) -> Params {
        let mut p = s.base.clone();
        p.insert("x".into(), x.into());
        p.insert("y".into(), y.into());
        p
    }

    /// A cost and an error that are products of per-knob factors (error 1 / (x·y), cost x·y²),
    /// measured at the defaults and on the two single-knob lines only, predict the off-line
    /// combinations to within the ridge's shrinkage (under 1 %); values never measured are
    /// interpolated and extrapolated along their axis.
    #[test]
    fn a_separable_function_is_predicted_off_the_single_knob_lines() {
        let s = space();
        let f = |x: i64, y: i64| (1.0 / (x * y) as f64, (x * y * y) as f64);
        let measured: Vec<(i64, i64)> = vec![(4, 4), (1, 4), (16, 4), (4, 2), (4, 8)];
        let params: Vec<Params> = measured.iter().map(|&(x, y)| at(&s, x, y)).collect();
        let points: Vec<(&Params, f64, f64)> = measured
            .iter()
            .zip(&params)
            .map(|(&(x, y), p)| {
                let (e, c) = f(x, y);
                (p, e, c)
            })
            .collect();
        let m = Model::fit(&s, &points).unwrap();
        for (x, y) in [(16, 8), (1, 2), (16, 2)] {
            let (e, c) = m.predict(&at(&s, x, y));
            let (te, tc) = f(x, y);
            assert!((e / te - 1.0).abs() < 1e-2, "({x}, {y}): error {e} vs {te}");
            assert!((c / tc - 1.0).abs() < 1e-2, "({x}, {y}): cost {c} vs {tc}");
        }
        // x = 8 was never measured: interpolated between x = 4 and 16 by position (8 is halfway
        // in 1, 2, 4, 8, 16), which for a power law is its value: 1 / 64, 8 · 64.
        let (e, c) = m.predict(&at(&s, 8, 8));
        assert!((e * 64.0 - 1.0).abs() < 1e-2 && (c / 512.0 - 1.0).abs() < 1e-2, "{e} {c}");
        // y = 16 was not either: extrapolated along y = 4, 8 (× 2 per position).
        let (e, c) = m.predict(&at(&s, 4, 16));
        assert!((e * 64.0 - 1.0).abs() < 1e-2 && (c / 1024.0 - 1.0).abs() < 1e-2, "{e} {c}");
        assert!(Model::fit(&s, &points[..1]).is_none());
    }
}
