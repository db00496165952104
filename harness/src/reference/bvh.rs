//! A bounding volume hierarchy over world-space triangles, in f64.
//!
//! Our own rather than a crate's: the reference needs f64 throughout (the crates we looked at —
//! `bvh`, `obvhs` — are f32), an any-hit query that ignores triangles which cast no volumetric
//! shadow, and traversal with no allocation per ray (a fixed stack), since it runs hundreds of
//! millions of shadow rays per image. Built top-down with a binned SAH (12 bins), leaves ≤ 4.

use glam::DVec3;

/// A triangle as the reference sees it.
#[derive(Clone, Copy, Debug)]
pub struct Tri {
    pub p: [DVec3; 3],
    /// Whether it blocks light (objects with `casts_volumetric_shadow`).
    pub casts_shadow: bool,
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first triangle index; inner: index of the right child (left is self + 1).
    offset: u32,
    /// Leaf: triangle count (> 0); inner: 0.
    count: u32,
}

/// Closest hit: distance along the ray, triangle index, barycentrics (of p1, p2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f64,
    pub tri: u32,
    pub u: f64,
    pub v: f64,
}

pub struct Bvh {
    nodes: Vec<Node>,
    /// Triangles in leaf order.
    pub tris: Vec<Tri>,
    /// Original index of each leaf-ordered triangle.
    pub order: Vec<u32>,
}

const LEAF: usize = 4;
const BINS: usize = 12;
const STACK: usize = 64;
const MAX_DEPTH: usize = 48;

impl Bvh {
    pub fn build(tris: Vec<Tri>) -> Bvh {
        let n = tris.len();
        let centroids: Vec<DVec3> = tris
            .iter()
            .map(|t| (t.p[0] + t.p[1] + t.p[2]) / 3.0)
            .collect();
        let mut idx: Vec<u32> = (0..n as u32).collect();
        let mut nodes = Vec::with_capacity(2 * n.max(1));
        if n == 0 {
            nodes.push(Node {
                lo: DVec3::splat(f64::INFINITY),
                hi: DVec3::splat(f64::NEG_INFINITY),
                offset: 0,
                count: 0,
            });
        } else {
            build_rec(&tris, &centroids, &mut idx, 0, n, &mut nodes, 0);
        }
        let ordered = idx.iter().map(|&i| tris[i as usize]).collect();
        Bvh {
            nodes,
            tris: ordered,
            order: idx,
        }
    }

