//! Biri 2006's indirect single scattering (§III.C) for the ground truth: light scattered once by
//! the medium and then reflected by a surface toward the eye. Enabled per scene
//! (`indirect_single_scattering`); it lands in the `surface` AOV (and so in `total`), attenuated
//! to the eye by e^(−σ_t d) like the direct surface term.
//!
//! The quantity (the same definition the `biri-shadow-volumes` method tabulates):
//!
//! L_iss(P → v) = ∫_{n·ω > 0} f_r(ω, v) L_ss(P, ω) (n·ω) dω,
//! L_ss(P, ω) = ∫_0^∞ σ_s p(θ) I e^(−σ_t (x + r(x))) / r(x)² dx,
//!
//! with X = P + x ω a point on the gather ray, r its distance to the point light, θ the angle
//! between the light's propagation (X − S)/r and −ω, f_r = albedo/π + ks (m+2)/(2π) (ω·r_v)₊^m
//! (the scene's normalised Phong, r_v the view direction mirrored about n) — the BRDF of the
//! direct surface term. What is and is not shadowed, as in the paper: every gather ray runs to
//! infinity (d = ∞: no geometry stops it, not even other objects), the medium along it is lit
//! everywhere (no volumetric shadows), and P's own visibility of the light does not mask the
//! term (points in a surface shadow still see lit fog). The whole hemisphere counts, whether or
//! not the surface faces the light (the paper's Fig. 8 drops the term when n·l ≤ 0, a side effect
//! of its full-sphere signed cosine; see the method's README). Point lights only (the method's
//! Γ tables assume isotropic point sources); other lights and particle media are refused.
//!
//! Quadrature (no tables, no approximations): spherical coordinates (φ, ψ) about the direction
//! to the light u_s. For a point light L_ss depends on φ alone, and with Biri's angle variable
//! along the gather ray (x = l cos φ + l sin φ tan α), sin φ · L_ss = σ_s I / l · S(φ),
//! S(φ) = ∫_{φ−π/2}^{π/2} p(−sin α) e^(−σ_t l [cos φ + sin φ tan(α/2 + π/4)]) dα, bounded and
//! smooth (the 1/angle peak toward the light is gone). Then L_iss = σ_s I / l ∫_0^π S(φ) A(φ) dφ
//! with A(φ) = ∫ f_r (n·ω)₊ dψ over the azimuth: the Lambert part in closed form
//! (2(a ψ_c + b sin ψ_c), a = cos φ (n·u_s), b = sin φ |n_⊥|, ψ_c = acos(−a/b)), the Phong part
//! by Gauss–Kronrod over the lit azimuth range, split at the lobe's peak and edges. The outer
//! integral is split where A is not smooth (the cone of angle φ about u_s touching the horizon
//! or the Phong lobe's edge) and refined adaptively to the reference's relative tolerance; the
//! inner ones use fixed composite rules (G7K15 panels: 2 per smooth piece at the default
//! tolerance, more when tighter; S(φ)'s panels also cut where its exponential factor falls by
//! e^(1/64), e^(1/8), e, e^6, and end at e^40) so that the outer integrand is smooth in φ.

use std::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;
use scenes::desc::Material;
use scenes::{Homogeneous, LightState, Scene};

use super::quadrature::{gk15, refine};

/// Why the reference cannot compute this scene's indirect term, if it cannot.
pub fn check(scene: &Scene) -> Result<(), String> {
    if !scene.desc.indirect_single_scattering {
        return Ok(());
    }
    let f = scene.features();
    if f.medium == "particles" {
        return Err(format!(
            "scene '{}': indirect single scattering is defined for a homogeneous medium only",
            scene.name
        ));
    }
    if let Some(k) = f.light_kinds.iter().find(|k| **k != "point") {
        return Err(format!(
            "scene '{}': indirect single scattering is computed for point lights only (found a {k} light)",
            scene.name
        ));
    }
    if f.height_fog {
        return Err(format!(
            "scene '{}': indirect single scattering is computed for a constant σ only, not with medium.height_fog (its gather rays to infinity assume a homogeneous medium)",
            scene.name
        ));
    }
    Ok(())
}

