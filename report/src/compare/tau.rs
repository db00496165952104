//! Kendall's τ-b: how far two adapters agree on the order of the same configurations' times.
//!
//! τ-b (Kendall 1945) corrects τ for ties: with `n₀ = n(n−1)/2` pairs, `n₁`/`n₂` the pairs tied
//! in the first/second ranking, `n_c`/`n_d` the concordant/discordant pairs (a pair tied in
//! either ranking is neither),
//!
//! ```text
//! τ_b = (n_c − n_d) / sqrt((n₀ − n₁)(n₀ − n₂))
//! ```
//!
//! 1 when both orders agree, −1 when one is the reverse of the other. Undefined (None) with
//! fewer than two items or when one ranking ties everything. [`PairCounts`] add up, so the
//! "pooled" τ of a comparison counts every same-scene pair of every scene once: times of
//! different scenes are never ranked against each other (a scene's cost is not a method's).

use serde::Serialize;

/// The pair counts τ-b is made of; they add up over groups (scenes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct PairCounts {
    /// Items ranked (summed over groups when pooled).
    pub items: u64,
    /// All pairs within a group, `n(n−1)/2` per group.
    pub pairs: u64,
    pub concordant: u64,
    pub discordant: u64,
    /// Pairs tied in the first ranking.
    pub ties_a: u64,
    /// Pairs tied in the second ranking.
    pub ties_b: u64,
}

impl PairCounts {
    /// Counts the pairs of `(a, b)` observations (O(n²): a scene has a few dozen records).
    pub fn of(values: &[(f64, f64)]) -> PairCounts {
        let mut c = PairCounts {
            items: values.len() as u64,
            ..PairCounts::default()
        };
        for (i, &(a1, b1)) in values.iter().enumerate() {
            for &(a2, b2) in &values[i + 1..] {
                c.pairs += 1;
                let (da, db) = (a1.total_cmp(&a2), b1.total_cmp(&b2));
                c.ties_a += u64::from(da.is_eq());
                c.ties_b += u64::from(db.is_eq());
                if !da.is_eq() && !db.is_eq() {
                    if da == db {
                        c.concordant += 1;
                    } else {
                        c.discordant += 1;
                    }
                }
            }
        }
        c
    }

    /// τ-b of the counted pairs; None when undefined (no untied pair in one ranking).
    pub fn tau_b(&self) -> Option<f64> {
        let untied_a = self.pairs - self.ties_a;
        let untied_b = self.pairs - self.ties_b;
        if untied_a == 0 || untied_b == 0 {
            return None;
        }
        let num = self.concordant as f64 - self.discordant as f64;
        Some(num / ((untied_a as f64) * (untied_b as f64)).sqrt())
    }
}

impl std::ops::Add for PairCounts {
    type Output = PairCounts;
    fn add(self, o: PairCounts) -> PairCounts {
        PairCounts {
            items: self.items + o.items,
            pairs: self.pairs + o.pairs,
            concordant: self.concordant + o.concordant,
            discordant: self.discordant + o.discordant,
            ties_a: self.ties_a + o.ties_a,
            ties_b: self.ties_b + o.ties_b,
        }
    }
}

impl std::iter::Sum for PairCounts {
    fn sum<I: Iterator<Item = PairCounts>>(iter: I) -> PairCounts {
        iter.fold(PairCounts::default(), |a, b| a + b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tau(a: &[f64], b: &[f64]) -> Option<f64> {
        let v: Vec<(f64, f64)> = a.iter().copied().zip(b.iter().copied()).collect();
        PairCounts::of(&v).tau_b()
    }

    #[test]
    fn same_order_is_one_and_reverse_is_minus_one() {
        assert_eq!(
            tau(&[1.0, 2.0, 3.0, 4.0], &[10.0, 20.0, 35.0, 90.0]),
            Some(1.0)
        );
        assert_eq!(
            tau(&[1.0, 2.0, 3.0, 4.0], &[4.0, 3.0, 2.0, 1.0]),
            Some(-1.0)
        );
    }

    /// By hand, without ties: a = 1 2 3 4 5, b = 3 1 2 5 4. Of the 10 pairs, the discordant ones
    /// are (1,2), (1,3) and (4,5): τ = (7 − 3) / 10 = 0.4.
    #[test]
    fn a_hand_computed_case_without_ties() {
        let c = PairCounts::of(&[(1., 3.), (2., 1.), (3., 2.), (4., 5.), (5., 4.)]);
        assert_eq!((c.pairs, c.concordant, c.discordant), (10, 7, 3));
        assert!((c.tau_b().unwrap() - 0.4).abs() < 1e-12);
    }

    /// By hand, with ties (τ-b): a = 1 1 2 3, b = 1 2 2 3.
    /// Pairs (i, j): (1,2) tied in a; (1,3) a< b< C; (1,4) C; (2,3) a< b= → tied in b;
    /// (2,4) C; (3,4) C. n₀ = 6, n₁ = 1, n₂ = 1, n_c = 4, n_d = 0:
    /// τ_b = 4 / sqrt(5 · 5) = 0.8 (plain τ-a would say 4/6).
    #[test]
    fn a_hand_computed_case_with_ties_is_tau_b() {
        let c = PairCounts::of(&[(1., 1.), (1., 2.), (2., 2.), (3., 3.)]);
        assert_eq!(
            c,
            PairCounts {
                items: 4,
                pairs: 6,
                concordant: 4,
                discordant: 0,
                ties_a: 1,
                ties_b: 1,
            }
        );
        assert!((c.tau_b().unwrap() - 0.8).abs() < 1e-12);
        // A pair tied in both rankings counts in both tie counts and in neither n_c nor n_d:
        // a = 1 1 2, b = 5 5 6 → n₀ = 3, n₁ = n₂ = 1, n_c = 2: τ_b = 2 / sqrt(2 · 2) = 1.
        assert_eq!(tau(&[1., 1., 2.], &[5., 5., 6.]), Some(1.0));
    }

    #[test]
    fn undefined_with_fewer_than_two_items_or_a_constant_ranking() {
        assert_eq!(tau(&[], &[]), None);
        assert_eq!(tau(&[1.0], &[2.0]), None);
        assert_eq!(tau(&[1.0, 1.0, 1.0], &[1.0, 2.0, 3.0]), None);
    }

    /// Pooling adds the pair counts of the groups: two scenes, one in agreement (3 items, 3
    /// concordant) and one reversed (2 items, 1 discordant): (3 − 1) / sqrt(4 · 4) = 0.5,
    /// while the mean of the scenes' τ would be (1 + −1) / 2 = 0.
    #[test]
    fn pooled_counts_add_over_scenes() {
        let s1 = PairCounts::of(&[(1., 1.), (2., 2.), (3., 3.)]);
        let s2 = PairCounts::of(&[(1., 2.), (2., 1.)]);
        let pooled: PairCounts = [s1, s2].into_iter().sum();
        assert_eq!((pooled.items, pooled.pairs), (5, 4));
        assert_eq!(pooled.tau_b(), Some(0.5));
    }
}
