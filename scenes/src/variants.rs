//! Scene variants made programmatically from a scene (ARCHITECTURE §8.2, §9.5): more caster
//! triangles on the same surfaces, or a new name for another resolution. A variant of a
//! library scene is named after it, so every command that takes a scene name accepts it:
//!
//! - `<scene>-sub<L>`: every caster subdivided L ≤ [`MAX_SUB_LEVELS`] times from the library
//!   mesh ([`subdivided`]; Biri et al. 2006 Table II in `reproduce`). Resolved by
//!   [`crate::library::resolve`].
//! - `<scene>-tris<N>`: the casters re-tessellated to about N triangles in total
//!   ([`with_caster_triangles`], the triangle sweep of `scaling`).
//! - `<scene>-res<N>`: the scene itself, renamed for the pixel sweep of `scaling` at N²
//!   ([`at_resolution`]).
//! - `<scene>-lights<N>`: a scene with atrium stonework, its local lights replaced by the
//!   first N ≤ 64 torches of the atrium's sconces, its directional lights kept ([`with_torches`],
//!   the light-count sweep of `scaling`). Resolved by [`crate::library::resolve`].
//!
//! A caster is every object but a ground plane; subdivision is midpoint subdivision
//! ([`crate::mesh::subdivide`]), which keeps the surface where it is.

use std::sync::Arc;

use crate::desc::{LightDesc, Shape};
use crate::load::build_mesh;
use crate::mesh::atrium::layout::{MAX_TORCHES, torches};
use crate::mesh::subdivide::{subdivide, subdivide_to};
use crate::scene::Scene;

/// Most subdivision levels a `-sub<L>` variant may ask for (each quadruples the triangles).
pub const MAX_SUB_LEVELS: u32 = 8;

/// Whether an object counts as a caster for the variants (every shape but the ground plane).
pub fn is_caster(shape: &Shape) -> bool {
    !matches!(shape, Shape::Plane { .. })
}

/// Triangles of the scene's casters.
pub fn caster_triangles(scene: &Scene) -> usize {
    scene
        .desc
        .objects
        .iter()
        .zip(&scene.meshes)
        .filter(|(o, _)| is_caster(&o.shape))
        .map(|(_, m)| m.triangle_count())
        .sum()
}

/// `name` split into a base name and subdivision levels when it reads `<base>-sub<L>`.
pub fn parse_sub(name: &str) -> Option<(&str, u32)> {
    split_count(name, "-sub")
}

/// `<base><tag><N>` split into the base name and N, when N parses.
fn split_count<'a, N: std::str::FromStr>(name: &'a str, tag: &str) -> Option<(&'a str, N)> {
    let (base, n) = name.rsplit_once(tag)?;
    Some((base, n.parse().ok()?))
}

/// The scene a `<scene>-sub<L>` variant was made from (the name itself otherwise).
pub fn family(name: &str) -> &str {
    parse_sub(name).map_or(name, |(base, _)| base)
}

/// `scene` with every caster subdivided `levels` times (same surface, 4^levels the triangles),
/// named `<scene>-sub<levels>`.
pub fn subdivided(scene: &Scene, levels: u32) -> Scene {
    let mut s = scene.clone();
    for (o, m) in s.desc.objects.iter().zip(s.meshes.iter_mut()) {
        if is_caster(&o.shape) {
            *m = Arc::new(subdivide(m, levels));
        }
    }
    s.name = format!("{}-sub{levels}", scene.name);
    s
}

/// `scene` with its casters re-tessellated to about `target` triangles in total, each caster
/// getting its share by its current triangle count, named `<scene>-tris<N>` with the count
/// reached. Sphere casters are first rebuilt as 32×16 UV spheres (960 triangles; the
/// description is changed to match) so that the steps of midpoint subdivision land near round
/// targets; every variant of a sweep then has that same faceted surface.
pub fn with_caster_triangles(scene: &Scene, target: usize) -> Result<Scene, String> {
    let mut s = scene.clone();
    let base = std::path::Path::new(".");
    for (o, m) in s.desc.objects.iter_mut().zip(s.meshes.iter_mut()) {
        if let Shape::Sphere {
            segments, rings, ..
        } = &mut o.shape
        {
            (*segments, *rings) = (32, 16);
            *m = Arc::new(build_mesh(&o.shape, base)?);
        }
    }
    let total = caster_triangles(&s).max(1);
    for (o, m) in s.desc.objects.iter().zip(s.meshes.iter_mut()) {
        if is_caster(&o.shape) {
            let share = (target as f64 * m.triangle_count() as f64 / total as f64).round();
            // Within 10 % below the target is close enough (960 for "1k"); otherwise refine.
            let (_, fine) = subdivide_to(m, (share * 0.9) as usize);
            *m = Arc::new(fine);
        }
    }
    s.name = format!("{}-tris{}", scene.name, caster_triangles(&s));
    Ok(s)
}

