//! The radiance of one camera ray (ARCHITECTURE §1), computed without any of the approximations the
//! methods make: exact visibility (ray casts for surfaces; for the medium, the exact shadowed
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
//! Particle media (see `Tracer::trace_particles`): the integrand is smooth between sphere
//! entries/exits of the camera ray (density jumps) and the places where a light leg grazes a
//! sphere (square-root kinks of the leg's optical depth, roots of a quadratic). The ray is cut
//! at both, each part integrated in a variable whose derivative vanishes at the ends (so those
//! kinks become smooth), and all panels of the ray refined together, largest error first, to
//! rel_tol × the ray's estimate. The spheres a piece's legs can cross are gathered once per
//! piece; each node sums exact chords over that short list (per-thread buffers, no allocation
//! per ray once they have grown).

use glam::DVec3;
use scenes::light::{pattern_breaks, spot_frame};
use scenes::{Homogeneous, LightState};

use super::particles::{
    LegList, ParticleField, Piece, PieceScratch, Toward, leg_depth, leg_grazes,
};
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
        let sigma_t = self.medium.sigma_t.as_dvec3();
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
            surface = self.surface(p, d, h) * exp(-sigma_t * h.t);
        }
        let ambient = self.medium.ambient.as_dvec3() * (DVec3::ONE - exp(-sigma_t * distance));
        RayRadiance {
            inscatter,
            surface,
            total: inscatter + surface + ambient,
            distance,
            hit: hit.is_some(),
        }
    }

    /// Reflected radiance at surface point `p` toward the eye (not yet attenuated).
    fn surface(&self, p: DVec3, d: DVec3, h: super::bvh::Hit) -> DVec3 {
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
        let sigma_t = self.medium.sigma_t.as_dvec3();
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
                        light.intensity_toward(p) * exp(-sigma_t * r) / (r * r),
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
        let w0 = o - lp;
        let integrand_t = |t: f64| -> DVec3 {
            let w = w0 + d * t;
            let r = w.length();
            if r <= 0.0 {
                return DVec3::ZERO;
            }
            let cos_theta = -w.dot(d) / r;
            sigma_s
                * (phase.eval(cos_theta) / (r * r))
                * light.intensity_toward(lp + w)
                * exp(-sigma_t * (t + r))
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
    fn lit_intervals(&self, o: DVec3, d: DVec3, len: f64, light: &LightState) -> Vec<(f64, f64)> {
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
        let mut sum = DVec3::ZERO;
        for (a, b) in self.lit_intervals_directional(o, d, len, dir) {
            // ∫_a^b e^(−σt x) dx = e^(−σt a) (1 − e^(−σt (b−a))) / σt, stable as σt → 0.
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

    /// A particle medium's ray (ARCHITECTURE §1): the camera ray is cut into pieces of constant
    /// density (every sphere entry and exit), each piece intersected with each light's lit
    /// intervals and integrated adaptively; at every quadrature node the light leg's optical
    /// depth is the exact sum of chords toward the light (self-shadowing), over the spheres
    /// gathered once per piece that can cut any of its legs ([`ParticleField::gather_legs`]).
    /// The background medium adds its σ everywhere but, like the homogeneous medium, does not
    /// attenuate directional light on the light leg. Rays that hit nothing see the sky,
    /// attenuated along the whole ray; it lands in the `surface` AOV (the background's radiance).
    fn trace_particles(
        &self,
        field: &ParticleField,
        o: DVec3,
        d: DVec3,
        near: f64,
        far: f64,
    ) -> RayRadiance {
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            self.trace_particles_in(field, o, d, near, far, &mut guard)
        })
    }

    fn trace_particles_in(
        &self,
        field: &ParticleField,
        o: DVec3,
        d: DVec3,
        near: f64,
        far: f64,
        sc: &mut ParticleScratch,
    ) -> RayRadiance {
        let bg_t = field.background_sigma_t;
        let bg_s = field.background_sigma_s;
        let hit = self.world.bvh.intersect(o, d, near, far);
        let distance = hit.map_or(far, |h| h.t);
        field.pieces_into(o, d, distance, &mut sc.piece_scratch, &mut sc.pieces);
        // Taken out (no allocation) so the jobs can borrow the rest of the scratch.
        let pieces = std::mem::take(&mut sc.pieces);
        let depth_end = pieces
            .last()
            .map_or(0.0, |p| p.depth0 + p.tau * (p.t1 - p.t0));
        // Every (light, lit piece) integral becomes jobs (see `piece_jobs`), each with a first
        // G7K15 panel; all are then refined together against one budget for the whole ray.
        sc.jobs.clear();
        sc.legs.clear();
        sc.shapes.clear();
        for (li, light) in self.lights.iter().enumerate() {
            let lit = self.lit_intervals(o, d, distance, light);
            let shape = LegShape::new(light, field, o, d, distance);
            sc.shapes.push(shape);
            let mut k = 0;
            for &(a, b) in &lit {
                while k < pieces.len() && pieces[k].t1 <= a {
                    k += 1;
                }
                let mut j = k;
                while j < pieces.len() && pieces[j].t0 < b {
                    let pc = pieces[j];
                    j += 1;
                    let sigma_s = bg_s + pc.sigma_s;
                    let (lo, hi) = (pc.t0.max(a), pc.t1.min(b));
                    if hi > lo && sigma_s.max_element() > 0.0 {
                        self.piece_jobs(field, &shape, li, o, d, (lo, hi), sigma_s, pc, sc);
                    }
                }
            }
        }
        sc.pieces = pieces;
        // Globally adaptive refinement (QUADPACK's strategy): split the panel with the largest
        // error estimate until the errors of all panels of the ray sum to at most rel_tol ×
        // the ray's running estimate. Kinks of the light-leg depth (legs grazing a sphere)
        // then get the few bisections they need, not a share proportional to their width.
        let ParticleScratch {
            jobs,
            legs,
            heap,
            shapes,
            ..
        } = sc;
        heap.clear();
        let (mut sum, mut err_sum) = (DVec3::ZERO, 0.0f64);
        for (k, job) in jobs.iter().enumerate() {
            sum += job.est;
            let e = job.err.max_element();
            err_sum += e;
            let (lo, hi) = job.panel();
            let min_width = (hi - lo) * 2f64.powi(-30);
            heap.push(HeapPanel {
                e,
                lo,
                hi,
                est: job.est,
                job: k as u32,
                min_width,
            });
        }
        // Panels too narrow to split: kept, their error no longer counted (it cannot shrink).
        let mut narrow = DVec3::ZERO;
        while let Some(top) = heap.peek() {
            let target = self.settings.rel_tol * sum.abs().max_element();
            if err_sum <= target.max(1e-300) || top.e <= 0.0 {
                break;
            }
            let p = heap.pop().unwrap();
            if p.hi - p.lo < p.min_width {
                narrow += p.est;
                err_sum -= p.e;
                continue;
            }
            let job = &jobs[p.job as usize];
            let light = &self.lights[job.light];
            let f = |u: f64| self.job_value(field, &shapes[job.light], light, job, legs, o, d, u);
            let m = 0.5 * (p.lo + p.hi);
            let (l, le) = gk15(&f, p.lo, m);
            let (r, re) = gk15(&f, m, p.hi);
            sum += l + r - p.est;
            let (le, re) = (le.max_element(), re.max_element());
            err_sum += le + re - p.e;
            for (lo, hi, est, e) in [(p.lo, m, l, le), (m, p.hi, r, re)] {
                heap.push(HeapPanel {
                    e,
                    lo,
                    hi,
                    est,
                    ..p
                });
            }
        }
        // The sum again from the final panels (the running one carries rounding).
        let inscatter = heap.iter().map(|p| p.est).sum::<DVec3>() + narrow;
        let atten = exp(-(bg_t * distance + DVec3::splat(depth_end)));
        let surface = match hit {
            Some(h) => self.surface(o + d * h.t, d, h) * atten,
            None => field.sky * atten,
        };
        RayRadiance {
            inscatter,
            surface,
            total: inscatter + surface,
            distance,
            hit: hit.is_some(),
        }
    }

    /// Appends the jobs of the lit part [lo, hi] of piece `pc` for light `li`, each with its
    /// first G7K15 panel. The spheres that can cut its light legs are gathered once; where a
    /// leg grazes one of them the light leg's depth has a square-root kink, so the span is
    /// cut there and each part integrated in a variable smooth at such ends. A span whose
    /// legs sweep many spheres (a long piece in a background haze, whose legs graze spheres
    /// by the thousand) is halved until its lists are short, and is left to the adaptive
    /// refinement instead, which resolves only the kinks that matter; past SPLIT_DEPTH
    /// halvings its nodes walk the field's BVH.
    #[allow(clippy::too_many_arguments)]
    fn piece_jobs(
        &self,
        field: &ParticleField,
        shape: &LegShape,
        li: usize,
        o: DVec3,
        d: DVec3,
        (lo, hi): (f64, f64),
        sigma_s: DVec3,
        pc: Piece,
        sc: &mut ParticleScratch,
    ) {
        let light = &self.lights[li];
        let toward = shape.toward();
        sc.spans.clear();
        sc.spans.push((lo, hi, 0));
        while let Some((lo, hi, depth)) = sc.spans.pop() {
            let first = sc.legs.len();
            field.gather_legs(o + d * lo, o + d * hi, toward, &mut sc.legs);
            let many = sc.legs.len() - first > MAX_LEGS;
            if many && depth < SPLIT_DEPTH {
                sc.legs.truncate(first);
                let m = 0.5 * (lo + hi);
                sc.spans.push((m, hi, depth + 1));
                sc.spans.push((lo, m, depth + 1));
                continue;
            }
            let legs = if many {
                sc.legs.truncate(first);
                None
            } else {
                Some((first, sc.legs.len()))
            };
            let smooth = depth == 0 && legs.is_some();
            sc.cuts.clear();
            sc.cuts.push(lo);
            if let (true, Some((g0, g1))) = (smooth, legs) {
                leg_grazes(sc.legs.view(g0, g1), o, d, lo, hi, toward, &mut sc.cuts);
            }
            sc.cuts.push(hi);
            sc.cuts.sort_unstable_by(f64::total_cmp);
            let min_gap = 1e-12 * (hi - lo).max(hi.abs());
            let mut a = lo;
            for k in 1..sc.cuts.len() {
                let b = sc.cuts[k];
                if b - a <= min_gap && k + 1 < sc.cuts.len() {
                    continue;
                }
                let (x0, x1) = shape.bounds(a, b);
                a = b;
                if x1 <= x0 {
                    continue;
                }
                let mut job = Job {
                    light: li,
                    legs,
                    smooth,
                    sigma_s,
                    pc,
                    x0,
                    x1,
                    est: DVec3::ZERO,
                    err: DVec3::ZERO,
                };
                let f = |u: f64| self.job_value(field, shape, light, &job, &sc.legs, o, d, u);
                let (u0, u1) = job.panel();
                (job.est, job.err) = gk15(&f, u0, u1);
                sc.jobs.push(job);
            }
        }
    }

    /// A job's integrand in its panel variable u (see [`Job::panel`]).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn job_value(
        &self,
        field: &ParticleField,
        shape: &LegShape,
        light: &LightState,
        job: &Job,
        legs: &LegList,
        o: DVec3,
        d: DVec3,
        u: f64,
    ) -> DVec3 {
        if !job.smooth {
            return self.piece_value(field, shape, light, job, legs, o, d, u);
        }
        // x = x0 + (x1 − x0)(1 − cos πu)/2: dx/du vanishes at both ends, so √(x − x0) and
        // √(x1 − x) become smooth in u (the grazing kinks sit at the ends of a job).
        let (s, c) = (std::f64::consts::PI * u).sin_cos();
        let w = job.x1 - job.x0;
        let x = job.x0 + w * 0.5 * (1.0 - c);
        self.piece_value(field, shape, light, job, legs, o, d, x)
            * (w * 0.5 * std::f64::consts::PI * s)
    }

    /// The in-scatter integrand σ_s p(θ) I(ω) e^(−τ_eye(t) − τ_light(t)) / r² of one
    /// constant-density piece, in its integration variable x (see [`LegShape`]).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn piece_value(
        &self,
        field: &ParticleField,
        shape: &LegShape,
        light: &LightState,
        job: &Job,
        legs: &LegList,
        o: DVec3,
        d: DVec3,
        x: f64,
    ) -> DVec3 {
        let depth = |x: DVec3, u: DVec3, smax: f64| match job.legs {
            Some((a, b)) => leg_depth(legs.view(a, b), x, u, smax),
            None => field.optical_depth(x, u, 0.0, smax),
        };
        let bg_t = field.background_sigma_t;
        let pc = &job.pc;
        // Eye-leg optical depth at t (RGB: background + grey particles).
        let eye = |t: f64| bg_t * t + DVec3::splat(pc.depth0 + pc.tau * (t - pc.t0));
        match *shape {
            LegShape::Sun { l, e } => {
                let t = x;
                let leg = depth(o + d * t, l, f64::INFINITY);
                job.sigma_s * e * exp(-(eye(t) + DVec3::splat(leg)))
            }
            LegShape::Local { lp, angle } => {
                let (t, jac) = match angle {
                    // Biri's angle φ: t = t0 + h tan φ, dt/r² = dφ/h.
                    Some((t0, h)) => {
                        let r = h / x.cos();
                        (t0 + h * x.tan(), r * r / h)
                    }
                    None => (x, 1.0),
                };
                let p = o + d * t;
                let w = p - lp;
                let r = w.length();
                if r <= 0.0 {
                    return DVec3::ZERO;
                }
                // θ between the light's propagation (w/r) and the direction toward the eye (−d).
                let cos_theta = -w.dot(d) / r;
                let leg = depth(p, -w / r, r);
                job.sigma_s
                    * (field.phase.eval(cos_theta) / (r * r) * jac)
                    * light.intensity_toward(p)
                    * exp(-(eye(t) + bg_t * r + DVec3::splat(leg)))
            }
        }
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

/// Per-thread buffers of the particle path, grown once and reused by every ray.
#[derive(Default)]
struct ParticleScratch {
    piece_scratch: PieceScratch,
    pieces: Vec<Piece>,
    jobs: Vec<Job>,
    legs: LegList,
    heap: std::collections::BinaryHeap<HeapPanel>,
    /// Cut points of one span.
    cuts: Vec<f64>,
    /// Spans awaiting a gather: (t0, t1, halvings).
    spans: Vec<(f64, f64, u32)>,
    /// Per light of the scene.
    shapes: Vec<LegShape>,
}

/// A panel of the particle path's global refinement, ordered by its error estimate.
#[derive(Clone, Copy, Debug)]
struct HeapPanel {
    /// Error estimate (largest channel).
    e: f64,
    lo: f64,
    hi: f64,
    est: DVec3,
    job: u32,
    /// Panels narrower than this (2⁻³⁰ of their job's interval) are not split.
    min_width: f64,
}

impl PartialEq for HeapPanel {
    fn eq(&self, other: &Self) -> bool {
        self.e.total_cmp(&other.e).is_eq()
    }
}
impl Eq for HeapPanel {}
impl PartialOrd for HeapPanel {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for HeapPanel {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.e.total_cmp(&other.e)
    }
}

/// Above this many gathered spheres a span is halved (at most SPLIT_DEPTH times; then its
/// nodes walk the field's BVH, which costs about as much as testing this many in a row).
const MAX_LEGS: usize = 160;
const SPLIT_DEPTH: u32 = 6;

thread_local! {
    static SCRATCH: std::cell::RefCell<ParticleScratch> = std::cell::RefCell::default();
}

/// One (light, lit constant-density piece) integral of a particle ray.
#[derive(Clone, Copy, Debug)]
struct Job {
    light: usize,
    /// Range of its gathered spheres in the scratch `legs`; None: use the field's BVH.
    legs: Option<(usize, usize)>,
    /// Cut at every graze and integrated in the smoothing variable u (see `Tracer::job_value`).
    smooth: bool,
    sigma_s: DVec3,
    pc: Piece,
    /// Bounds in the integration variable.
    x0: f64,
    x1: f64,
    /// First G7K15 panel.
    est: DVec3,
    err: DVec3,
}

impl Job {
    /// The domain of its panels: u in [0, 1] (see `Tracer::job_value`) when smooth, else the
    /// integration variable itself.
    fn panel(&self) -> (f64, f64) {
        if self.smooth {
            (0.0, 1.0)
        } else {
            (self.x0, self.x1)
        }
    }
}

/// What a light needs per quadrature node of a particle ray, and the integration variable:
/// t for the sun (phase and irradiance constant along the ray); Biri's angle φ for a local
/// light (dt/r² = dφ/h) unless the ray passes through the light.
#[derive(Clone, Copy, Debug)]
enum LegShape {
    /// Unit vector toward the sun; irradiance × phase.
    Sun { l: DVec3, e: DVec3 },
    /// Light position; (t0, h) of the closest approach when integrating in φ.
    Local {
        lp: DVec3,
        angle: Option<(f64, f64)>,
    },
}

impl LegShape {
    fn new(light: &LightState, field: &ParticleField, o: DVec3, d: DVec3, len: f64) -> LegShape {
        match light {
            LightState::Directional {
                direction,
                irradiance,
            } => LegShape::Sun {
                l: -direction.as_dvec3(),
                e: irradiance.as_dvec3() * field.phase.eval(direction.as_dvec3().dot(-d)),
            },
            _ => {
                let lp = light.position().unwrap().as_dvec3();
                let w0 = o - lp;
                let t0 = -w0.dot(d);
                let h = (w0 + d * t0).length();
                let angle = (h > 1e-12 * (w0.length() + len)).then_some((t0, h));
                LegShape::Local { lp, angle }
            }
        }
    }

    fn toward(&self) -> Toward {
        match *self {
            LegShape::Sun { l, .. } => Toward::Direction(l),
            LegShape::Local { lp, .. } => Toward::Point(lp),
        }
    }

    /// [lo, hi] in t → bounds in the integration variable.
    fn bounds(&self, lo: f64, hi: f64) -> (f64, f64) {
        match *self {
            LegShape::Local {
                angle: Some((t0, h)),
                ..
            } => (((lo - t0) / h).atan(), ((hi - t0) / h).atan()),
            _ => (lo, hi),
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

fn exp(v: DVec3) -> DVec3 {
    DVec3::new(v.x.exp(), v.y.exp(), v.z.exp())
}

/// ∫_a^b e^(−s x) dx.
pub fn exp_integral(s: f64, a: f64, b: f64) -> f64 {
    if s * (b - a) < 1e-12 {
        return (b - a) * (-s * a).exp();
    }
    (-s * a).exp() * -(-s * (b - a)).exp_m1() / s
}

// Gauss–Kronrod 7–15 nodes and weights (QUADPACK qk15).
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_728_0,
];
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One G7K15 panel: (Kronrod estimate, |Kronrod − Gauss| per channel).
pub fn gk15(f: &impl Fn(f64) -> DVec3, a: f64, b: f64) -> (DVec3, DVec3) {
    let c = 0.5 * (a + b);
    let hl = 0.5 * (b - a);
    let fc = f(c);
    let mut k = fc * WGK[7];
    let mut g = fc * WG[3];
    for j in 0..7 {
        let x = hl * XGK[j];
        let s = f(c - x) + f(c + x);
        k += s * WGK[j];
        if j % 2 == 1 {
            g += s * WG[j / 2];
        }
    }
    (k * hl, (k - g).abs() * hl)
}

/// Adaptive G7K15 on [a, b] until each panel's error is below `rel_tol` times the running
/// estimate of the whole integral (per channel maximum), or panels are 2⁻³⁰ of the interval.
pub fn adaptive(f: &impl Fn(f64) -> DVec3, a: f64, b: f64, rel_tol: f64) -> DVec3 {
    if b <= a {
        return DVec3::ZERO;
    }
    let (whole, err) = gk15(f, a, b);
    let scale = whole.abs().max_element();
    refine(f, a, b, whole, err, rel_tol * scale.max(1e-300))
}

/// Adaptive G7K15 on [a, b] from its first panel (whole, err) until the summed panel errors
/// are below the absolute `target` (per channel maximum), or panels are 2⁻³⁰ of the interval.
pub fn refine(
    f: &impl Fn(f64) -> DVec3,
    a: f64,
    b: f64,
    whole: DVec3,
    err: DVec3,
    target: f64,
) -> DVec3 {
    if b <= a {
        return DVec3::ZERO;
    }
    let min_width = (b - a) * 2f64.powi(-30);
    let mut stack = vec![(a, b, whole, err)];
    let mut sum = DVec3::ZERO;
    while let Some((lo, hi, est, e)) = stack.pop() {
        // Each panel gets a share of the error budget proportional to its width.
        let allowed = target * (hi - lo) / (b - a);
        if e.max_element() <= allowed.max(1e-300) || hi - lo < min_width {
            sum += est;
            continue;
        }
        let m = 0.5 * (lo + hi);
        let (l, le) = gk15(f, lo, m);
        let (r, re) = gk15(f, m, hi);
        stack.push((lo, m, l, le));
        stack.push((m, hi, r, re));
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adaptive_quadrature_integrates_a_peak() {
        // ∫_{-1}^{1} 1/(1e-4 + x²) dx = 2/√1e-4 · atan(1/√1e-4).
        let f = |x: f64| DVec3::splat(1.0 / (1e-4 + x * x));
        let exact = 2.0 / 1e-2 * (1.0f64 / 1e-2).atan();
        let got = adaptive(&f, -1.0, 1.0, 1e-10).x;
        assert!((got / exact - 1.0).abs() < 1e-9, "{got} vs {exact}");
    }

    #[test]
    fn exp_integral_matches_its_limit() {
        assert!((exp_integral(0.0, 1.0, 3.0) - 2.0).abs() < 1e-15);
        let s = 0.7;
        let exact = ((-s * 1.0f64).exp() - (-s * 3.0f64).exp()) / s;
        assert!((exp_integral(s, 1.0, 3.0) - exact).abs() < 1e-15);
    }
}
