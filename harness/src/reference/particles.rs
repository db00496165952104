//! Particle media for the reference (ARCHITECTURE §1, "particles"): exact optical depth along any
//! segment as Σ τ_j · chord_j through the spheres, found with a BVH over the particles (f64,
//! median split, leaves ≤ 4, fixed-stack traversal), and the camera ray cut into pieces of
//! constant density at every sphere entry and exit (see `Tracer::trace_particles` in
//! [`super::integrate`]). For the light legs of a piece, [`ParticleField::gather_legs`] lists
//! once every sphere that can cut any of them (a conservative superset, so sums over the list
//! are the exact sums) and [`leg_grazes`] finds where a leg grazes one (a kink to cut at).

use glam::DVec3;
use scenes::{Particles, Phase};

#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
    /// Extinction τ inside, 1/m.
    pub tau: f64,
    /// σ_s inside = albedo · τ, RGB.
    pub sigma_s: DVec3,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first sphere; inner: right child (left is self + 1).
    offset: u32,
    /// Leaf: sphere count (> 0); inner: 0.
    count: u32,
}

/// The particles of one scene, with their BVH, plus the background medium and the sky.
pub struct ParticleField {
    /// In leaf order.
    pub spheres: Vec<Sphere>,
    nodes: Vec<Node>,
    pub background_sigma_t: DVec3,
    pub background_sigma_s: DVec3,
    pub phase: Phase,
    pub sky: DVec3,
    /// Largest coordinate magnitude of any sphere's bounds, m (for rounding slack).
    extent: f64,
}

const LEAF: usize = 4;
const STACK: usize = 64;

/// One constant-density piece [t0, t1] of a camera ray.
#[derive(Clone, Copy, Debug)]
pub struct Piece {
    pub t0: f64,
    pub t1: f64,
    /// Particle extinction on the piece (grey), 1/m.
    pub tau: f64,
    /// Particle σ_s on the piece, RGB, 1/m.
    pub sigma_s: DVec3,
    /// Particle optical depth from the eye to t0.
    pub depth0: f64,
}

impl ParticleField {
    pub fn new(p: &Particles) -> ParticleField {
        let spheres: Vec<Sphere> = p
            .particles
            .iter()
            .map(|q| Sphere {
                center: q.center.as_dvec3(),
                radius: q.radius as f64,
                tau: q.density as f64,
                sigma_s: q.albedo.as_dvec3() * q.density as f64,
            })
            .collect();
        Self::from_spheres(spheres, p)
    }

    fn from_spheres(mut spheres: Vec<Sphere>, p: &Particles) -> ParticleField {
        let mut nodes = Vec::with_capacity(2 * spheres.len() / LEAF + 2);
        let n = spheres.len();
        build(&mut spheres, 0, n, &mut nodes, 0);
        let extent = nodes
            .first()
            .map_or(0.0, |r| r.lo.abs().max(r.hi.abs()).max_element());
        ParticleField {
            spheres,
            nodes,
            background_sigma_t: p.background.sigma_t.as_dvec3(),
            background_sigma_s: p.background.sigma_s.as_dvec3(),
            phase: p.phase,
            sky: p.sky.as_dvec3(),
            extent,
        }
    }

