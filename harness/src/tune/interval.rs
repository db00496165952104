//! The floor ratio of a configuration and its 95 % interval (ARCHITECTURE §4.6), from its
//! interleaved pairs: each pair i gives x_i = ln(method_i / floor_i); the ratio is
//! exp(median x), and its interval the distribution-free interval of the median from order
//! statistics, [x_(k), x_(n+1−k)] with k the largest rank such that P(B ≤ k − 1) ≤ 2.5 % for
//! B ~ Binomial(n, ½). It assumes only that the pairs' log ratios are independent draws of one
//! distribution: no normality, and a few wild frames (a scheduler hiccup) move it by a rank,
//! not by their size. Below 6 pairs no such interval exists and it is unbounded.

use serde::{Deserialize, Serialize};

/// How the interval is computed, as tune.json states it.
pub const DESCRIPTION: &str = "95 % distribution-free interval of the median of ln(method / floor) over interleaved pairs (order statistics, binomial ranks); ratio = exp(median)";

/// The interval's confidence.
pub const CONFIDENCE: f64 = 0.95;

/// A ratio's estimate and its interval.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    pub estimate: f64,
    /// Bounds; 0 and +∞ (serialised as null) where fewer than 6 pairs.
    pub low: f64,
    #[serde(with = "infinite_as_null")]
    pub high: f64,
    /// Pairs it rests on.
    pub n: usize,
}

impl Interval {
    /// exp(median) of `logs` and its interval; None for no samples.
    pub fn of_logs(logs: &[f64]) -> Option<Interval> {
        let mut x: Vec<f64> = logs.iter().copied().filter(|v| v.is_finite()).collect();
        if x.is_empty() {
            return None;
        }
        x.sort_by(f64::total_cmp);
        let n = x.len();
        let median = if n % 2 == 1 {
            x[n / 2]
        } else {
            0.5 * (x[n / 2 - 1] + x[n / 2])
        };
        let (low, high) = match median_rank(n) {
            Some(k) => (x[k - 1].exp(), x[n - k].exp()),
            None => (0.0, f64::INFINITY),
        };
        Some(Interval {
            estimate: median.exp(),
            low,
            high,
            n,
        })
    }

    /// The larger relative distance from the estimate to a bound (0.05: ±5 %).
    pub fn half_width(&self) -> f64 {
        (self.high / self.estimate - 1.0).max(1.0 - self.low / self.estimate)
    }

    /// Whether the two intervals do not overlap (a conservative test of a difference).
    pub fn separates(&self, other: &Interval) -> bool {
        self.high < other.low || other.high < self.low
    }

    pub fn contains(&self, x: f64) -> bool {
        (self.low..=self.high).contains(&x)
    }
}

/// The rank k (1-based) of the median's interval for `n` samples: the largest k with
/// P(Binomial(n, ½) ≤ k − 1) ≤ (1 − CONFIDENCE) / 2; None where even k = 1 misses it.
pub fn median_rank(n: usize) -> Option<usize> {
    let tail = (1.0 - CONFIDENCE) / 2.0;
    // ln P(B = j), from j = 0 up; the cumulative sum in probability space (n ≤ ~10⁵ frames).
    let mut ln_pmf = -(n as f64) * std::f64::consts::LN_2;
    let mut cdf = 0.0;
    let mut k = None;
    for j in 0..n {
        cdf += ln_pmf.exp();
        if cdf > tail {
            break;
        }
        k = Some(j + 1);
        ln_pmf += ((n - j) as f64).ln() - ((j + 1) as f64).ln();
    }
    k.filter(|&k| k <= n.div_ceil(2))
}

mod infinite_as_null {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        if x.is_finite() {
            s.serialize_f64(*x)
        } else {
            s.serialize_none()
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ranks against the binomial tail computed here by exact summation, and the known
    /// table values (n = 6: k = 1; n = 10: k = 2; n = 20: k = 6; n = 100: k = 40).
    #[test]
    fn median_ranks_match_the_binomial_tail() {
        assert_eq!(median_rank(5), None);
        assert_eq!(median_rank(6), Some(1));
        assert_eq!(median_rank(10), Some(2));
        assert_eq!(median_rank(20), Some(6));
        assert_eq!(median_rank(100), Some(40));
        for n in 6..200usize {
            let k = median_rank(n).unwrap();
            let cdf = |m: usize| -> f64 {
                (0..=m)
                    .map(|j| {
                        let ln_c: f64 = (0..j)
                            .map(|i| ((n - i) as f64).ln() - ((i + 1) as f64).ln())
                            .sum();
                        (ln_c - n as f64 * std::f64::consts::LN_2).exp()
                    })
                    .sum()
            };
            assert!(cdf(k - 1) <= 0.025 + 1e-12, "n {n} k {k}");
            assert!(cdf(k) > 0.025, "n {n} k {k} is not the largest");
        }
    }

    /// Coverage by simulation: for log-normal pair ratios with a known median, the interval
    /// holds the true ratio in ≈ 95 % or more of 2000 seeded trials (the order-statistic
    /// interval is conservative: at least 95 %).
    #[test]
    fn the_interval_covers_the_true_ratio_at_least_95_percent() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let truth = 1.5f64;
        for n in [8usize, 20, 41] {
            let mut covered = 0;
            for _ in 0..2000 {
                let logs: Vec<f64> = (0..n)
                    .map(|_| {
                        // Box–Muller, σ = 0.1.
                        let (u, v) = (uniform().max(1e-300), uniform());
                        truth.ln()
                            + 0.1 * (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
                    })
                    .collect();
                let i = Interval::of_logs(&logs).unwrap();
                covered += usize::from(i.contains(truth));
            }
            let rate = covered as f64 / 2000.0;
            assert!((0.935..=1.0).contains(&rate), "n {n}: coverage {rate}");
        }
    }

    #[test]
    fn too_few_pairs_give_an_unbounded_interval_and_separation_is_overlap() {
        let i = Interval::of_logs(&[0.0, 0.1, 0.2]).unwrap();
        assert_eq!((i.low, i.high), (0.0, f64::INFINITY));
        assert!((i.estimate - 0.1f64.exp()).abs() < 1e-12);
        let a = Interval {
            estimate: 1.0,
            low: 0.95,
            high: 1.05,
            n: 10,
        };
        let b = Interval {
            estimate: 1.2,
            low: 1.1,
            high: 1.3,
            n: 10,
        };
        let c = Interval {
            estimate: 1.08,
            low: 1.04,
            high: 1.12,
            n: 10,
        };
        assert!(a.separates(&b) && b.separates(&a));
        assert!(!a.separates(&c) && !c.separates(&b));
        assert!((a.half_width() - 0.05).abs() < 1e-12);
        let json = serde_json::to_string(&i).unwrap();
        assert!(json.contains("\"high\":null"), "{json}");
        let back: Interval = serde_json::from_str(&json).unwrap();
        assert_eq!(back.high, f64::INFINITY);
    }
}
