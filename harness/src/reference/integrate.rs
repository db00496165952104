//! The radiance of one camera ray (ARCHITECTURE §1), computed without any of the
//! approximations the methods make: exact visibility (ray casts for surfaces; for the medium, the exact shadowed
//! intervals of [`super::shadow`], with sampling plus bisection only as the fallback for
//! degenerate geometry), and adaptive Gauss–Kronrod quadrature in Biri's angle variable.
//!
//! For a point or spot light at L, let t₀ be the ray parameter of the point closest to L and h
//! that distance. With t = t₀ + h tan φ, the distance to the light is r = h / cos φ and
//! dt / r² = dφ / h, so the in-scatter integrand
//! σ_s p(θ) V I(ω) e^(−σ_t (t + r)) / r² dt becomes σ_s p(θ) V I(ω) e^(−σ_t (t + r)) / h dφ,
//! which is bounded and smooth: the 1/r² peak is gone. The interval is split at every place the
//! integrand is not smooth — shadow boundaries (exact, see [`super::shadow`]), the spot's
//! cone edges (ray–cone roots) and the pattern's edges (ray–plane roots) — and each lit piece
//! is integrated adaptively to the relative tolerance. Directional light has a constant phase
//! angle along a ray, so each lit interval integrates in closed form.
//!
//! Particle media are traced in `particle_ray.rs`; the quadrature is in `quadrature.rs`.

use glam::DVec3;
use scenes::light::{pattern_breaks, spot_frame};
use scenes::{Homogeneous, LightState};

use super::height_fog::Fog;
use super::particles::ParticleField;
/// Re-exported: methods' tests integrate their closed forms with it.
pub use super::quadrature::adaptive;
use super::quadrature::{exp, exp_integral};
use super::shadow::{Source, shadowed};
use super::world::World;

/// Accuracy knobs of the reference. `tighter()` divides every tolerance by 4 (and samples
/// visibility 4× more densely): the convergence check compares the two.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    /// Relative tolerance of each lit interval's quadrature. Default 1e-6.
    pub rel_tol: f64,
    /// Visibility samples along each camera ray per light (uniform in the angle φ for local
    /// lights, in distance for directional light). Default 256.
    pub visibility_samples: u32,
    /// Shadow boundaries are located to this fraction of the ray's length. Default 1e-9.
    pub bisect_tol: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            rel_tol: 1e-6,
            visibility_samples: 256,
            bisect_tol: 1e-9,
        }
    }
}

impl Settings {
    pub fn tighter(&self) -> Settings {
        Settings {
            rel_tol: self.rel_tol / 4.0,
            visibility_samples: self.visibility_samples * 4,
            bisect_tol: self.bisect_tol / 4.0,
        }
    }
}

/// Radiance of one ray, split into the three AOVs, plus the ray's length.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RayRadiance {
    pub inscatter: DVec3,
    pub surface: DVec3,
    pub total: DVec3,
    /// Distance to the visible surface, or to the far plane.
    pub distance: f64,
    pub hit: bool,
}

/// Everything constant across the rays of one image.
pub struct Tracer<'a> {
    pub world: &'a World,
    pub medium: Homogeneous,
    pub lights: &'a [LightState],
    pub settings: Settings,
    /// Offset for shadow-ray origins, m.
    pub eps: f64,
    /// Length of shadow rays toward a directional light (beyond every triangle), m.
    pub sun_distance: f64,
    /// A particle medium's spheres (then `medium` is its background). None: homogeneous.
    pub particles: Option<&'a ParticleField>,
    /// Add Biri's indirect single scattering to the surface term (see [`super::indirect`]).
    pub indirect: bool,
}