/// The BRDF of a material as the direct term uses it.
#[derive(Clone, Copy, Debug)]
pub struct Brdf {
    /// Lambert albedo (the BRDF is albedo/π).
    pub albedo: DVec3,
    /// Normalised Phong (ks, shininess m): ks (m+2)/(2π) (ω·r_v)₊^m.
    pub phong: Option<(DVec3, f64)>,
}

impl Brdf {
    pub fn of(mat: &Material) -> Brdf {
        Brdf {
            albedo: mat.albedo.as_dvec3(),
            phong: mat
                .phong
                .as_ref()
                .map(|p| (p.ks.as_dvec3(), p.shininess as f64)),
        }
    }
}

/// L_iss at `p` (shading normal `n`, unit `v` toward the eye) summed over the point lights, not yet
/// attenuated on the eye leg. `rel_tol`: the relative tolerance of the outer quadrature.
pub fn radiance(
    medium: &Homogeneous,
    lights: &[LightState],
    p: DVec3,
    n: DVec3,
    v: DVec3,
    mat: &Material,
    rel_tol: f64,
) -> DVec3 {
    let brdf = Brdf::of(mat);
    lights
        .iter()
        .filter_map(|l| match l {
            LightState::Point {
                position,
                intensity,
            } => Some(point_light(
                medium,
                position.as_dvec3(),
                intensity.as_dvec3(),
                p,
                n,
                v,
                &brdf,
                rel_tol,
            )),
            _ => None,
        })
        .sum()
}

/// S(φ) = ∫_{φ−π/2}^{π/2} p(−sin α) e^(−λ [cos φ + sin φ tan(α/2 + π/4)]) dα per channel
/// (λ = σ_t l): l sin φ L_ss / (σ_s I) along the gather ray at angle φ from the light. The
/// integrand is smooth on the closed interval, but its exponential factor falls from e^(−λ) at
/// the start (e = cos φ + sin φ tan(·) = 1 there: the point P itself) to 0 over an α-range that
/// shrinks with λ sin φ; equal panels resolve that badly for small φ (1e-5 relative with 8 of
/// them). So the panels are `pieces` equal ones (for the phase function) cut again where the
/// slowest channel's exponent λ (e − 1) reaches 1/2, 2, 8 and 24, and the range ends where it
/// reaches 48: the rest is below e^(−48) ≈ 1.4e-21 of the integrand at the start. One G7K15 rule
/// per panel.
pub fn s_of_phi(medium: &Homogeneous, lambda: DVec3, phi: f64, pieces: usize) -> DVec3 {
    let (sp, cp) = phi.sin_cos();
    let f = |a: f64| {
        let (s, c) = a.sin_cos();
        // tan(α/2 + π/4) = (1 + sin α)/cos α = cos α/(1 − sin α): the form without cancellation.
        let q = if s >= 0.0 {
            (1.0 + s) / c
        } else {
            c / (1.0 - s)
        };
        let e = cp + sp * q;
        let ph = medium.phase.eval(-s);
        DVec3::new(
            ph * ex(lambda.x, e),
            ph * ex(lambda.y, e),
            ph * ex(lambda.z, e),
        )
    };
    let lo = phi - FRAC_PI_2;
    // α where e = cos φ + sin φ tan(α/2 + π/4) takes the value `e` (e ≥ 1, increasing in α).
    let alpha_at = |e: f64| 2.0 * ((e - cp) / sp).atan() - FRAC_PI_2;
    let slowest = lambda.min_element();
    let mut hi = FRAC_PI_2;
    let mut cuts: Vec<f64> = Vec::with_capacity(pieces + 10);
    if slowest > 0.0 && sp > 0.0 {
        hi = alpha_at(1.0 + 40.0 / slowest).clamp(lo, FRAC_PI_2);
        cuts.extend(
            [1.0 / 64.0, 0.125, 1.0, 6.0]
                .iter()
                .map(|k| alpha_at(1.0 + k / slowest))
                .filter(|a| *a > lo && *a < hi),
        );
    }
    let width = (FRAC_PI_2 - lo) / pieces as f64;
    cuts.extend(
        (1..pieces)
            .map(|k| lo + width * k as f64)
            .filter(|a| *a < hi),
    );
    cuts.push(lo);
    cuts.push(hi);
    cuts.sort_by(f64::total_cmp);
    cuts.windows(2).map(|w| gk15(&f, w[0], w[1]).0).sum()
}

