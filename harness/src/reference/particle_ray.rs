//! The particle-medium path of the reference tracer ([`Tracer::trace`] on a scene with a
//! particle medium, ARCHITECTURE §1 "particles", §3).
//!
//! The integrand is smooth between sphere entries/exits of the camera ray (density jumps)
//! and the places where a light leg grazes a sphere (square-root kinks of the leg's optical
//! depth, roots of a quadratic). The ray is cut at both, each part integrated in a variable whose derivative vanishes at the ends (so those
//! kinks become smooth), and all panels of the ray refined together, largest error first, to
//! rel_tol × the ray's estimate. The spheres a piece's legs can cross are gathered once per
//! piece; each node sums exact chords over that short list (per-thread buffers, no allocation
//! per ray once they have grown).

use glam::DVec3;
use scenes::LightState;

use super::integrate::{RayRadiance, Tracer};
use super::particles::{
    LegList, ParticleField, Piece, PieceScratch, Toward, leg_depth, leg_grazes,
};
use super::quadrature::{exp, gk15};

impl Tracer<'_> {
    /// A particle medium's ray (ARCHITECTURE §1): the camera ray is cut into pieces of constant
    /// density (every sphere entry and exit), each piece intersected with each light's lit
    /// intervals and integrated adaptively; at every quadrature node the light leg's optical
    /// depth is the exact sum of chords toward the light (self-shadowing), over the spheres
    /// gathered once per piece that can cut any of its legs ([`ParticleField::gather_legs`]).
    /// The background medium adds its σ everywhere but, like the homogeneous medium, does not
    /// attenuate directional light on the light leg. Rays that hit nothing see the sky,
    /// attenuated along the whole ray; it lands in the `surface` AOV (the background's radiance).
    pub(super) fn trace_particles(
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
