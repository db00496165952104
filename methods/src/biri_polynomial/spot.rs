//! Eq. 7 of the paper: lights whose intensity varies with direction (spots with a falloff and a
//! projected pattern), CPU side, f64.
//!
//! Along a ray, the directions ω(θ) from the light to the ray's points sweep half of the great
//! circle in the plane through the light and the ray: ω(θ) = cosθ n̂ + sinθ û, with n̂ the unit
//! vector from the light to its foot on the ray and û the ray direction. So a lit segment gives
//! σ_s e^(−σ_t t)/h ∫ Λ(θ) I(ω(θ)) dθ, which is no longer eq. 6's closed form. The paper
//! (§3.2) precomputes, on N half circles of the emission hemisphere, sampled at M angles γ,
//!
//!   Δ_i(γ) = ∫_{−π/2}^{γ} δ^i I(δ) dδ,
//!
//! and with γ = θ + β (β: where the ray's foot direction sits on the half circle) re-expands the
//! polynomial of Λ in δ (coefficients c'_i), so that a segment is Σ c'_i (Δ_i(γ_d) − Δ_i(γ_0)):
//! still O(n²) per segment.
//!
//! Our half circles: a plane through the light is named by its unit normal m in the spot's frame
//! (x = right, y = up, z = axis; `scenes::light::spot_frame`), m = (√(1−u²) cosφ, √(1−u²) sinφ, u).
//! Its half circle on the emission hemisphere is ω(δ) = cosδ c + sinδ e, δ ∈ [−π/2, π/2], with
//! c the circle's direction closest to the axis (z − u m, normalised) and e = m × c. Only planes
//! with |u| < sin(outer half-angle) meet the cone, so u is sampled there (`n_u` values), φ over
//! [0, 2π) (`n_phi` values), γ at `m` points; Δ_i between samples is interpolated bilinearly
//! in (u, φ) and linearly in γ — the approximation this construction adds (measured in the
//! tests). The plane m = n̂ × û is oriented so that δ increases with θ (m × n̂ = û).
//!
//! Limits: a cone of half-angle ≥ 90° is not representable on one hemisphere (the scenes' spots
//! are narrower; `HalfCircles::new` refuses it). The re-expansion in δ uses monomials around
//! δ = 0: fine in f64, ill-conditioned in f32 for short segments far from δ = 0.

// Series and table recurrences read best with explicit indices.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::{FRAC_PI_2, PI};

use glam::DVec3;

/// Δ_i(γ) tables on a grid of half circles, RGB.
pub struct HalfCircles {
    /// Polynomial order n: Δ_0 … Δ_n are stored.
    pub order: usize,
    pub n_u: usize,
    pub n_phi: usize,
    /// γ samples per half circle (uniform on [−π/2, π/2], both ends included).
    pub m: usize,
    /// |u| range: sin of the outer half-angle (slightly enlarged).
    pub u_max: f64,
    /// [(iu · n_phi + ip) · m + g] · (order+1) + i → Δ_i, RGB.
    data: Vec<[f64; 3]>,
}

/// The half circle of plane normal `m` (spot frame): (c, e), or None when m is the axis.
pub fn circle_frame(m: DVec3) -> Option<(DVec3, DVec3)> {
    let c = DVec3::Z - m.z * m;
    let len = c.length();
    if len < 1e-12 {
        return None;
    }
    let c = c / len;
    Some((c, m.cross(c)))
}

fn normal(u: f64, phi: f64) -> DVec3 {
    let s = (1.0 - u * u).max(0.0).sqrt();
    DVec3::new(s * phi.cos(), s * phi.sin(), u)
}