    /// Closest intersection with t in (tmin, tmax), any triangle.
    pub fn intersect(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> Option<Hit> {
        let inv = d.recip();
        let mut best: Option<Hit> = None;
        let mut tmax = tmax;
        self.walk(o, inv, tmin, &mut tmax, |i, tmax| {
            if let Some((t, u, v)) = intersect_tri(&self.tris[i], o, d, tmin, *tmax) {
                *tmax = t;
                best = Some(Hit {
                    t,
                    tri: i as u32,
                    u,
                    v,
                });
            }
            false
        });
        best
    }

    /// Whether any shadow-casting triangle lies on the segment o + t d, t in (tmin, tmax).
    pub fn occluded(&self, o: DVec3, d: DVec3, tmin: f64, tmax: f64) -> bool {
        let inv = d.recip();
        let mut tmax = tmax;
        let mut hit = false;
        self.walk(o, inv, tmin, &mut tmax, |i, tmax| {
            let tri = &self.tris[i];
            if tri.casts_shadow && intersect_tri(tri, o, d, tmin, *tmax).is_some() {
                hit = true;
                return true;
            }
            false
        });
        hit
    }

    /// Visits every shadow-casting triangle in a leaf whose box `overlaps` accepts (a box test
    /// that must be conservative: true whenever the box may hold a triangle of interest).
    pub fn for_each_caster(
        &self,
        overlaps: impl Fn(DVec3, DVec3) -> bool,
        mut visit: impl FnMut(&Tri),
    ) {
        self.traverse(
            |n| overlaps(n.lo, n.hi),
            |first, end| {
                self.tris[first..end]
                    .iter()
                    .filter(|t| t.casts_shadow)
                    .for_each(&mut visit);
                false
            },
        );
    }

    /// Visits leaf triangles whose boxes the ray enters before `tmax`; `visit` returns true to stop.
    #[inline]
    fn walk(
        &self,
        o: DVec3,
        inv: DVec3,
        tmin: f64,
        tmax: &mut f64,
        mut visit: impl FnMut(usize, &mut f64) -> bool,
    ) {
        // The leaf visitor shrinks tmax while the box test reads it.
        let t = std::cell::Cell::new(*tmax);
        self.traverse(
            |n| slab(n, o, inv, tmin, t.get()),
            |first, end| {
                (first..end).any(|i| {
                    let mut tm = t.get();
                    let stop = visit(i, &mut tm);
                    t.set(tm);
                    stop
                })
            },
        );
        *tmax = t.get();
    }

    /// Depth-first traversal with a fixed stack: `enter` decides whether to open a node, `leaf`
    /// gets each opened leaf's triangle range and returns true to stop.
    #[inline]
    fn traverse(
        &self,
        mut enter: impl FnMut(&Node) -> bool,
        mut leaf: impl FnMut(usize, usize) -> bool,
    ) {
        // An empty scene has a single empty root that is neither a leaf nor an inner node.
        if self.tris.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut sp = 0usize;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if enter(n) {
                if n.count > 0 {
                    if leaf(n.offset as usize, (n.offset + n.count) as usize) {
                        return;
                    }
                } else {
                    // The build caps depth at MAX_DEPTH < STACK, so this never overflows.
                    stack[sp] = n.offset;
                    sp += 1;
                    node += 1;
                    continue;
                }
            }
            if sp == 0 {
                return;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
    }
}

#[inline]
fn slab(n: &Node, o: DVec3, inv: DVec3, tmin: f64, tmax: f64) -> bool {
    let t0 = (n.lo - o) * inv;
    let t1 = (n.hi - o) * inv;
    // NaN (0 · inf on a box face) must not reject a box: min/max below ignore NaN.
    let near = t0.min(t1).max_element().max(tmin);
    let far = t0.max(t1).min_element().min(tmax);
    near <= far
}

/// Möller–Trumbore in f64, with t in (tmin, tmax); returns (t, u, v).
#[inline]
pub fn intersect_tri(
    tri: &Tri,
    o: DVec3,
    d: DVec3,
    tmin: f64,
    tmax: f64,
) -> Option<(f64, f64, f64)> {
    let e1 = tri.p[1] - tri.p[0];
    let e2 = tri.p[2] - tri.p[0];
    let pv = d.cross(e2);
    let det = e1.dot(pv);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv = 1.0 / det;
    let tv = o - tri.p[0];
    let u = tv.dot(pv) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qv = tv.cross(e1);
    let v = d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qv) * inv;
    (t > tmin && t < tmax).then_some((t, u, v))
}

fn bounds_of(tris: &[Tri], idx: &[u32]) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for &i in idx {
        for p in tris[i as usize].p {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    (lo, hi)
}

fn area(lo: DVec3, hi: DVec3) -> f64 {
    let e = (hi - lo).max(DVec3::ZERO);
    e.x * e.y + e.y * e.z + e.z * e.x
}

fn build_rec(
    tris: &[Tri],
    cen: &[DVec3],
    idx: &mut [u32],
    first: usize,
    count: usize,
    nodes: &mut Vec<Node>,
    depth: usize,
) {
    let me = nodes.len();
    let (lo, hi) = bounds_of(tris, &idx[first..first + count]);
    nodes.push(Node {
        lo,
        hi,
        offset: first as u32,
        count: count as u32,
    });
    if count <= LEAF || depth >= MAX_DEPTH {
        return;
    }
    // Binned SAH over the centroid bounds.
    let (mut clo, mut chi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &i in &idx[first..first + count] {
        clo = clo.min(cen[i as usize]);
        chi = chi.max(cen[i as usize]);
    }
    let ext = chi - clo;
    let mut best = (f64::INFINITY, 0usize, 0usize);
    for axis in 0..3 {
        if ext[axis] <= 0.0 {
            continue;
        }
        let mut bins = [(
            DVec3::splat(f64::INFINITY),
            DVec3::splat(f64::NEG_INFINITY),
            0usize,
        ); BINS];
        let bin_of =
            |c: DVec3| (((c[axis] - clo[axis]) / ext[axis] * BINS as f64) as usize).min(BINS - 1);
        for &i in &idx[first..first + count] {
            let b = &mut bins[bin_of(cen[i as usize])];
            for p in tris[i as usize].p {
                b.0 = b.0.min(p);
                b.1 = b.1.max(p);
            }
            b.2 += 1;
        }
        for split in 1..BINS {
            let (mut l, mut r) = (
                (
                    DVec3::splat(f64::INFINITY),
                    DVec3::splat(f64::NEG_INFINITY),
                    0,
                ),
                (
                    DVec3::splat(f64::INFINITY),
                    DVec3::splat(f64::NEG_INFINITY),
                    0,
                ),
            );
            for (k, b) in bins.iter().enumerate() {
                let side = if k < split { &mut l } else { &mut r };
                if b.2 > 0 {
                    side.0 = side.0.min(b.0);
                    side.1 = side.1.max(b.1);
                    side.2 += b.2;
                }
            }
            if l.2 == 0 || r.2 == 0 {
                continue;
            }
            let cost = area(l.0, l.1) * l.2 as f64 + area(r.0, r.1) * r.2 as f64;
            if cost < best.0 {
                best = (cost, axis, split);
            }
        }
    }
    let slice = &mut idx[first..first + count];
    let mid = if best.0.is_finite() && best.0 < area(lo, hi) * count as f64 {
        let (axis, split) = (best.1, best.2);
        let bin_of =
            |c: DVec3| (((c[axis] - clo[axis]) / ext[axis] * BINS as f64) as usize).min(BINS - 1);
        let mut m = 0;
        for k in 0..slice.len() {
            if bin_of(cen[slice[k] as usize]) < split {
                slice.swap(k, m);
                m += 1;
            }
        }
        m
    } else if count > 2 * LEAF {
        // SAH says a leaf, but a huge leaf is slow: median split on the longest axis.
        let axis = ext.max_position();
        slice.sort_by(|a, b| cen[*a as usize][axis].total_cmp(&cen[*b as usize][axis]));
        count / 2
    } else {
        return;
    };
    if mid == 0 || mid == count {
        return;
    }
    nodes[me].count = 0;
    build_rec(tris, cen, idx, first, mid, nodes, depth + 1);
    nodes[me].offset = nodes.len() as u32;
    build_rec(tris, cen, idx, first + mid, count - mid, nodes, depth + 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic soup of random triangles; the BVH must agree with brute force.
    #[test]
    fn bvh_agrees_with_brute_force() {
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64) / (1u64 << 53) as f64
        };
        let mut tris = Vec::new();
        for k in 0..2000 {
            let c = DVec3::new(rnd(), rnd(), rnd()) * 10.0;
            let p = [
                c,
                c + DVec3::new(rnd(), rnd(), rnd()) * 0.6,
                c + DVec3::new(rnd(), rnd(), rnd()) * 0.6,
            ];
            tris.push(Tri {
                p,
                casts_shadow: k % 3 != 0,
            });
        }
        let bvh = Bvh::build(tris.clone());
        for _ in 0..2000 {
            let o = DVec3::new(rnd(), rnd(), rnd()) * 12.0 - 1.0;
            let d = (DVec3::new(rnd(), rnd(), rnd()) - 0.5).normalize();
            let brute = tris
                .iter()
                .enumerate()
                .filter_map(|(i, t)| intersect_tri(t, o, d, 0.0, 8.0).map(|h| (h.0, i)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let fast = bvh.intersect(o, d, 0.0, 8.0);
            assert_eq!(brute.map(|b| b.0), fast.map(|h| h.t));
            if let (Some(b), Some(h)) = (brute, fast) {
                assert_eq!(b.1 as u32, bvh.order[h.tri as usize]);
            }
            let brute_occ = tris
                .iter()
                .any(|t| t.casts_shadow && intersect_tri(t, o, d, 0.0, 8.0).is_some());
            assert_eq!(brute_occ, bvh.occluded(o, d, 0.0, 8.0));
        }
    }
}