/// `scene` renamed `<scene>-res<n>` for the pixel sweep at `n`².
pub fn at_resolution(scene: &Scene, n: u32) -> Scene {
    let mut s = scene.clone();
    s.name = format!("{}-res{n}", scene.name);
    s
}

/// `name` split into a base name and a torch count when it reads `<base>-lights<N>`.
pub fn parse_lights(name: &str) -> Option<(&str, usize)> {
    split_count(name, "-lights")
}

/// `scene` (which must contain atrium stonework) with its point and spot lights replaced by
/// the first `n` torches of [`torches`], each with the intensity of the scene's first point
/// light; directional lights are kept. Named `<scene>-lights<n>`.
pub fn with_torches(scene: &Scene, n: usize) -> Result<Scene, String> {
    let name = format!("{}-lights{n}", scene.name);
    if !(1..=MAX_TORCHES).contains(&n) {
        return Err(format!(
            "scene '{name}': the atrium has sconces for 1 to {MAX_TORCHES} torches, got {n}"
        ));
    }
    if !scene
        .desc
        .objects
        .iter()
        .any(|o| matches!(o.shape, Shape::Atrium { .. }))
    {
        return Err(format!(
            "scene '{name}': -lights<N> places torches on atrium columns, and '{}' has no `atrium` object",
            scene.name
        ));
    }
    let intensity = scene
        .desc
        .lights
        .iter()
        .find_map(|l| match l {
            LightDesc::Point { intensity, .. } => Some(*intensity),
            _ => None,
        })
        .ok_or_else(|| {
            format!(
                "scene '{name}': '{}' has no point light to copy a torch's intensity from",
                scene.name
            )
        })?;
    let mut s = scene.clone();
    s.desc
        .lights
        .retain(|l| matches!(l, LightDesc::Directional { .. }));
    s.desc
        .lights
        .extend(torches(n).into_iter().map(|position| LightDesc::Point {
            position,
            intensity,
            keyframes: Vec::new(),
        }));
    s.name = name;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::library::resolve;

    /// The variants hit the targets the default sweep promises (960 · 4^k), keep every
    /// non-caster mesh untouched, and keep the casters' surface: subdivision adds vertices on
    /// the 32×16 sphere's facets, so the area is that of level 0.
    #[test]
    fn triangle_variants_land_on_the_targets_and_keep_the_surface() {
        let base = resolve("sphere-point").unwrap();
        let sphere = |s: &Scene| {
            s.desc
                .objects
                .iter()
                .position(|o| matches!(o.shape, Shape::Sphere { .. }))
                .unwrap()
        };
        let mut level0_area = None;
        for (target, expect) in [
            (1000, 960),
            (4000, 3840),
            (64_000, 61_440),
            (1_000_000, 983_040),
        ] {
            let v = with_caster_triangles(&base, target).unwrap();
            assert_eq!(caster_triangles(&v), expect, "target {target}");
            assert_eq!(v.name, format!("sphere-point-tris{expect}"));
            // The floor is the library's.
            for (i, o) in v.desc.objects.iter().enumerate() {
                if !is_caster(&o.shape) {
                    assert_eq!(v.meshes[i], base.meshes[i]);
                }
            }
            let a = v.meshes[sphere(&v)].area();
            let a0 = *level0_area.get_or_insert(a);
            assert!((a / a0 - 1.0).abs() < 1e-5, "area {a} vs {a0}");
        }
        // The faceted 32×16 sphere's area is below the true sphere's 4πr² (r = 0.9), close.
        let exact = 4.0 * std::f64::consts::PI * 0.81;
        let a0 = level0_area.unwrap();
        assert!(a0 < exact && a0 > 0.97 * exact, "{a0} vs {exact}");
    }

    #[test]
    fn sub_variants_resolve_and_bad_specs_are_refused() {
        let base = resolve("spring-point").unwrap();
        let v = resolve("spring-point-sub2").unwrap();
        assert_eq!(v.name, "spring-point-sub2");
        assert_eq!(caster_triangles(&v), 16 * caster_triangles(&base));
        assert_eq!(
            v.triangle_count() - caster_triangles(&v),
            2,
            "the floor stays 2 triangles"
        );
        assert_eq!(resolve("spring-point").unwrap().name, "spring-point");
        let err = resolve("spring-point-sub9").unwrap_err();
        assert!(err.contains("at most 8"), "{err}");
        let err = resolve("nowhere-sub2").unwrap_err();
        assert!(err.contains("sphere-point"), "{err}");
        assert_eq!(family("spring-point-sub2"), "spring-point");
        assert_eq!(family("spring-point"), "spring-point");
    }
}