impl HalfCircles {
    /// Tables for intensity `intensity(ω)` (ω a unit direction in the spot frame, W/sr RGB),
    /// zero outside the cone of half-angle `outer` (radians, < π/2). `sub`: quadrature points
    /// per γ interval (midpoint rule; the patterns are piecewise constant, so many and small).
    pub fn new(
        order: usize,
        n_u: usize,
        n_phi: usize,
        m: usize,
        outer: f64,
        sub: usize,
        intensity: impl Fn(DVec3) -> [f64; 3],
    ) -> Result<HalfCircles, String> {
        if !(outer > 0.0 && outer < FRAC_PI_2) {
            return Err(format!(
                "spot half-angle must be in (0, 90°) for the half-circle tables, not {:.1}°",
                outer.to_degrees()
            ));
        }
        if n_u < 2 || n_phi < 1 || m < 2 || sub < 1 {
            return Err("half-circle tables need n_u ≥ 2, n_phi ≥ 1, m ≥ 2, sub ≥ 1".into());
        }
        let u_max = (outer.sin() * 1.02).min(1.0);
        let k = order + 1;
        let mut data = vec![[0.0; 3]; n_u * n_phi * m * k];
        let dg = PI / (m - 1) as f64;
        for iu in 0..n_u {
            let u = -u_max + 2.0 * u_max * iu as f64 / (n_u - 1) as f64;
            for ip in 0..n_phi {
                let phi = 2.0 * PI * ip as f64 / n_phi as f64;
                let Some((c, e)) = circle_frame(normal(u, phi)) else {
                    continue;
                };
                let base = (iu * n_phi + ip) * m;
                let mut acc = vec![[0.0; 3]; k];
                for g in 1..m {
                    let g0 = -FRAC_PI_2 + dg * (g - 1) as f64;
                    for s in 0..sub {
                        let d = g0 + dg * (s as f64 + 0.5) / sub as f64;
                        let w = d.cos() * c + d.sin() * e;
                        let val = intensity(w);
                        let mut p = dg / sub as f64;
                        for i in 0..k {
                            for ch in 0..3 {
                                acc[i][ch] += p * val[ch];
                            }
                            p *= d;
                        }
                    }
                    for i in 0..k {
                        data[(base + g) * k + i] = acc[i];
                    }
                }
            }
        }
        Ok(HalfCircles {
            order,
            n_u,
            n_phi,
            m,
            u_max,
            data,
        })
    }

    /// The tables in their storage order (`spot_tables` uploads them as is).
    pub fn raw(&self) -> &[[f64; 3]] {
        &self.data
    }

    fn at(&self, iu: usize, ip: usize, g: usize, i: usize) -> [f64; 3] {
        self.data[((iu * self.n_phi + ip) * self.m + g) * (self.order + 1) + i]
    }

    /// Δ_0 … Δ_n at γ on the (interpolated) half circle of plane normal `m` (spot frame).
    pub fn delta(&self, m: DVec3, gamma: f64) -> Vec<[f64; 3]> {
        let k = self.order + 1;
        let mut out = vec![[0.0; 3]; k];
        if m.z.abs() >= self.u_max {
            return out; // the plane misses the cone
        }
        let fu = (m.z + self.u_max) / (2.0 * self.u_max) * (self.n_u - 1) as f64;
        let iu = (fu.floor() as usize).min(self.n_u - 2);
        let wu = fu - iu as f64;
        let phi = m.y.atan2(m.x).rem_euclid(2.0 * PI);
        let fp = phi / (2.0 * PI) * self.n_phi as f64;
        let ip = (fp.floor() as usize).min(self.n_phi - 1);
        let wp = fp - ip as f64;
        let ip1 = (ip + 1) % self.n_phi;
        let fg = (gamma.clamp(-FRAC_PI_2, FRAC_PI_2) + FRAC_PI_2) / PI * (self.m - 1) as f64;
        let ig = (fg.floor() as usize).min(self.m - 2);
        let wg = fg - ig as f64;
        for (cu, wcu) in [(iu, 1.0 - wu), (iu + 1, wu)] {
            for (cp, wcp) in [(ip, 1.0 - wp), (ip1, wp)] {
                for (cg, wcg) in [(ig, 1.0 - wg), (ig + 1, wg)] {
                    let w = wcu * wcp * wcg;
                    if w == 0.0 {
                        continue;
                    }
                    for i in 0..k {
                        let v = self.at(cu, cp, cg, i);
                        for ch in 0..3 {
                            out[i][ch] += w * v[ch];
                        }
                    }
                }
            }
        }
        out
    }
}