    /// Calls `f(sphere, t_in, t_out)` for every sphere the ray o + t d (d unit) crosses with a
    /// chord overlapping (tmin, tmax), the chord clipped to it.
    pub fn for_each_chord(
        &self,
        o: DVec3,
        d: DVec3,
        tmin: f64,
        tmax: f64,
        mut f: impl FnMut(&Sphere, f64, f64),
    ) {
        if self.spheres.is_empty() {
            return;
        }
        let inv = DVec3::ONE / d;
        let mut stack = [0u32; STACK];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let idx = stack[sp];
            let node = &self.nodes[idx as usize];
            if !slab(node.lo, node.hi, o, inv, tmin, tmax) {
                continue;
            }
            if node.count > 0 {
                for s in &self.spheres[node.offset as usize..(node.offset + node.count) as usize] {
                    if let Some((a, b)) = chord(s, o, d) {
                        let (a, b) = (a.max(tmin), b.min(tmax));
                        if b > a {
                            f(s, a, b);
                        }
                    }
                }
            } else if sp + 2 <= STACK {
                stack[sp] = node.offset;
                stack[sp + 1] = idx + 1;
                sp += 2;
            }
        }
    }

    /// Particle optical depth Σ τ_j · chord_j along o + t d, t in [tmin, tmax].
    pub fn optical_depth(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> f64 {
        let mut sum = 0.0;
        self.for_each_chord(o, d, tmin, tmax, |s, a, b| sum += s.tau * (b - a));
        sum
    }

    /// The ray [0, len] cut at every sphere entry and exit into pieces of constant density.
    pub fn pieces(&self, o: DVec3, d: DVec3, len: f64) -> Vec<Piece> {
        let mut out = Vec::new();
        self.pieces_into(o, d, len, &mut PieceScratch::default(), &mut out);
        out
    }

    /// [`Self::pieces`] into `out` (cleared first), reusing `scratch`: no allocation per ray
    /// once the buffers have grown.
    pub fn pieces_into(
        &self,
        o: DVec3,
        d: DVec3,
        len: f64,
        scratch: &mut PieceScratch,
        out: &mut Vec<Piece>,
    ) {
        out.clear();
        let PieceScratch { events, hit } = scratch;
        events.clear();
        hit.clear();
        self.for_each_chord(o, d, 0.0, len, |s, a, b| {
            events.push((a, hit.len(), true));
            events.push((b, hit.len(), false));
            hit.push(*s);
        });
        // Exits before entries at equal t (so empty space resets to exactly empty), then by
        // sphere: a total order, so the unstable (allocation-free) sort is deterministic.
        events.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.2.cmp(&y.2)).then(x.1.cmp(&y.1)));
        let (mut tau, mut sigma_s, mut active) = (0.0f64, DVec3::ZERO, 0usize);
        let (mut t, mut depth) = (0.0f64, 0.0f64);
        for &(te, k, enter) in events.iter() {
            if te > t {
                out.push(Piece {
                    t0: t,
                    t1: te,
                    tau,
                    sigma_s,
                    depth0: depth,
                });
                depth += tau * (te - t);
                t = te;
            }
            let s = &hit[k];
            if enter {
                active += 1;
                tau += s.tau;
                sigma_s += s.sigma_s;
            } else {
                active -= 1;
                tau -= s.tau;
                sigma_s -= s.sigma_s;
                if active == 0 {
                    // No drift from adding and subtracting: empty space is exactly empty.
                    tau = 0.0;
                    sigma_s = DVec3::ZERO;
                }
            }
        }
        if len > t {
            out.push(Piece {
                t0: t,
                t1: len,
                tau,
                sigma_s,
                depth0: depth,
            });
        }
    }

    /// Appends to `out` every sphere that may cut a light leg from a point of the segment
    /// [a, b] to the light: a conservative superset (spheres within their radius of the fan
    /// the legs sweep, with a margin), so sums over it equal sums over the whole field. One
    /// BVH walk per camera-ray piece instead of one per quadrature node, and the nodes then
    /// loop over a short contiguous array.
    pub fn gather_legs(&self, a: DVec3, b: DVec3, toward: Toward, out: &mut LegList) {
        if self.spheres.is_empty() {
            return;
        }
        let fan = Fan::new(a, b, toward, self.extent);
        let mut stack = [0u32; STACK];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let idx = stack[sp];
            let node = &self.nodes[idx as usize];
            let c = 0.5 * (node.lo + node.hi);
            if !fan.near(c, 0.5 * (node.hi - node.lo).length()) {
                continue;
            }
            if node.count > 0 {
                for s in &self.spheres[node.offset as usize..(node.offset + node.count) as usize] {
                    if fan.near(s.center, s.radius) {
                        out.push(s);
                    }
                }
            } else if sp + 2 <= STACK {
                stack[sp] = node.offset;
                stack[sp + 1] = idx + 1;
                sp += 2;
            }
        }
    }
}

