//! The scene's particles as spatial clusters (balanced k-d splits refined by Lloyd steps) and
//! each cluster's statistics, robust ones included (core and size by medians), from which
//! `blocks.rs` builds the blocks.

use glam::Vec3;
use scenes::particles::Particle;

/// Lloyd steps after the k-d split.
pub const LLOYD_STEPS: usize = 4;

/// Splits particle indices into `k` spatial clusters of (nearly) equal counts: recursive
/// median-style splits along the longest axis of the centres' bounds, each side receiving a
/// share of the clusters proportional to its share of the particles. Deterministic.
pub fn kd_clusters(ps: &[Particle], k: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::with_capacity(k);
    let mut idx: Vec<usize> = (0..ps.len()).collect();
    split(ps, &mut idx, k.clamp(1, ps.len().max(1)), &mut out);
    out
}

/// k-d clusters refined by `iters` Lloyd (k-means) steps: k-d cells are boxes and slabs, whose
/// shapes differ from cell to cell; Voronoi cells of a uniform cloud are rounder and alike,
/// which is what instancing one prototype block assumes. Clusters that empty are dropped.
pub fn clusters(ps: &[Particle], k: usize, iters: usize) -> Vec<Vec<usize>> {
    let mut cl = kd_clusters(ps, k);
    for _ in 0..iters {
        let cents: Vec<Vec3> = cl
            .iter()
            .map(|c| c.iter().map(|&i| ps[i].center).sum::<Vec3>() / c.len().max(1) as f32)
            .collect();
        let mut next: Vec<Vec<usize>> = vec![Vec::new(); cents.len()];
        for (i, p) in ps.iter().enumerate() {
            let mut best = (f32::INFINITY, 0);
            for (j, c) in cents.iter().enumerate() {
                let d = (p.center - *c).length_squared();
                if d < best.0 {
                    best = (d, j);
                }
            }
            next[best.1].push(i);
        }
        next.retain(|c| !c.is_empty());
        cl = next;
    }
    cl
}

fn split(ps: &[Particle], idx: &mut [usize], k: usize, out: &mut Vec<Vec<usize>>) {
    if k <= 1 || idx.len() <= 1 {
        out.push(idx.to_vec());
        return;
    }
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &i in idx.iter() {
        lo = lo.min(ps[i].center);
        hi = hi.max(ps[i].center);
    }
    let ext = hi - lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let k_left = k / 2;
    let n_left = (idx.len() * k_left / k).clamp(1, idx.len() - 1);
    idx.select_nth_unstable_by(n_left, |a, b| {
        ps[*a].center[axis].total_cmp(&ps[*b].center[axis])
    });
    let (l, r) = idx.split_at_mut(n_left);
    split(ps, l, k_left, out);
    split(ps, r, k - k_left, out);
}

/// Centroid, spread about it, optical mass Σ τ r³ and mass-weighted albedo of a cluster.
pub(super) struct Stats {
    pub centroid: Vec3,
    /// Per-axis median of the members' centres, m: the centre of the cluster's bulk, which one
    /// far particle does not move (the centroid does, by its distance over the count).
    pub core: Vec3,
    /// Median over the members of (distance from `core` + radius), m: the cluster's size,
    /// robust like `core`, never 0 (a one-particle cluster's is its radius).
    pub spread: f32,
    pub mass: f64,
    pub albedo: Vec3,
    /// max |p − centroid| + r.
    pub bound: f32,
}

pub(super) fn stats(ps: &[Particle], members: &[usize]) -> Stats {
    let n = members.len().max(1) as f32;
    let centroid = members.iter().map(|&i| ps[i].center).sum::<Vec3>() / n;
    let axis = |a: usize| median(members.iter().map(|&i| ps[i].center[a]));
    let core = Vec3::new(axis(0), axis(1), axis(2));
    let spread = median(
        members
            .iter()
            .map(|&i| (ps[i].center - core).length() + ps[i].radius),
    );
    let mass: f64 = members
        .iter()
        .map(|&i| ps[i].density as f64 * (ps[i].radius as f64).powi(3))
        .sum();
    let albedo = if mass > 0.0 {
        members
            .iter()
            .map(|&i| ps[i].albedo * (ps[i].density * ps[i].radius.powi(3)))
            .sum::<Vec3>()
            / mass as f32
    } else {
        members.iter().map(|&i| ps[i].albedo).sum::<Vec3>() / n
    };
    let bound = members
        .iter()
        .map(|&i| (ps[i].center - centroid).length() + ps[i].radius)
        .fold(0.0f32, f32::max);
    Stats {
        centroid,
        core,
        spread,
        mass,
        albedo,
        bound,
    }
}

/// The median of some values (the mean of the middle two for an even count; 0 for none).
pub(super) fn median(v: impl Iterator<Item = f32>) -> f32 {
    let mut v: Vec<f32> = v.collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f32::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The centroid of all particles.
pub fn centroid(ps: &[Particle]) -> Vec3 {
    ps.iter().map(|p| p.center).sum::<Vec3>() / ps.len().max(1) as f32
}