/// ∫_a^b f by the 15-point Kronrod rule on `n` equal panels. The inner integrals use fixed
/// nodes so that they are smooth functions of φ: an adaptive inner rule changes its panels
/// from one φ to the next, and the outer adaptive rule then chases that noise.
pub fn fixed(f: &impl Fn(f64) -> DVec3, a: f64, b: f64, n: usize) -> DVec3 {
    if b <= a {
        return DVec3::ZERO;
    }
    let h = (b - a) / n as f64;
    (0..n)
        .map(|k| gk15(f, a + h * k as f64, a + h * (k + 1) as f64).0)
        .sum()
}

/// Equal panels of each inner integral for an outer tolerance: 2 at the default 1e-6 (S(φ) is
/// then within 1e-8 relative for φ > 0.01, see `s_of_phi`; L_iss within 3e-9 of its value at
/// 1e-10 on the indirect-point materials), more when tighter (the convergence check sees them
/// change).
pub fn inner_pieces(rel_tol: f64) -> usize {
    (2.0 * (1e-6 / rel_tol.max(1e-15)).powf(0.25))
        .ceil()
        .clamp(2.0, 64.0) as usize
}

/// The angle x wrapped into (−π, π].
fn wrap(x: f64) -> f64 {
    let y = x.rem_euclid(2.0 * PI);
    if y > PI { y - 2.0 * PI } else { y }
}

/// e^(−λ e), with λ = 0 giving 1 even where e is huge.
fn ex(lambda: f64, e: f64) -> f64 {
    if lambda == 0.0 {
        1.0
    } else {
        (-lambda * e).exp()
    }
}

/// ∫_0^{2π} max(0, a + b cos ψ) dψ (b ≥ 0): the azimuthal integral of the clamped cosine.
pub fn clamped_cos_azimuth(a: f64, b: f64) -> f64 {
    if b <= 0.0 {
        return 2.0 * PI * a.max(0.0);
    }
    let psi_c = (-a / b).clamp(-1.0, 1.0).acos();
    2.0 * (a * psi_c + b * psi_c.sin())
}

