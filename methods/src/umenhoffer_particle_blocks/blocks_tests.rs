//! Tests of the block sets: clusters (balanced, compact), the prototype (optical mass, outliers,
//! typical size), the declared blocks and the clusters mode.

use super::*;
use crate::umenhoffer_particle_blocks::clusters::kd_clusters;

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