/// Reusable buffers of [`ParticleField::pieces_into`].
#[derive(Default)]
pub struct PieceScratch {
    events: Vec<(f64, usize, bool)>,
    hit: Vec<Sphere>,
}

/// Where light legs go from a point x: to a point light (the segment x → light), or toward
/// the sun (the unbounded ray x + s·l, l unit).
#[derive(Clone, Copy, Debug)]
pub enum Toward {
    Point(DVec3),
    Direction(DVec3),
}

/// Gathered spheres as the light-leg sums need them, structure-of-arrays so the per-node
/// loop is branch-free and vectorises.
#[derive(Default)]
pub struct LegList {
    cx: Vec<f64>,
    cy: Vec<f64>,
    cz: Vec<f64>,
    r2: Vec<f64>,
    tau: Vec<f64>,
}

/// A range of a [`LegList`].
#[derive(Clone, Copy)]
pub struct Legs<'a> {
    cx: &'a [f64],
    cy: &'a [f64],
    cz: &'a [f64],
    r2: &'a [f64],
    tau: &'a [f64],
}

impl LegList {
    pub fn len(&self) -> usize {
        self.tau.len()
    }

    pub fn is_empty(&self) -> bool {
        self.tau.is_empty()
    }

    pub fn clear(&mut self) {
        self.truncate(0);
    }

    pub fn truncate(&mut self, n: usize) {
        for v in [
            &mut self.cx,
            &mut self.cy,
            &mut self.cz,
            &mut self.r2,
            &mut self.tau,
        ] {
            v.truncate(n);
        }
    }

    fn push(&mut self, s: &Sphere) {
        self.cx.push(s.center.x);
        self.cy.push(s.center.y);
        self.cz.push(s.center.z);
        self.r2.push(s.radius * s.radius);
        self.tau.push(s.tau);
    }

    /// Entries a..b.
    pub fn view(&self, a: usize, b: usize) -> Legs<'_> {
        Legs {
            cx: &self.cx[a..b],
            cy: &self.cy[a..b],
            cz: &self.cz[a..b],
            r2: &self.r2[a..b],
            tau: &self.tau[a..b],
        }
    }
}

impl Legs<'_> {
    fn center(&self, k: usize) -> DVec3 {
        DVec3::new(self.cx[k], self.cy[k], self.cz[k])
    }
}

/// Σ τ·chord over `legs` along x + s u (u unit), s in (0, smax): the chords of
/// [`ParticleField::optical_depth`] (perpendicular offset² as |q|² − (q·u)²), summed over a
/// gathered list without branches (a miss has h = 0, so an empty clipped chord).
#[inline]
pub fn leg_depth(legs: Legs, x: DVec3, u: DVec3, smax: f64) -> f64 {
    let n = legs.tau.len();
    let (cx, cy, cz, r2, tau) = (
        &legs.cx[..n],
        &legs.cy[..n],
        &legs.cz[..n],
        &legs.r2[..n],
        &legs.tau[..n],
    );
    let mut sum = 0.0;
    for k in 0..n {
        let (qx, qy, qz) = (cx[k] - x.x, cy[k] - x.y, cz[k] - x.z);
        let tc = qx * u.x + qy * u.y + qz * u.z;
        let h2 = r2[k] - (qx * qx + qy * qy + qz * qz - tc * tc);
        let h = h2.max(0.0).sqrt();
        let len = (tc + h).min(smax) - (tc - h).max(0.0);
        sum += tau[k] * len.max(0.0);
    }
    sum
}