impl Tracer<'_> {
    /// Radiance along the ray `o + t d` (d unit), clipped to [near, far] like the rasteriser.
    pub fn trace(&self, o: DVec3, d: DVec3, near: f64, far: f64) -> RayRadiance {
        if let Some(field) = self.particles {
            return self.trace_particles(field, o, d, near, far);
        }
        let hit = self.world.bvh.intersect(o, d, near, far);
        let distance = hit.map_or(far, |h| h.t);
        let mut inscatter = DVec3::ZERO;
        if self.medium.sigma_s.max_element() > 0.0 {
            for light in self.lights {
                inscatter += match light {
                    LightState::Directional {
                        direction,
                        irradiance,
                    } => self.directional(
                        o,
                        d,
                        distance,
                        direction.as_dvec3(),
                        irradiance.as_dvec3(),
                    ),
                    _ => self.local(o, d, distance, light),
                };
            }
        }
        let mut surface = DVec3::ZERO;
        if let Some(h) = hit {
            let p = o + d * h.t;
            surface = self.surface(p, d, h) * self.transmittance(o, d, h.t);
        }
        let ambient =
            self.medium.ambient.as_dvec3() * (DVec3::ONE - self.transmittance(o, d, distance));
        RayRadiance {
            inscatter,
            surface,
            total: inscatter + surface + ambient,
            distance,
            hit: hit.is_some(),
        }
    }

    /// The height fog, if the medium has one.
    fn fog(&self) -> Option<Fog> {
        self.medium.height_fog.map(Fog::from)
    }

    /// e^(−τ) per channel over the segment from `a` along the unit direction `d` for `s` m:
    /// e^(−σ_t s), or with height fog e^(−σ_t L), L the segment's fog length.
    fn transmittance(&self, a: DVec3, d: DVec3, s: f64) -> DVec3 {
        let sigma_t = self.medium.sigma_t.as_dvec3();
        match self.fog() {
            None => exp(-sigma_t * s),
            Some(f) => exp(-sigma_t * f.length(a, d, s)),
        }
    }

    /// Reflected radiance at surface point `p` toward the eye (not yet attenuated).
    pub(super) fn surface(&self, p: DVec3, d: DVec3, h: super::bvh::Hit) -> DVec3 {
        let tri = &self.world.bvh.tris[h.tri as usize];
        let sh = &self.world.shading[h.tri as usize];
        let mat = &self.world.materials[sh.material as usize];
        let mut ng = (tri.p[1] - tri.p[0])
            .cross(tri.p[2] - tri.p[0])
            .normalize_or_zero();
        let mut n =
            (sh.n[0] * (1.0 - h.u - h.v) + sh.n[1] * h.u + sh.n[2] * h.v).normalize_or_zero();
        if ng.dot(-d) < 0.0 {
            // We see the back of the face: lit only if the material is two-sided.
            if !mat.two_sided {
                return DVec3::ZERO;
            }
            ng = -ng;
            n = -n;
        }
        let origin = p + ng * self.eps;
        let albedo = mat.albedo.as_dvec3() / std::f64::consts::PI;
        let mut out = DVec3::ZERO;
        for light in self.lights {
            let (l, r, incident) = match light {
                LightState::Directional {
                    direction,
                    irradiance,
                } => (-direction.as_dvec3(), f64::INFINITY, irradiance.as_dvec3()),
                _ => {
                    let lp = light.position().unwrap().as_dvec3();
                    let to = lp - p;
                    let r = to.length();
                    if r <= 0.0 {
                        continue;
                    }
                    (
                        to / r,
                        r,
                        light.intensity_toward(p) * self.transmittance(p, to / r, r) / (r * r),
                    )
                }
            };
            let cos = n.dot(l);
            if cos <= 0.0 || ng.dot(l) <= 0.0 || incident.max_element() <= 0.0 {
                continue;
            }
            if self.world.bvh.occluded(origin, l, 0.0, r) {
                continue;
            }
            // Particles shadow the surface (directional light too: r = ∞ reaches the sun).
            let incident = match self.particles {
                Some(f) => incident * (-f.optical_depth(origin, l, 0.0, r)).exp(),
                None => incident,
            };
            let mut brdf = albedo;
            if let Some(ph) = &mat.phong {
                let refl = n * (2.0 * cos) - l;
                let s = refl.dot(-d).max(0.0).powf(ph.shininess as f64);
                brdf += ph.ks.as_dvec3()
                    * ((ph.shininess as f64 + 2.0) / (2.0 * std::f64::consts::PI) * s);
            }
            out += brdf * incident * cos;
        }
        if self.indirect {
            let rel_tol = self.settings.rel_tol;
            out += super::indirect::radiance(&self.medium, self.lights, p, n, -d, mat, rel_tol);
        }
        out
    }

    /// In-scatter of a point or spot light over [0, len].
    fn local(&self, o: DVec3, d: DVec3, len: f64, light: &LightState) -> DVec3 {
        let lp = light.position().unwrap().as_dvec3();
        let sigma_s = self.medium.sigma_s.as_dvec3();
        let sigma_t = self.medium.sigma_t.as_dvec3();
        let phase = self.medium.phase;
        let fog = self.fog();
        let w0 = o - lp;
        let integrand_t = |t: f64| -> DVec3 {
            let w = w0 + d * t;
            let r = w.length();
            if r <= 0.0 {
                return DVec3::ZERO;
            }
            let cos_theta = -w.dot(d) / r;
            // σ_s(x) and the fog length of eye leg + light leg (t + r without height fog).
            let (density, path) = match fog {
                None => (1.0, t + r),
                Some(f) => (
                    f.scale(lp.y + w.y),
                    f.length(o, d, t) + f.length(lp + w, -w / r, r),
                ),
            };
            sigma_s
                * density
                * (phase.eval(cos_theta) / (r * r))
                * light.intensity_toward(lp + w)
                * exp(-sigma_t * path)
        };
        let mut sum = DVec3::ZERO;
        for (a, b) in self.lit_intervals(o, d, len, light) {
            sum += self.integrate_local(o, d, len, lp, a, b, &integrand_t);
        }
        sum
    }

    /// ∫_a^b f(t) dt for a point or spot light at `lp`, in Biri's angle variable when the ray
    /// does not pass through the light (dt/r² = dφ/h: integrate r²·f(t)/h over φ).
    #[allow(clippy::too_many_arguments)]
    fn integrate_local(
        &self,
        o: DVec3,
        d: DVec3,
        len: f64,
        lp: DVec3,
        a: f64,
        b: f64,
        f: &impl Fn(f64) -> DVec3,
    ) -> DVec3 {
        let w0 = o - lp;
        let t0 = -w0.dot(d);
        let h = (w0 + d * t0).length();
        if h > 1e-12 * (w0.length() + len) {
            let g = |phi: f64| {
                let t = t0 + h * phi.tan();
                let r = h / phi.cos();
                f(t) * (r * r / h)
            };
            adaptive(
                &g,
                ((a - t0) / h).atan(),
                ((b - t0) / h).atan(),
                self.settings.rel_tol,
            )
        } else {
            adaptive(f, a, b, self.settings.rel_tol)
        }
    }

    /// The sub-intervals of [0, len] where `light` reaches the ray unblocked by triangles and
    /// with non-zero intensity, split at every place the integrand is not smooth: shadow
    /// boundaries, the spot's cone edges, the pattern's edges.
    pub(super) fn lit_intervals(
        &self,
        o: DVec3,
        d: DVec3,
        len: f64,
        light: &LightState,
    ) -> Vec<(f64, f64)> {
        if let LightState::Directional { direction, .. } = light {
            return self.lit_intervals_directional(o, d, len, direction.as_dvec3());
        }
        let lp = light.position().unwrap().as_dvec3();
        let w0 = o - lp;
        let t0 = -w0.dot(d);
        let h = (w0 + d * t0).length();
        let mut cuts = vec![0.0, len];
        if let LightState::Spot {
            direction,
            cos_inner,
            cos_outer,
            tan_outer,
            pattern,
            ..
        } = light
        {
            let axis = direction.as_dvec3();
            for c in [*cos_inner as f64, *cos_outer as f64] {
                cone_roots(w0, d, axis, c, len, &mut cuts);
            }
            if let Some(p) = pattern {
                let (right, up) = spot_frame(axis);
                for b in pattern_breaks(p) {
                    let k = (2.0 * b - 1.0) * *tan_outer as f64;
                    for e in [right, up] {
                        plane_root(w0, d, e - axis * k, axis, len, &mut cuts);
                    }
                }
            }
        }
        // Lit intervals: visibility sampled uniformly in φ (dense near the light), boundaries bisected.
        let angular = h > 1e-12 * (w0.length() + len);
        let (phi_a, phi_b) = if angular {
            (((0.0 - t0) / h).atan(), ((len - t0) / h).atan())
        } else {
            (0.0, 0.0)
        };
        let t_of = |s: f64| {
            if angular {
                t0 + h * (phi_a + (phi_b - phi_a) * s).tan()
            } else {
                len * s
            }
        };
        let visible = |t: f64| {
            let x = o + d * t;
            let to = lp - x;
            let r = to.length();
            r > 0.0 && !self.world.bvh.occluded(x, to / r, self.eps, r - self.eps)
        };
        let shadow = shadowed(&self.world.bvh, o, d, len, Source::Point(lp));
        match &shadow {
            Some(sh) => cuts.extend(sh.iter().flat_map(|&(a, b)| [a, b])),
            None => self.find_boundaries(len, t_of, &visible, &mut cuts),
        }
        let lit = |t: f64| match &shadow {
            Some(sh) => !sh.iter().any(|&(a, b)| t > a && t < b),
            None => visible(t),
        };
        cuts.retain(|t| t.is_finite());
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        cuts.windows(2)
            .map(|p| (p[0], p[1]))
            .filter(|&(a, b)| {
                let mid = 0.5 * (a + b);
                b - a > 0.0 && light.intensity_toward(o + d * mid).max_element() > 0.0 && lit(mid)
            })
            .collect()
    }

    /// In-scatter of a directional light over [0, len]: lit intervals, each in closed form.
    fn directional(&self, o: DVec3, d: DVec3, len: f64, dir: DVec3, e: DVec3) -> DVec3 {
        let sigma_s = self.medium.sigma_s.as_dvec3();
        let sigma_t = self.medium.sigma_t.as_dvec3();
        let p = self.medium.phase.eval(dir.dot(-d));
        let fog = self.fog();
        let mut sum = DVec3::ZERO;
        for (a, b) in self.lit_intervals_directional(o, d, len, dir) {
            // ∫_a^b e^(−σt x) dx = e^(−σt a) (1 − e^(−σt (b−a))) / σt, stable as σt → 0.
            // With height fog, σ_s(x) dx = σ_s dL in the fog length L, so the same closed form
            // holds between the fog lengths of a and b.
            let (a, b) = match fog {
                None => (a, b),
                Some(f) => {
                    let la = f.length(o, d, a);
                    (la, la + f.length(o + d * a, d, b - a))
                }
            };
            let seg = DVec3::from_array([0, 1, 2].map(|c| exp_integral(sigma_t[c], a, b)));
            sum += sigma_s * p * e * seg;
        }
        sum
    }

    fn lit_intervals_directional(
        &self,
        o: DVec3,
        d: DVec3,
        len: f64,
        dir: DVec3,
    ) -> Vec<(f64, f64)> {
        let visible = |t: f64| {
            !self
                .world
                .bvh
                .occluded(o + d * t, -dir, self.eps, self.sun_distance)
        };
        let mut cuts = vec![0.0, len];
        let shadow = shadowed(
            &self.world.bvh,
            o,
            d,
            len,
            Source::Direction(-dir, self.sun_distance),
        );
        match &shadow {
            Some(sh) => cuts.extend(sh.iter().flat_map(|&(a, b)| [a, b])),
            None => self.find_boundaries(len, |s| len * s, &visible, &mut cuts),
        }
        let lit = |t: f64| match &shadow {
            Some(sh) => !sh.iter().any(|&(a, b)| t > a && t < b),
            None => visible(t),
        };
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        cuts.windows(2)
            .map(|p| (p[0], p[1]))
            .filter(|&(a, b)| b > a && lit(0.5 * (a + b)))
            .collect()
    }

    /// Samples visibility at `visibility_samples + 1` points t_of(k/N) and bisects every change.
    fn find_boundaries(
        &self,
        len: f64,
        t_of: impl Fn(f64) -> f64,
        visible: &impl Fn(f64) -> bool,
        cuts: &mut Vec<f64>,
    ) {
        let n = self.settings.visibility_samples.max(2);
        // Stay a hair inside the ray's ends: at t = len the sample sits on the surface itself.
        let inset = 1e-9 * len;
        let clamp = |t: f64| t.clamp(inset, len - inset);
        let mut prev_t = clamp(t_of(0.0));
        let mut prev_v = visible(prev_t);
        let tol = self.settings.bisect_tol * len.max(1e-12);
        for k in 1..=n {
            let t = clamp(t_of(k as f64 / n as f64));
            let v = visible(t);
            if v != prev_v {
                let (mut lo, mut hi) = (prev_t, t);
                while hi - lo > tol {
                    let m = 0.5 * (lo + hi);
                    if visible(m) == prev_v { lo = m } else { hi = m }
                }
                cuts.push(0.5 * (lo + hi));
            }
            prev_t = t;
            prev_v = v;
        }
    }
}

