//! CPU side of the particle hierarchy: the scene's particles grouped into blocks, and what the
//! GPU draws from them — one *primitive* per block (or per particle, unblocked), the impostor
//! *tiles* and the particles rendered into them.
//!
//! Where the blocks come from:
//! - **declared** ([`declared`], knob `from_scene`, default on): when ONE `blocks` generator
//!   made every particle of the scene (`scenes::particles::BlockInstancing`), its block is the
//!   prototype (about the block's origin) and its instances are the instances, with their own
//!   scale and density scale — the paper's construction ("build a block of b particles and
//!   instance it N/b times"), so no shape error remains; `blocks` is then ignored.
//! - **clustered** ([`blocked`]): `blocks` spatial clusters (balanced k-d splits + Lloyd steps).
//!
//! Two ways to map blocks to impostors (the knob `instancing`):
//! - `prototype` (the paper): ONE block rendered into one impostor per direction (light,
//!   camera) and instanced at every block. Clustered, the prototype is the cluster nearest the
//!   cloud's centroid among the *typical* ones (at least 3/4 of the median particle count,
//!   size within [`TYPICAL_SIZE`] of the median), recentred on its core (per-axis median); its particles
//!   farther than [`OUTLIER_FACTOR`] × its size are outliers, left out of the impostor (their
//!   optical mass goes into the instances' τ). Each cluster's instance sits at its core, scaled
//!   by the ratio of sizes (size: median of distance-from-core + radius), τ scaled so its
//!   optical mass Σ τ·r³ is the cluster's. Robust statistics throughout: one outlying particle
//!   sets neither the prototype's extent nor an instance's size (before, the RMS spread and the
//!   farthest particle did, and 800 blocks drew larger billboards than 1600 on cloud-plane).
//!   Cost: b impostor splats + N/b block splats. The geometry is approximate (every block looks
//!   alike); that error is part of what is measured.
//! - `clusters`: every cluster (declared: every instance) gets its own impostor pair from its
//!   own particles (exact geometry up to impostor resolution); cost N impostor splats + N/b
//!   block splats.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use scenes::particles::{BlockInstancing, Particle};

/// One billboard the light pass and the final gathering draw. Mirrors `Prim` in common.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Prim {
    /// xyz: centre (m); w: half-size of the billboard (m) — the block's (or sphere's) bounding radius.
    pub center: [f32; 4],
    /// rgb: albedo; w: τ (1/m) of an analytic sphere, or the extinction multiplier of an instance.
    pub albedo: [f32; 4],
    /// x: instance scale (world m per prototype m); y: light tile (−1: analytic sphere);
    /// z: camera tile; w: unused.
    pub extra: [f32; 4],
}

/// One particle splatted into an impostor tile. Mirrors `ImpParticle` in common.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct ImpParticle {
    /// xyz: centre relative to its block's centroid (prototype metres); w: radius.
    pub pos: [f32; 4],
    /// x: τ (1/m); y: light tile; z: camera tile; w: unused.
    pub data: [f32; 4],
}

/// An impostor tile's orthographic frame for this frame. Mirrors `Tile` in common.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Tile {
    /// xyz: right; w: half-extent h of the tile (prototype metres).
    pub right: [f32; 4],
    /// xyz: up.
    pub up: [f32; 4],
    /// xyz: forward (the direction the impostor is rendered along).
    pub fwd: [f32; 4],
}

/// How clusters become impostors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instancing {
    Prototype,
    Clusters,
}

/// Which way a tile looks, decided per frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TileView {
    /// Along the light, toward this anchor (a cluster centroid or the cloud's centroid).
    Light(Vec3),
    /// Along the camera ray toward this anchor.
    Camera(Vec3),
}

/// Everything the passes draw, built once in `prepare`.
pub struct BlockSet {
    /// Unsorted; the gather sorts them back to front each frame.
    pub prims: Vec<Prim>,
    pub imp: Vec<ImpParticle>,
    /// One per tile: its direction rule and half-extent.
    pub tiles: Vec<(TileView, f32)>,
    /// Particles per block (mean), for the report.
    pub per_block: f64,
    /// Centroid of all particles.
    pub centroid: Vec3,
    /// Built from the scene's declared block instances (not from clusters).
    pub declared: bool,
    /// Each primitive's own particles (indices into the scene's), in `prims` order: a block's
    /// cluster or declared instance, a sphere's one particle (`held.rs` draws a block that holds
    /// a viewer as these).
    pub members: Vec<Vec<usize>>,
}

