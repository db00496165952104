//! CPU side of the particle hierarchy: the scene's particles grouped into blocks, built into the
//! [`BlockSet`] the GPU draws (the records are in `primitives.rs`, the clustering and its
//! statistics in `clusters.rs`).
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

use glam::Vec3;
use scenes::particles::{BlockInstancing, Particle};

use super::clusters::{LLOYD_STEPS, Stats, centroid, clusters, median, stats};
use super::dominant;
use super::primitives::{BlockSet, ImpParticle, Prim, TileView, sphere};

/// How clusters become impostors.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instancing {
    Prototype,
    Clusters,
}

/// A prototype particle whose distance from the core plus radius exceeds this many times the
/// cluster's size (the median of the same) is an outlier: not drawn into the prototype (its
/// optical mass is folded into the instances' τ scaling). Uniform in a ball the farthest
/// centre is at 1.26× the median distance.
pub const OUTLIER_FACTOR: f32 = 2.0;

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

/// `build`'s blocks of `ps` with the loose particles (dominant.rs: optically thick, or huge for
/// a cloud of `extent`) taken out and drawn as their own spheres, so that they can be dominant
/// spheres wherever they are: in a block, a prototype instance would spread a dense particle's
/// optical mass over the block, and a huge one would set the block's bounds. Without loose
/// particles `build` of all; with nothing else, every particle its own sphere.
pub fn with_loose(
    ps: &[Particle],
    extent: f32,
    build: impl FnOnce(&[Particle]) -> BlockSet,
) -> BlockSet {
    let (loose, rest): (Vec<usize>, Vec<usize>) =
        (0..ps.len()).partition(|&i| dominant::loose(ps[i].radius, ps[i].density, extent));
    if loose.is_empty() {
        return build(ps);
    }
    if rest.is_empty() {
        return unblocked(ps);
    }
    let kept: Vec<Particle> = rest.iter().map(|&i| ps[i]).collect();
    let mut set = build(&kept);
    for i in set.members.iter_mut().flatten() {
        *i = rest[*i];
    }
    for &i in &loose {
        set.prims.push(sphere(&ps[i]));
        set.members.push(vec![i]);
    }
    set
}

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

#[cfg(test)]
#[path = "blocks_tests.rs"]
mod tests;
