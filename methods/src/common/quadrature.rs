//! Composite 8-point Gauss–Legendre quadrature, for the tables the methods precompute on the CPU
//! (Biri's Γ and its indirect Γ_L / Γ_P, Sun et al.'s airlight F(u, v)).

/// 8-point Gauss–Legendre nodes and weights on [−1, 1].
const GL8: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_2, 0.101_228_536_290_376_26),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_47),
    (0.960_289_856_497_536_2, 0.101_228_536_290_376_26),
];

/// ∫_a^b f by Gauss–Legendre on `n` equal pieces.
pub fn gauss(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    (0..n)
        .map(|k| {
            let m = a + (k as f64 + 0.5) * h;
            GL8.iter()
                .map(|(x, wt)| wt * f(m + 0.5 * h * x))
                .sum::<f64>()
                * 0.5
                * h
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact for polynomials up to degree 15 on one piece; the weights sum to 2.
    #[test]
    fn integrates_polynomials_of_degree_15_exactly() {
        let f = |x: f64| 3.0 * x.powi(15) - x.powi(8) + 2.0 * x - 1.0;
        let antiderivative = |x: f64| 3.0 * x.powi(16) / 16.0 - x.powi(9) / 9.0 + x * x - x;
        let (a, b) = (-0.7, 1.3);
        let exact = antiderivative(b) - antiderivative(a);
        assert!((gauss(f, a, b, 1) - exact).abs() < 1e-12 * exact.abs().max(1.0));
        assert!((gauss(|_| 1.0, -1.0, 1.0, 1) - 2.0).abs() < 1e-15);
    }
}