/// Appends to `out` the ray parameters t in (lo, hi) where the light leg from o + t d grazes
/// one of `spheres`: there its chord, so the leg's optical depth, has a square-root kink, and
/// quadrature converges slowly across it. (Each is a root of a quadratic in t: the distance
/// from the centre to the leg's line equals the radius.)
pub fn leg_grazes(
    spheres: Legs,
    o: DVec3,
    d: DVec3,
    lo: f64,
    hi: f64,
    toward: Toward,
    out: &mut Vec<f64>,
) {
    let mut push = |qa: f64, qb: f64, qc: f64| {
        // qa t² + qb t + qc = 0, numerically stable roots.
        if qa.abs() <= 1e-300 {
            if qb.abs() > 1e-300 {
                let t = -qc / qb;
                if t > lo && t < hi {
                    out.push(t);
                }
            }
            return;
        }
        let disc = qb * qb - 4.0 * qa * qc;
        if disc <= 0.0 {
            return;
        }
        let q = -0.5 * (qb + qb.signum() * disc.sqrt());
        for t in [q / qa, if q != 0.0 { qc / q } else { f64::NAN }] {
            if t > lo && t < hi {
                out.push(t);
            }
        }
    };
    match toward {
        Toward::Direction(l) => {
            // |A − t B|² = r², A, B the centre offset and d with their l components removed.
            let b = d - l * d.dot(l);
            let bb = b.length_squared();
            for k in 0..spheres.tau.len() {
                let q = spheres.center(k) - o;
                let a = q - l * q.dot(l);
                push(bb, -2.0 * a.dot(b), a.length_squared() - spheres.r2[k]);
            }
        }
        Toward::Point(lp) => {
            // |cl × w(t)|² = r² |w(t)|², w(t) = w0 + t d the leg's direction (unnormalised).
            let w0 = o - lp;
            let (dd, wd, ww) = (d.length_squared(), w0.dot(d), w0.length_squared());
            for k in 0..spheres.tau.len() {
                let (cl, r2) = (spheres.center(k) - lp, spheres.r2[k]);
                let (u, v) = (cl.cross(w0), cl.cross(d));
                push(
                    v.length_squared() - r2 * dd,
                    2.0 * (u.dot(v) - r2 * wd),
                    u.length_squared() - r2 * ww,
                );
            }
        }
    }
}

/// The set swept by the light legs of the points of a segment [a, b]: the triangle
/// (light, a, b) for a point light, the half-strip {a + u (b − a) + s l, s ≥ 0} for the sun.
struct Fan {
    a: DVec3,
    b: DVec3,
    toward: Toward,
    /// Sun: b − a and its squared length, both with the l component removed.
    e: DVec3,
    ee: f64,
    /// Absolute slack on every radius, m.
    slack: f64,
    /// Point light: the triangle's bounding box (a cheap rejection before the distance).
    lo: DVec3,
    hi: DVec3,
}

impl Fan {
    /// `extent`: a length bounding the field's coordinates (sets the absolute slack).
    fn new(a: DVec3, b: DVec3, toward: Toward, extent: f64) -> Fan {
        let (mut e, mut ee) = (DVec3::ZERO, 0.0);
        if let Toward::Direction(l) = toward {
            e = (b - a) - l * (b - a).dot(l);
            ee = e.length_squared();
        }
        let scale = a.abs().max_element() + b.abs().max_element() + extent;
        let (lo, hi) = match toward {
            Toward::Point(lp) => (a.min(b).min(lp), a.max(b).max(lp)),
            Toward::Direction(_) => (DVec3::NEG_INFINITY, DVec3::INFINITY),
        };
        Fan {
            a,
            b,
            toward,
            e,
            ee,
            slack: 1e-9 * scale.max(1.0),
            lo,
            hi,
        }
    }