/// Ray parameters in (0, len) where w(t) = w0 + d t crosses the cone (w·a)² = c²|w|², w·a > 0.
fn cone_roots(w0: DVec3, d: DVec3, axis: DVec3, c: f64, len: f64, cuts: &mut Vec<f64>) {
    let (da, wa) = (d.dot(axis), w0.dot(axis));
    let c2 = c * c;
    let qa = da * da - c2;
    let qb = 2.0 * (wa * da - c2 * w0.dot(d));
    let qc = wa * wa - c2 * w0.length_squared();
    let mut push = |t: f64| {
        if t > 0.0 && t < len && (w0 + d * t).dot(axis) > 0.0 {
            cuts.push(t);
        }
    };
    if qa.abs() < 1e-15 {
        if qb.abs() > 1e-300 {
            push(-qc / qb);
        }
        return;
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return;
    }
    // Numerically stable quadratic roots.
    let q = -0.5 * (qb + qb.signum() * disc.sqrt());
    if q != 0.0 {
        push(qc / q);
    }
    push(q / qa);
}

/// Where w(t) crosses the plane through the light with normal `n`, in front of the light.
fn plane_root(w0: DVec3, d: DVec3, n: DVec3, axis: DVec3, len: f64, cuts: &mut Vec<f64>) {
    let dn = d.dot(n);
    if dn.abs() < 1e-300 {
        return;
    }
    let t = -w0.dot(n) / dn;
    if t > 0.0 && t < len && (w0 + d * t).dot(axis) > 0.0 {
        cuts.push(t);
    }
}