/// A stable orthonormal (right, up) pair perpendicular to `dir`; the same rule as `basis_of`
/// in common.wgsl, so a cluster's tile and its billboard share their orientation.
pub fn basis_of(dir: Vec3) -> (Vec3, Vec3) {
    let up_ref = if dir.y.abs() > 0.99 { Vec3::X } else { Vec3::Y };
    let right = dir.cross(up_ref).normalize();
    (right, right.cross(dir))
}

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
struct Stats {
    centroid: Vec3,
    /// Per-axis median of the members' centres, m: the centre of the cluster's bulk, which one
    /// far particle does not move (the centroid does, by its distance over the count).
    core: Vec3,
    /// Median over the members of (distance from `core` + radius), m: the cluster's size,
    /// robust like `core`, never 0 (a one-particle cluster's is its radius).
    spread: f32,
    mass: f64,
    albedo: Vec3,
    /// max |p − centroid| + r.
    bound: f32,
}

fn stats(ps: &[Particle], members: &[usize]) -> Stats {
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
fn median(v: impl Iterator<Item = f32>) -> f32 {
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

/// A prototype particle whose distance from the core plus radius exceeds this many times the
/// cluster's size (the median of the same) is an outlier: not drawn into the prototype (its
/// optical mass is folded into the instances' τ scaling). Uniform in a ball the farthest
/// centre is at 1.26× the median distance.
pub const OUTLIER_FACTOR: f32 = 2.0;

/// A scene particle as an analytic sphere primitive (exact chord per fragment, no impostor).
pub fn sphere(p: &Particle) -> Prim {
    Prim {
        center: [p.center.x, p.center.y, p.center.z, p.radius],
        albedo: [p.albedo.x, p.albedo.y, p.albedo.z, p.density],
        extra: [1.0, -1.0, -1.0, 0.0],
    }
}

/// One primitive per particle: the unblocked splat (analytic spheres, no impostors).
pub fn unblocked(ps: &[Particle]) -> BlockSet {
    let prims = ps.iter().map(sphere).collect();
    BlockSet {
        prims,
        imp: Vec::new(),
        tiles: Vec::new(),
        per_block: 1.0,
        centroid: centroid(ps),
        declared: false,
        members: (0..ps.len()).map(|i| vec![i]).collect(),
    }
}

fn centroid(ps: &[Particle]) -> Vec3 {
    ps.iter().map(|p| p.center).sum::<Vec3>() / ps.len().max(1) as f32
}

/// Lloyd steps after the k-d split.
pub const LLOYD_STEPS: usize = 4;

/// Padding so rasterised particle quads never spill over a tile's border.
const PAD: f32 = 1.02;

/// `blocks` clusters as impostor-backed primitives (see the module doc).
pub fn blocked(ps: &[Particle], blocks: usize, mode: Instancing) -> BlockSet {
    let clusters = clusters(ps, blocks, LLOYD_STEPS);
    match mode {
        Instancing::Clusters => per_cluster(ps, &clusters),
        Instancing::Prototype => prototype(ps, &clusters),
    }
}

/// Every cluster its own impostor pair from its own particles.
fn per_cluster(ps: &[Particle], clusters: &[Vec<usize>]) -> BlockSet {
    let mut set = BlockSet::empty(ps, clusters.len());
    set.members = clusters.to_vec();
    for c in clusters {
        let s = stats(ps, c);
        let (tl, tc) = (set.tiles.len() as f32, set.tiles.len() as f32 + 1.0);
        set.tiles.push((TileView::Light(s.centroid), s.bound * PAD));
        set.tiles
            .push((TileView::Camera(s.centroid), s.bound * PAD));
        for &i in c {
            let p = &ps[i];
            let d = p.center - s.centroid;
            set.imp.push(ImpParticle {
                pos: [d.x, d.y, d.z, p.radius],
                data: [p.density, tl, tc, 0.0],
            });
        }
        set.prims.push(Prim {
            center: [s.centroid.x, s.centroid.y, s.centroid.z, s.bound * PAD],
            albedo: [s.albedo.x, s.albedo.y, s.albedo.z, 1.0],
            extra: [1.0, tl, tc, 0.0],
        });
    }
    set
}

/// The prototype: the cluster nearest the cloud's centroid (the most representative of the
/// interior) among the typical ones — at least [`TYPICAL_COUNT`] × the median particle count
/// and a size within [`TYPICAL_SIZE`] of the clusters' median size, since an atypically small
/// or large prototype would shrink or inflate every instance. Without a typical cluster, the one whose
/// size is nearest the median.
fn typical(st: &[Stats], clusters: &[Vec<usize>], all: Vec3) -> usize {
    let n_med = median(clusters.iter().map(|c| c.len() as f32));
    let s_med = median(st.iter().map(|s| s.spread)).max(1e-9);
    let off = |i: usize| (st[i].spread.max(1e-9) / s_med).ln().abs();
    let near = |i: usize| (st[i].centroid - all).length_squared();
    let full: Vec<usize> = (0..st.len())
        .filter(|&i| clusters[i].len() as f32 >= TYPICAL_COUNT * n_med)
        .collect();
    full.iter()
        .copied()
        .filter(|&i| off(i) <= TYPICAL_SIZE.ln())
        .min_by(|&a, &b| near(a).total_cmp(&near(b)))
        .or_else(|| {
            full.iter()
                .copied()
                .min_by(|&a, &b| off(a).total_cmp(&off(b)))
        })
        .unwrap_or(0)
}

/// A cluster's extent about its core without its outliers (m), and the members kept.
fn extent(ps: &[Particle], members: &[usize], s: &Stats) -> (f32, Vec<usize>) {
    let size = |i: usize| (ps[i].center - s.core).length() + ps[i].radius;
    let kept: Vec<usize> = members
        .iter()
        .copied()
        .filter(|&i| size(i) <= s.spread * OUTLIER_FACTOR)
        .collect();
    (kept.iter().map(|&i| size(i)).fold(0.0, f32::max), kept)
}

/// A cluster is typical if its size is within this factor (either way) of the median size.
pub const TYPICAL_SIZE: f32 = 1.25;
/// … and it has at least this fraction of the median particle count.
pub const TYPICAL_COUNT: f32 = 0.75;

/// ONE prototype block (the most typical cluster, recentred on its core, outliers dropped)
/// instanced at every cluster's core, scaled by the ratio of spreads (median distances), τ
/// scaled so each instance's optical mass is its cluster's (which folds the dropped outliers'
/// mass in). Robust statistics throughout, so one far particle sets no size.
fn prototype(ps: &[Particle], clusters: &[Vec<usize>]) -> BlockSet {
    let mut set = BlockSet::empty(ps, clusters.len());
    set.members = clusters.to_vec();
    let st: Vec<Stats> = clusters.iter().map(|c| stats(ps, c)).collect();
    if st.is_empty() {
        return set;
    }
    let proto = typical(&st, clusters, set.centroid);
    let sp = &st[proto];
    let (h, kept) = extent(ps, &clusters[proto], sp);
    let mut mass = 0.0f64;
    for &i in &kept {
        let p = &ps[i];
        let d = p.center - sp.core;
        mass += p.density as f64 * (p.radius as f64).powi(3);
        set.imp.push(ImpParticle {
            pos: [d.x, d.y, d.z, p.radius],
            data: [p.density, 0.0, 1.0, 0.0],
        });
    }
    set.tiles.push((TileView::Light(set.centroid), h * PAD));
    set.tiles.push((TileView::Camera(set.centroid), h * PAD));
    for s in &st {
        let scale = s.spread / sp.spread;
        let tau_mul = if mass > 0.0 {
            (s.mass / (mass * (scale as f64).powi(3))) as f32
        } else {
            0.0
        };
        set.prims.push(Prim {
            center: [s.core.x, s.core.y, s.core.z, h * PAD * scale],
            albedo: [s.albedo.x, s.albedo.y, s.albedo.z, tau_mul],
            extra: [scale, 0.0, 1.0, 0.0],
        });
    }
    set
}

/// The scene's declared structure as blocks, when ONE `blocks` generator made every particle
/// (None otherwise: the caller clusters). Prototype: the declared block, about its origin, is
/// the one impostor pair, instanced at each declared instance with its scale and density
/// scale — the paper's construction, no modelling error. Clusters: each instance's own
/// particles are a cluster.
pub fn declared(ps: &[Particle], decl: &[BlockInstancing], mode: Instancing) -> Option<BlockSet> {
    let [b] = decl else { return None };
    if b.block.is_empty() || b.block.len() * b.instances.len() != ps.len() {
        return None;
    }
    if mode == Instancing::Clusters {
        let cl: Vec<Vec<usize>> = b
            .instances
            .iter()
            .map(|i| (i.first..i.first + b.block.len()).collect())
            .collect();
        return Some(BlockSet {
            declared: true,
            ..per_cluster(ps, &cl)
        });
    }
    let mut set = BlockSet::empty(ps, b.instances.len());
    set.declared = true;
    set.members = b
        .instances
        .iter()
        .map(|i| (i.first..i.first + b.block.len()).collect())
        .collect();
    let members: Vec<usize> = (0..b.block.len()).collect();
    let s = stats(&b.block, &members);
    let h = b
        .block
        .iter()
        .map(|p| p.center.length() + p.radius)
        .fold(0.0f32, f32::max);
    set.tiles.push((TileView::Light(set.centroid), h * PAD));
    set.tiles.push((TileView::Camera(set.centroid), h * PAD));
    set.imp.extend(b.block.iter().map(|p| ImpParticle {
        pos: [p.center.x, p.center.y, p.center.z, p.radius],
        data: [p.density, 0.0, 1.0, 0.0],
    }));
    set.prims.extend(b.instances.iter().map(|i| Prim {
        center: [i.center.x, i.center.y, i.center.z, h * PAD * i.scale],
        albedo: [s.albedo.x, s.albedo.y, s.albedo.z, i.density_scale],
        extra: [i.scale, 0.0, 1.0, 0.0],
    }));
    Some(set)
}

impl BlockSet {
    /// No primitives yet, for `blocks` blocks of `ps`.
    fn empty(ps: &[Particle], blocks: usize) -> BlockSet {
        BlockSet {
            prims: Vec::with_capacity(blocks),
            imp: Vec::new(),
            tiles: Vec::new(),
            per_block: ps.len() as f64 / blocks.max(1) as f64,
            centroid: centroid(ps),
            declared: false,
            members: Vec::with_capacity(blocks),
        }
    }
}

/// This frame's tile frames: light tiles look along the light (directional: its propagation
/// direction; local: from the light to the anchor), camera tiles from the eye to the anchor.
pub fn tile_frames(
    tiles: &[(TileView, f32)],
    eye: Vec3,
    light_dir: Option<Vec3>,
    light_pos: Option<Vec3>,
) -> Vec<Tile> {
    tiles
        .iter()
        .map(|&(view, h)| {
            let fwd = match view {
                TileView::Camera(a) => (a - eye).try_normalize().unwrap_or(Vec3::Z),
                TileView::Light(a) => match (light_dir, light_pos) {
                    (Some(d), _) => d,
                    (None, Some(p)) => (a - p).try_normalize().unwrap_or(Vec3::NEG_Y),
                    (None, None) => Vec3::NEG_Y,
                },
            };
            let (r, u) = basis_of(fwd);
            Tile {
                right: [r.x, r.y, r.z, h],
                up: [u.x, u.y, u.z, 0.0],
                fwd: [fwd.x, fwd.y, fwd.z, 0.0],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> Vec<Particle> {
        (0..n)
            .map(|i| Particle {
                center: Vec3::new((i % 10) as f32, ((i / 10) % 10) as f32, (i / 100) as f32),
                radius: 0.3 + 0.01 * (i % 7) as f32,
                density: 1.0 + (i % 3) as f32,
                albedo: Vec3::splat(0.9),
            })
            .collect()
    }

    #[test]
    fn clusters_partition_the_particles_into_balanced_groups() {
        let ps = grid(1000);
        for k in [1usize, 7, 40, 400, 1000, 5000] {
            let cl = kd_clusters(&ps, k);
            assert_eq!(cl.len(), k.min(1000), "k = {k}");
            let mut seen: Vec<usize> = cl.iter().flatten().copied().collect();
            seen.sort();
            assert_eq!(seen, (0..1000).collect::<Vec<_>>());
            let (lo, hi) = (
                cl.iter().map(Vec::len).min().unwrap(),
                cl.iter().map(Vec::len).max().unwrap(),
            );
            assert!(hi <= lo + 2 + hi / 4, "k = {k}: sizes {lo}..{hi}");
        }
    }

    #[test]
    fn clusters_are_spatially_compact() {
        // 40 clusters of a 10×10×10 grid: each should span far less than the whole grid, and
        // the Lloyd steps keep every particle exactly once.
        let ps = grid(1000);
        let cl = clusters(&ps, 40, LLOYD_STEPS);
        let mut seen: Vec<usize> = cl.iter().flatten().copied().collect();
        seen.sort();
        assert_eq!(seen, (0..1000).collect::<Vec<_>>());
        for c in cl {
            let s = stats(&ps, &c);
            assert!(s.bound < 4.5, "cluster bound {}", s.bound);
        }
    }

    #[test]
    fn prototype_instances_preserve_each_clusters_optical_mass() {
        let ps = grid(1000);
        let set = blocked(&ps, 40, Instancing::Prototype);
        assert_eq!(set.prims.len(), 40);
        assert_eq!(set.tiles.len(), 2);
        let proto_mass: f64 = set
            .imp
            .iter()
            .map(|q| q.data[0] as f64 * (q.pos[3] as f64).powi(3))
            .sum();
        let clusters = clusters(&ps, 40, LLOYD_STEPS);
        let mut total_inst = 0.0;
        for p in &set.prims {
            let (k, s) = (p.albedo[3] as f64, p.extra[0] as f64);
            total_inst += k * s.powi(3) * proto_mass;
        }
        let total: f64 = clusters.iter().map(|c| stats(&ps, c).mass).sum();
        assert!(
            (total_inst / total - 1.0).abs() < 1e-4,
            "{total_inst} vs {total}"
        );
    }

    /// Half-extent of the prototype's tiles and the largest instance billboard.
    fn extents(set: &BlockSet) -> (f32, f32) {
        let big = set.prims.iter().map(|p| p.center[3]).fold(0.0, f32::max);
        (set.tiles[0].1, big)
    }

    #[test]
    fn one_outlier_does_not_set_the_prototypes_size() {
        let ps = grid(1000);
        let mut with = ps.clone();
        // 20 m from a 10 m grid: an outlier of the single cluster (k = 1), and of whichever
        // edge cluster takes it (k = 40).
        with.push(Particle {
            center: Vec3::new(4.5, 4.5, 25.0),
            ..ps[0]
        });
        for k in [1usize, 40] {
            let (h0, big0) = extents(&blocked(&ps, k, Instancing::Prototype));
            let set = blocked(&with, k, Instancing::Prototype);
            let (h1, big1) = extents(&set);
            assert!(h1 <= 1.1 * h0, "k = {k}: prototype half-extent {h0} → {h1}");
            assert!(
                big1 <= 1.5 * big0,
                "k = {k}: largest billboard {big0} → {big1}"
            );
            // The dropped outlier's optical mass is kept: Σ over instances of τ-multiplier ·
            // scale³ · prototype mass is the whole cloud's.
            let proto: f64 = set
                .imp
                .iter()
                .map(|q| q.data[0] as f64 * (q.pos[3] as f64).powi(3))
                .sum();
            let inst: f64 = set
                .prims
                .iter()
                .map(|p| p.albedo[3] as f64 * (p.extra[0] as f64).powi(3) * proto)
                .sum();
            let all: f64 = with
                .iter()
                .map(|p| p.density as f64 * (p.radius as f64).powi(3))
                .sum();
            assert!((inst / all - 1.0).abs() < 1e-4, "k = {k}: {inst} vs {all}");
        }
    }

    #[test]
    fn the_prototype_is_a_typical_cluster_so_instances_keep_their_size() {
        // Instances scale by spread ratio: with a typical prototype the median scale is ~1.
        let ps = grid(1000);
        for k in [40usize, 200] {
            let set = blocked(&ps, k, Instancing::Prototype);
            let med = median(set.prims.iter().map(|p| p.extra[0]));
            assert!((0.85..=1.15).contains(&med), "k = {k}: median scale {med}");
        }
    }

    #[test]
    fn declared_blocks_are_the_prototype_and_the_instances() {
        let block: Vec<Particle> = grid(50)
            .into_iter()
            .map(|p| Particle {
                center: (p.center - Vec3::new(4.5, 2.0, 0.0)) * 0.1,
                ..p
            })
            .collect();
        let instances: Vec<scenes::particles::BlockInstance> = (0..6)
            .map(|k| scenes::particles::BlockInstance {
                center: Vec3::new(k as f32, 0.5 * k as f32, 0.0),
                scale: 0.5 + 0.25 * k as f32,
                density_scale: 1.0 + k as f32,
                first: 50 * k,
            })
            .collect();
        let ps: Vec<Particle> = instances
            .iter()
            .flat_map(|i| block.iter().map(|p| i.place(p)))
            .collect();
        let decl = [BlockInstancing {
            block: block.clone(),
            instances: instances.clone(),
        }];
        let set = declared(&ps, &decl, Instancing::Prototype).expect("declared");
        assert!(set.declared);
        assert_eq!(
            (set.imp.len(), set.prims.len(), set.tiles.len()),
            (50, 6, 2)
        );
        for (q, p) in set.imp.iter().zip(&block) {
            assert_eq!(q.pos, [p.center.x, p.center.y, p.center.z, p.radius]);
            assert_eq!(q.data[0], p.density);
        }
        let h = set.tiles[0].1;
        for (p, i) in set.prims.iter().zip(&instances) {
            assert_eq!(&p.center[..3], &i.center.to_array());
            assert_eq!((p.extra[0], p.albedo[3]), (i.scale, i.density_scale));
            assert!((p.center[3] - h * i.scale).abs() < 1e-6);
        }
        // Every block particle fits its tile.
        for q in &set.imp {
            assert!(Vec3::new(q.pos[0], q.pos[1], q.pos[2]).length() + q.pos[3] <= h);
        }
        // Clusters mode: one cluster per instance, exactly its particles.
        let cl = declared(&ps, &decl, Instancing::Clusters).unwrap();
        assert_eq!((cl.prims.len(), cl.imp.len(), cl.tiles.len()), (6, 300, 12));
        // Not the whole medium (an extra particle) → no declared structure.
        let mut more = ps.clone();
        more.push(ps[0]);
        assert!(declared(&more, &decl, Instancing::Prototype).is_none());
        assert!(declared(&ps, &[], Instancing::Prototype).is_none());
    }

    #[test]
    fn cluster_mode_keeps_every_particle_exactly() {
        let ps = grid(300);
        let set = blocked(&ps, 20, Instancing::Clusters);
        assert_eq!(set.imp.len(), 300);
        assert_eq!(set.tiles.len(), 40);
        // Every impostor particle lies inside its tile's extent.
        for q in &set.imp {
            let h = set.tiles[q.data[1] as usize].1;
            let d = Vec3::new(q.pos[0], q.pos[1], q.pos[2]).length() + q.pos[3];
            assert!(d <= h, "{d} > {h}");
        }
    }

    #[test]
    fn basis_is_orthonormal_and_perpendicular() {
        for d in [
            Vec3::X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::new(0.3, -1.0, 0.2).normalize(),
        ] {
            let (r, u) = basis_of(d);
            assert!((r.length() - 1.0).abs() < 1e-5 && (u.length() - 1.0).abs() < 1e-5);
            assert!(r.dot(d).abs() < 1e-5 && u.dot(d).abs() < 1e-5 && r.dot(u).abs() < 1e-5);
        }
    }
}