    /// Whether a ball (c, r) may meet the fan. Conservative: a relative and an absolute margin
    /// absorb rounding (a false positive costs a little time, a false negative a wrong sum).
    #[inline]
    fn near(&self, c: DVec3, r: f64) -> bool {
        let r = r * (1.0 + 1e-6) + self.slack;
        match self.toward {
            Toward::Direction(l) => {
                // Some leg line within r of c (in the plane ⊥ l), and c not wholly behind both
                // ends of the segment along l.
                let ca = c - self.a;
                let cal = ca.dot(l);
                if cal.max(cal - (self.b - self.a).dot(l)) < -r {
                    return false;
                }
                let p = ca - l * cal;
                let u = if self.ee > 0.0 {
                    (p.dot(self.e) / self.ee).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (p - self.e * u).length_squared() <= r * r
            }
            Toward::Point(lp) => {
                let r3 = DVec3::splat(r);
                !((c + r3).cmplt(self.lo).any() || (c - r3).cmpgt(self.hi).any())
                    && triangle_distance2(c, lp, self.a, self.b) <= r * r
            }
        }
    }
}

/// Squared distance from p to the triangle (a, b, c), degenerate triangles included.
fn triangle_distance2(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let n = (b - a).cross(c - a);
    let nn = n.length_squared();
    if nn > 0.0 {
        let ap = p - a;
        let inside = n.dot((b - a).cross(ap)) >= 0.0
            && n.dot((c - b).cross(p - b)) >= 0.0
            && n.dot((a - c).cross(p - c)) >= 0.0;
        if inside {
            let h = ap.dot(n);
            return h * h / nn;
        }
    }
    segment_distance2(p, a, b)
        .min(segment_distance2(p, b, c))
        .min(segment_distance2(p, c, a))
}

fn segment_distance2(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let e = b - a;
    let ee = e.length_squared();
    let u = if ee > 0.0 {
        ((p - a).dot(e) / ee).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - a - e * u).length_squared()
}

/// The chord (t_in, t_out) of the ray through a sphere, if any. Stable for distant origins:
/// the squared distance of the centre from the ray comes from the perpendicular component.
pub fn chord(s: &Sphere, o: DVec3, d: DVec3) -> Option<(f64, f64)> {
    let q = s.center - o;
    let tc = q.dot(d);
    let perp = q - d * tc;
    let h2 = s.radius * s.radius - perp.length_squared();
    if h2 <= 0.0 {
        return None;
    }
    let h = h2.sqrt();
    Some((tc - h, tc + h))
}

fn slab(lo: DVec3, hi: DVec3, o: DVec3, inv: DVec3, tmin: f64, tmax: f64) -> bool {
    let a = (lo - o) * inv;
    let b = (hi - o) * inv;
    let t0 = a.min(b).max_element().max(tmin);
    let t1 = a.max(b).min_element().min(tmax);
    // NaN (0 · ∞ on a slab face) compares false: treat it as a hit, conservatively.
    !(t0 > t1)
}

fn build(s: &mut [Sphere], start: usize, end: usize, nodes: &mut Vec<Node>, depth: usize) -> u32 {
    let me = nodes.len() as u32;
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let (mut clo, mut chi) = (lo, hi);
    for x in &s[start..end] {
        lo = lo.min(x.center - DVec3::splat(x.radius));
        hi = hi.max(x.center + DVec3::splat(x.radius));
        clo = clo.min(x.center);
        chi = chi.max(x.center);
    }
    nodes.push(Node {
        lo,
        hi,
        offset: start as u32,
        count: (end - start) as u32,
    });
    if end - start <= LEAF || depth >= 60 {
        return me;
    }
    let ext = chi - clo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = (start + end) / 2;
    s[start..end].select_nth_unstable_by(mid - start, |a, b| {
        a.center[axis].total_cmp(&b.center[axis])
    });
    build(s, start, mid, nodes, depth + 1);
    let right = build(s, mid, end, nodes, depth + 1);
    nodes[me as usize].offset = right;
    nodes[me as usize].count = 0;
    me
}

#[cfg(test)]
#[path = "particles_tests.rs"]
mod tests;
