//! Particle media for the reference (DESIGN §1, "particles"): exact optical depth along any
//! segment as Σ τ_j · chord_j through the spheres, found with a BVH over the particles (f64,
//! median split, leaves ≤ 4, fixed-stack traversal), and the camera ray cut into pieces of
//! constant density at every sphere entry and exit, so the in-scatter integrand is smooth on
//! each piece (see `Tracer::trace_particles` in [`super::integrate`]).

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
        ParticleField {
            spheres,
            nodes,
            background_sigma_t: p.background.sigma_t.as_dvec3(),
            background_sigma_s: p.background.sigma_s.as_dvec3(),
            phase: p.phase,
            sky: p.sky.as_dvec3(),
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
        let mut events: Vec<(f64, usize, bool)> = Vec::new();
        let mut hit: Vec<Sphere> = Vec::new();
        self.for_each_chord(o, d, 0.0, len, |s, a, b| {
            events.push((a, hit.len(), true));
            events.push((b, hit.len(), false));
            hit.push(*s);
        });
        events.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut out = Vec::with_capacity(events.len() + 1);
        let (mut tau, mut sigma_s, mut active) = (0.0f64, DVec3::ZERO, 0usize);
        let (mut t, mut depth) = (0.0f64, 0.0f64);
        for &(te, k, enter) in &events {
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
        out
    }
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