/// Re-expansion of Σ c_j θ^j in δ = θ + β: the c'_i of eq. 7.
pub fn shift(c: &[f64], beta: f64) -> Vec<f64> {
    let n = c.len();
    let mut out = vec![0.0; n];
    // (δ − β)^j = Σ_i C(j, i) δ^i (−β)^(j−i)
    for j in 0..n {
        let mut binom = 1.0;
        for i in 0..=j {
            // binom = C(j, i)
            out[i] += c[j] * binom * (-beta).powi((j - i) as i32);
            binom = binom * (j - i) as f64 / (i + 1) as f64;
        }
    }
    out
}

/// Monomial coefficients (in θ) of the Chebyshev series `coef` on [a, b].
pub fn chebyshev_to_monomial(coef: &[f64], a: f64, b: f64) -> Vec<f64> {
    let n = coef.len();
    // T_i(s) as monomials in s, then s = (θ − mid)/half.
    let mut t_prev = vec![0.0; n];
    let mut t_cur = vec![0.0; n];
    t_prev[0] = 1.0;
    if n > 1 {
        t_cur[1] = 1.0;
    }
    let mut in_s = vec![0.0; n];
    for i in 0..n {
        let ti = if i == 0 { &t_prev } else { &t_cur };
        for j in 0..n {
            in_s[j] += coef[i] * ti[j];
        }
        if i >= 1 && i + 1 < n {
            let mut next = vec![0.0; n];
            for j in 0..n - 1 {
                next[j + 1] += 2.0 * t_cur[j];
            }
            for j in 0..n {
                next[j] -= t_prev[j];
            }
            t_prev = std::mem::replace(&mut t_cur, next);
        }
    }
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    // Σ q_j ((θ − mid)/half)^j = Σ (q_j / half^j) (θ − mid)^j
    let scaled: Vec<f64> = in_s
        .iter()
        .enumerate()
        .map(|(j, q)| q / half.powi(j as i32))
        .collect();
    shift(&scaled, mid)
}

/// A ray's place on the half circles: the plane normal m (spot frame), β and the ray frame.
pub struct RayCircle {
    pub m: DVec3,
    pub beta: f64,
    pub t: f64,
    pub h: f64,
}

/// For a ray from `o` along unit `dir`, a light at `light` with spot frame (right, up, axis).
pub fn ray_circle(o: DVec3, dir: DVec3, light: DVec3, frame: [DVec3; 3]) -> Option<RayCircle> {
    let v = light - o;
    let t = v.dot(dir);
    let foot = o + t * dir - light;
    let h = foot.length();
    if h < 1e-9 {
        return None;
    }
    let n_hat = foot / h;
    let to_local = |w: DVec3| DVec3::new(w.dot(frame[0]), w.dot(frame[1]), w.dot(frame[2]));
    // Cross products in the spot frame itself: (right, up, axis) is left-handed, so a world
    // cross product would flip m.
    let n_local = to_local(n_hat);
    let m = n_local.cross(to_local(dir));
    let (c, e) = circle_frame(m)?;
    Some(RayCircle {
        m,
        beta: n_local.dot(e).atan2(n_local.dot(c)),
        t,
        h,
    })
}

/// ∫_{θa}^{θb} Λ(θ) I(ω(θ)) dθ by eq. 7, given Λ's monomial coefficients `c` in θ (RGB).
pub fn eq7(
    tables: &HalfCircles,
    rc: &RayCircle,
    c: &[f64],
    theta_a: f64,
    theta_b: f64,
) -> [f64; 3] {
    let cp = shift_to_delta(c, rc.beta);
    let (ga, gb) = (
        (theta_a + rc.beta).clamp(-FRAC_PI_2, FRAC_PI_2),
        (theta_b + rc.beta).clamp(-FRAC_PI_2, FRAC_PI_2),
    );
    let da = tables.delta(rc.m, ga);
    let db = tables.delta(rc.m, gb);
    let mut out = [0.0; 3];
    for (i, ci) in cp.iter().enumerate().take(tables.order + 1) {
        for ch in 0..3 {
            out[ch] += ci * (db[i][ch] - da[i][ch]);
        }
    }
    out
}

/// θ = δ − β: coefficients in δ of Σ c_j θ^j.
fn shift_to_delta(c: &[f64], beta: f64) -> Vec<f64> {
    // Σ c_j (δ − β)^j
    shift(c, beta)
}