/// One point light's L_iss (see the module doc).
#[allow(clippy::too_many_arguments)]
pub fn point_light(
    medium: &Homogeneous,
    lp: DVec3,
    intensity: DVec3,
    p: DVec3,
    n: DVec3,
    v: DVec3,
    brdf: &Brdf,
    rel_tol: f64,
) -> DVec3 {
    let w = lp - p;
    let l = w.length();
    let sigma_s = medium.sigma_s.as_dvec3();
    if l.is_nan() || l <= 0.0 || sigma_s.max_element() <= 0.0 {
        return DVec3::ZERO;
    }
    let us = w / l;
    let mu_n = n.dot(us).clamp(-1.0, 1.0);
    // Azimuth frame about u_s with e1 along n's part across u_s, so n = μ_n u_s + sin_n e1.
    let perp = n - us * mu_n;
    let sin_n = perp.length();
    let e1 = if sin_n > 1e-12 {
        perp / sin_n
    } else {
        us.any_orthonormal_vector()
    };
    let e2 = us.cross(e1);
    let lambda = medium.sigma_t.as_dvec3() * l;
    let pieces = inner_pieces(rel_tol);
    let r_v = n * (2.0 * n.dot(v)) - v;
    let lambert = brdf.albedo / PI;

    // A(φ): ∫ f_r (n·ω)₊ dψ over the azimuth.
    let azimuthal = |phi: f64| -> DVec3 {
        let (sp, cp) = phi.sin_cos();
        let (a, b) = (cp * mu_n, sp * sin_n);
        let mut out = lambert * clamped_cos_azimuth(a, b);
        if let Some((ks, m)) = brdf.phong {
            let psi_c = if b > 0.0 {
                (-a / b).clamp(-1.0, 1.0).acos()
            } else if a > 0.0 {
                PI
            } else {
                0.0
            };
            if psi_c > 0.0 {
                let lobe = |psi: f64| {
                    let (s, c) = psi.sin_cos();
                    let omega = us * cp + (e1 * c + e2 * s) * sp;
                    let cos_n = (a + b * c).max(0.0);
                    DVec3::splat(omega.dot(r_v).max(0.0).powf(m) * cos_n)
                };
                // ω·r_v = A + B cos(ψ − ψ₀): split at the lobe's peak ψ₀ and its edges, so
                // every panel's integrand is smooth.
                let big_a = cp * us.dot(r_v);
                let (bx, by) = (sp * e1.dot(r_v), sp * e2.dot(r_v));
                let big_b = bx.hypot(by);
                let mut cuts = vec![-psi_c, psi_c];
                if big_b > 1e-12 {
                    let psi0 = by.atan2(bx);
                    cuts.push(wrap(psi0));
                    if (big_a / big_b).abs() < 1.0 {
                        let e = (-big_a / big_b).acos();
                        cuts.extend([wrap(psi0 + e), wrap(psi0 - e)]);
                    }
                }
                cuts.retain(|c| (-psi_c..=psi_c).contains(c));
                cuts.sort_by(f64::total_cmp);
                let k: f64 = cuts
                    .windows(2)
                    .map(|w| fixed(&lobe, w[0], w[1], pieces).x)
                    .sum();
                out += ks * ((m + 2.0) / (2.0 * PI) * k);
            }
        }
        out
    };
    let integrand = |phi: f64| s_of_phi(medium, lambda, phi, pieces) * azimuthal(phi);

    // Split [0, π] where A(φ) has kinks: the cone about u_s tangent to the horizon (φ = |φ_n ∓ π/2|,
    // φ_n + π/2) and, with Phong, to the lobe's edge (ψ_s ± π/2) and at its peak (ψ_s).
    let phi_n = mu_n.acos();
    let mut cuts = vec![
        0.0,
        PI,
        FRAC_PI_2 - phi_n,
        phi_n - FRAC_PI_2,
        phi_n + FRAC_PI_2,
    ];
    if brdf.phong.is_some() {
        let psi_s = us.dot(r_v).clamp(-1.0, 1.0).acos();
        cuts.extend([
            psi_s,
            psi_s - FRAC_PI_2,
            FRAC_PI_2 - psi_s,
            psi_s + FRAC_PI_2,
        ]);
    }
    // S(φ) is not smooth at φ → 0 (≈ S(0) + c φ log φ: the gather ray grazes the light) nor,
    // more mildly, at φ → π: panels graded toward the ends (π/16, π/128, π/1024 and π − π/16)
    // spare the adaptive rule its bisections there (half its evaluations otherwise). Measured on
    // 400 indirect-point-like cases: 196 outer evaluations instead of 317, worst error against
    // rel_tol 1e-11 2.1e-8 instead of 1.6e-7 (`s_of_phi`'s panels included).
    for k in 0..3 {
        cuts.push(PI / 16.0 * 0.125f64.powi(k));
    }
    cuts.push(PI - PI / 16.0);
    cuts.retain(|c| (0.0..=PI).contains(c));
    cuts.sort_by(f64::total_cmp);
    cuts.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let panels: Vec<(f64, f64, DVec3, DVec3)> = cuts
        .windows(2)
        .map(|c| {
            let (est, err) = gk15(&integrand, c[0], c[1]);
            (c[0], c[1], est, err)
        })
        .collect();
    let total: DVec3 = panels.iter().map(|p| p.2).sum();
    let target = rel_tol * total.abs().max_element().max(1e-300);
    let span = PI;
    let sum: DVec3 = panels
        .iter()
        .map(|&(a, b, est, err)| refine(&integrand, a, b, est, err, target * (b - a) / span))
        .sum();
    sigma_s * intensity / l * sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::quadrature::adaptive;
    use glam::Vec3;
    use scenes::Phase;

    fn medium(sigma_a: f32, sigma_s: f32, phase: Phase) -> Homogeneous {
        Homogeneous {
            sigma_a: Vec3::splat(sigma_a),
            sigma_s: Vec3::splat(sigma_s),
            sigma_t: Vec3::splat(sigma_a + sigma_s),
            phase,
            ambient: Vec3::ZERO,
            height_fog: None,
        }
    }

    /// Closed form: isotropic phase, σ_t → 0 (σ_s = 1e-9, so e^(−σ_t ·) = 1 to 1e-8), light on the
    /// normal at distance l. Then L_ss(φ) = σ_s I (π − φ) / (4π l sin φ) (∫_0^∞ dx/r² = (π − φ)/h)
    /// and L_iss = (albedo/π) 2π ∫_0^{π/2} L_ss cos φ sin φ dφ = albedo σ_s I (π/2 + 1) / (2π l).
    #[test]
    fn lambert_light_on_the_normal_matches_the_closed_form() {
        let m = medium(0.0, 1e-9, Phase::Isotropic);
        let (l, i, albedo) = (2.5, 7.0, 0.6);
        let brdf = Brdf {
            albedo: DVec3::splat(albedo),
            phong: None,
        };
        let n = DVec3::new(0.3, 0.9, -0.2).normalize();
        let p = DVec3::new(1.0, -2.0, 0.5);
        let got = point_light(&m, p + n * l, DVec3::splat(i), p, n, DVec3::Y, &brdf, 1e-8).x;
        let exact = albedo * 1e-9 * i * (FRAC_PI_2 + 1.0) / (2.0 * PI * l);
        assert!((got / exact - 1.0).abs() < 1e-6, "{got} vs {exact}");
    }

    /// ∫_0^{2π} max(0, a + b cos ψ) dψ against a midpoint sum.
    #[test]
    fn clamped_cosine_azimuth_matches_a_sum() {
        for (a, b) in [(0.3, 0.5), (-0.2, 0.7), (0.9, 0.1), (-0.9, 0.1), (0.4, 0.0)] {
            let n = 200_000;
            let h = 2.0 * PI / n as f64;
            let sum: f64 = (0..n)
                .map(|k| (a + b * ((k as f64 + 0.5) * h).cos()).max(0.0) * h)
                .sum();
            assert!((clamped_cos_azimuth(a, b) - sum).abs() < 1e-8, "{a} {b}");
        }
    }

    /// An independent check of the general case (HG phase, σ_t l ≈ 1, light 55° off the normal,
    /// Lambert + Phong m = 12 at an oblique view): a midpoint grid over the hemisphere in
    /// coordinates about the NORMAL, with L_ss integrated along each gather ray in x (adaptive
    /// GK15 after x = u/(1−u)), not in Biri's angle. The grid's error comes from the 1/angle
    /// peak toward the light, first order in the spacing: the 200×400 and 400×800 grids are
    /// Richardson-extrapolated (measured: the halving changes the sum by 3.1e-3, the extrapolated
    /// value is within the eprintln'd difference of the reference; bound 5e-4).
    #[test]
    fn general_case_matches_a_hemisphere_grid() {
        let m = medium(0.05, 0.35, Phase::HenyeyGreenstein { g: 0.5 });
        let n = DVec3::Z;
        let p = DVec3::ZERO;
        let lp = DVec3::new(55f64.to_radians().sin(), 0.0, 55f64.to_radians().cos()) * 2.6;
        let i = DVec3::new(10.0, 8.0, 6.0);
        let v = DVec3::new(-0.5, 0.4, 0.75).normalize();
        let brdf = Brdf {
            albedo: DVec3::new(0.7, 0.5, 0.3),
            phong: Some((DVec3::splat(0.25), 12.0)),
        };
        let got = point_light(&m, lp, i, p, n, v, &brdf, 1e-7);
        let grid = |nt: usize| -> DVec3 {
            let np = 2 * nt;
            let (ht, hp) = (FRAC_PI_2 / nt as f64, 2.0 * PI / np as f64);
            let r_v = n * (2.0 * n.dot(v)) - v;
            let sigma_t = m.sigma_t.x as f64;
            let mut sum = DVec3::ZERO;
            for a in 0..nt {
                let th = (a as f64 + 0.5) * ht;
                for b in 0..np {
                    let ph = (b as f64 + 0.5) * hp;
                    let omega = DVec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                    let ray = |u: f64| {
                        let x = u / (1.0 - u);
                        let xp = p + omega * x;
                        let wv = xp - lp;
                        let r = wv.length();
                        let cos = wv.dot(-omega) / r;
                        DVec3::splat(
                            m.phase.eval(cos) * (-sigma_t * (x + r)).exp()
                                / (r * r)
                                / ((1.0 - u) * (1.0 - u)),
                        )
                    };
                    let lss = adaptive(&ray, 0.0, 1.0 - 1e-12, 1e-9) * m.sigma_s.x as f64 * i;
                    let mut f = brdf.albedo / PI;
                    let (ks, sh) = brdf.phong.unwrap();
                    f += ks * ((sh + 2.0) / (2.0 * PI) * omega.dot(r_v).max(0.0).powf(sh));
                    sum += f * lss * (th.cos() * th.sin() * ht * hp);
                }
            }
            sum
        };
        // The peak makes the midpoint grid first order: Richardson-extrapolate 2·fine − coarse.
        let (coarse, fine) = (grid(200), grid(400));
        let extrapolated = fine * 2.0 - coarse;
        let err = ((got - extrapolated) / extrapolated).abs().max_element();
        let grid_err = ((coarse - fine) / fine).abs().max_element();
        eprintln!(
            "reference L_iss {got:?}, extrapolated grid {extrapolated:?}: rel diff {err:.2e} \
             (halving the grid changes it by {grid_err:.2e})"
        );
        assert!(err < 5e-4, "{got:?} vs {extrapolated:?}");
    }

    /// Indirect scattering with a spot light is refused with a message naming it, not rendered wrong;
    /// the library's indirect-point scene is accepted.
    #[test]
    fn non_point_lights_are_refused() {
        let mut scene = scenes::library::resolve("fence-spot").unwrap();
        assert!(check(&scene).is_ok(), "the flag is off");
        scene.desc.indirect_single_scattering = true;
        let err = check(&scene).unwrap_err();
        assert!(
            err.contains("spot") && err.contains("point lights only"),
            "{err}"
        );
        assert!(check(&scenes::library::resolve("indirect-point").unwrap()).is_ok());
    }

    /// A surface facing away from the light still receives fog light; one facing it receives more.
    #[test]
    fn facing_away_from_the_light_is_smaller_but_not_zero() {
        let m = medium(0.02, 0.3, Phase::Isotropic);
        let brdf = Brdf {
            albedo: DVec3::ONE,
            phong: None,
        };
        let lp = DVec3::new(0.0, 0.0, 2.0);
        let toward = point_light(
            &m,
            lp,
            DVec3::ONE,
            DVec3::ZERO,
            DVec3::Z,
            DVec3::Z,
            &brdf,
            1e-6,
        )
        .x;
        let away = point_light(
            &m,
            lp,
            DVec3::ONE,
            DVec3::ZERO,
            -DVec3::Z,
            -DVec3::Z,
            &brdf,
            1e-6,
        )
        .x;
        assert!(away > 0.0 && away < 0.5 * toward, "{away} vs {toward}");
    }
}
