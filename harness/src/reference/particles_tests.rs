//! Tests of `particles.rs`.

use super::*;

fn cloud() -> ParticleField {
    let s = scenes::library::resolve("cloud-plane").unwrap();
    ParticleField::new(s.medium().particles().unwrap())
}

/// A deterministic stream of numbers in [0, 1).
fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / (1u64 << 53) as f64
    }
}

/// The gathered list must hold every sphere a leg from the segment can cross: its sums
/// equal the BVH's over the whole field at points all along the segment.
#[test]
fn gathered_legs_give_the_fields_optical_depth() {
    let field = cloud();
    let mut rnd = rng(7);
    let mut list = LegList::default();
    let (mut checked, mut nonzero) = (0, 0);
    for case in 0..200 {
        let a = DVec3::new(rnd() * 6.0 - 3.0, rnd() * 3.0 + 0.5, rnd() * 4.0 - 2.0);
        let b = a + (DVec3::new(rnd(), rnd(), rnd()) - 0.5) * 0.6;
        let toward = if case % 2 == 0 {
            Toward::Direction(DVec3::new(0.4, 1.0, 0.5).normalize())
        } else {
            Toward::Point(DVec3::new(rnd() * 8.0 - 4.0, 5.0, rnd() * 4.0 - 2.0))
        };
        list.clear();
        field.gather_legs(a, b, toward, &mut list);
        assert!(list.len() < field.spheres.len() / 4, "a short list");
        for k in 0..=20 {
            let x = a + (b - a) * (k as f64 / 20.0);
            let (u, smax) = match toward {
                Toward::Direction(l) => (l, f64::INFINITY),
                Toward::Point(lp) => ((lp - x).normalize(), (lp - x).length()),
            };
            let want = field.optical_depth(x, u, 0.0, smax);
            let got = leg_depth(list.view(0, list.len()), x, u, smax);
            assert!(
                (got - want).abs() <= 1e-12 * want.max(1.0),
                "case {case} k {k}: {got} vs {want}"
            );
            checked += 1;
            nonzero += (want > 0.1) as usize;
        }
    }
    assert!(
        checked == 200 * 21 && nonzero > 500,
        "{nonzero} legs cross the cloud"
    );
}

/// Every graze root is a tangency (centre-to-leg distance = radius), and every change of
/// "the leg crosses this sphere" seen by dense sampling lies next to a root.
#[test]
fn leg_grazes_are_the_tangencies() {
    let field = cloud();
    let mut rnd = rng(11);
    let mut list = LegList::default();
    let mut roots = Vec::new();
    let mut found = 0;
    for case in 0..40 {
        let o = DVec3::new(rnd() * 6.0 - 3.0, rnd() * 3.0 + 0.5, rnd() * 4.0 - 2.0);
        let d = (DVec3::new(rnd(), rnd(), rnd()) - 0.5).normalize();
        let (lo, hi) = (0.0, 0.5);
        let toward = if case % 2 == 0 {
            Toward::Direction(DVec3::new(-0.3, 1.0, 0.2).normalize())
        } else {
            Toward::Point(DVec3::new(1.0, 6.0, -1.0))
        };
        list.clear();
        field.gather_legs(o, o + d * hi, toward, &mut list);
        let legs = list.view(0, list.len());
        // Distance from centre k to the leg's line through o + t d, minus the radius.
        let gap = |k: usize, t: f64| {
            let x = o + d * t;
            let u = match toward {
                Toward::Direction(l) => l,
                Toward::Point(lp) => (lp - x).normalize(),
            };
            let q = legs.center(k) - x;
            (q - u * q.dot(u)).length() - legs.r2[k].sqrt()
        };
        for k in 0..list.len() {
            roots.clear();
            leg_grazes(list.view(k, k + 1), o, d, lo, hi, toward, &mut roots);
            for &t in &roots {
                assert!(
                    gap(k, t).abs() < 1e-9,
                    "case {case}: root {t} off by {}",
                    gap(k, t)
                );
                found += 1;
            }
            let n = 2000;
            for s in 0..n {
                let (t0, t1) = (hi * s as f64 / n as f64, hi * (s + 1) as f64 / n as f64);
                if (gap(k, t0) < 0.0) != (gap(k, t1) < 0.0) {
                    assert!(
                        roots.iter().any(|&r| r >= t0 - 1e-12 && r <= t1 + 1e-12),
                        "case {case}: sign change in [{t0}, {t1}] without a root: {roots:?}"
                    );
                }
            }
        }
    }
    assert!(found > 20, "{found} grazes");
}
