//! The medium: its coefficients and phase function, height fog, and particle lists, blocks and generators.

use glam::Vec3;

use crate::desc::{
    BlockDesc, GeneratorDesc, InstanceDesc, MediumDesc, ParticleDesc,
    PlacementDesc,
};
use crate::particles::{block_count, generated_count, instance_count};
use crate::phase::Phase;

use super::checker::*;

pub(super) fn phase(c: &mut Checker, ph: &Phase) {
    if let Phase::HenyeyGreenstein { g } = ph
        && !(g.is_finite() && g.abs() < 1.0)
    {
        c.push("medium.phase.g", format!("must be in (-1, 1), got {g}"));
    }
}

pub(super) fn medium(c: &mut Checker, m: &MediumDesc) {
    match m {
        MediumDesc::Homogeneous {
            sigma_a,
            sigma_s,
            phase: ph,
            ambient,
            height_fog,
        } => {
            c.non_negative3("medium.sigma_a", *sigma_a);
            c.non_negative3("medium.sigma_s", *sigma_s);
            c.non_negative3("medium.ambient", *ambient);
            phase(c, ph);
            if let Some(f) = height_fog {
                c.finite("medium.height_fog.base_height", f.base_height);
                c.positive("medium.height_fog.falloff_height", f.falloff_height);
            }
        }
        MediumDesc::Particles {
            particles,
            generators,
            phase: ph,
            background,
            sky,
        } => {
            phase(c, ph);
            c.non_negative3("medium.sky", *sky);
            if let Some(b) = background {
                c.non_negative3("medium.background.sigma_a", b.sigma_a);
                c.non_negative3("medium.background.sigma_s", b.sigma_s);
            }
            particle_list(c, "medium", particles, generators, true);
            let total = generators
                .iter()
                .map(generated_count)
                .fold(particles.len() as u64, u64::saturating_add);
            if total == 0 {
                c.push(
                    "medium",
                    "a particle medium needs at least one particle (`particles` or `generators`)",
                );
            } else if total > MAX_PARTICLES {
                c.push(
                    "medium",
                    format!("{total} particles; at most {MAX_PARTICLES} are allowed"),
                );
            }
        }
    }
}

/// Explicit particles and generators under `at` (the medium, or a block: `nested_ok` false).
pub(super) fn particle_list(
    c: &mut Checker,
    at: &str,
    particles: &[ParticleDesc],
    generators: &[GeneratorDesc],
    blocks_ok: bool,
) {
    for (i, p) in particles.iter().enumerate() {
        let at = format!("{at}.particles[{i}]");
        c.finite3(&format!("{at}.center"), p.center);
        c.positive(&format!("{at}.radius"), p.radius);
        non_negative(c, &format!("{at}.density"), p.density);
        c.unit_interval3(&format!("{at}.albedo"), p.albedo);
    }
    for (i, g) in generators.iter().enumerate() {
        let at = format!("{at}.generators[{i}]");
        if !blocks_ok && matches!(g, GeneratorDesc::Blocks { .. }) {
            c.push(
                &format!("{at}.shape"),
                "a block cannot contain a `blocks` generator (one level of instancing)",
            );
            continue;
        }
        generator(c, &at, g);
    }
}

/// A `blocks` generator: its block (≥ 1 particle, no nested blocks), its instances (≥ 1).
pub(super) fn blocks_generator(
    c: &mut Checker,
    at: &str,
    block: &BlockDesc,
    instances: &[InstanceDesc],
    placement: &Option<PlacementDesc>,
) {
    let b = format!("{at}.block");
    particle_list(c, &b, &block.particles, &block.generators, false);
    if block_count(block) == 0 {
        c.push(
            &b,
            "a block needs at least one particle (`particles` or `generators`)",
        );
    }
    for (i, inst) in instances.iter().enumerate() {
        let p = format!("{at}.instances[{i}]");
        c.finite3(&format!("{p}.center"), inst.center);
        c.positive(&format!("{p}.scale"), inst.scale);
        non_negative(c, &format!("{p}.density_scale"), inst.density_scale);
    }
    if let Some(pl) = placement {
        let p = format!("{at}.placement");
        c.count(&format!("{p}.count"), pl.count, 1, MAX_PARTICLES as u32);
        c.finite3(&format!("{p}.center"), pl.center);
        positive3(c, &format!("{p}.radii"), pl.radii);
        radius_range(c, &format!("{p}.scale"), pl.scale, true);
    }
    if instance_count(instances, placement) == 0 {
        c.push(
            at,
            "a `blocks` generator needs at least one instance (`instances` or `placement`)",
        );
    }
}

pub(super) fn positive3(c: &mut Checker, path: &str, v: Vec3) {
    if c.finite3(path, v) && v.min_element() <= 0.0 {
        c.push(path, format!("must be > 0 in every axis, got {v}"));
    }
}

pub(super) fn non_negative(c: &mut Checker, path: &str, x: f32) {
    if !(x.is_finite() && x >= 0.0) {
        c.push(path, format!("must be a finite number ≥ 0, got {x}"));
    }
}

pub(super) fn radius_range(c: &mut Checker, path: &str, r: [f32; 2], ordered: bool) {
    c.positive(&format!("{path}[0]"), r[0]);
    c.positive(&format!("{path}[1]"), r[1]);
    if ordered && r[0].is_finite() && r[1].is_finite() && r[0] > r[1] {
        c.push(path, format!("min must be ≤ max, got [{}, {}]", r[0], r[1]));
    }
}

pub(super) fn generator(c: &mut Checker, at: &str, g: &GeneratorDesc) {
    match g {
        GeneratorDesc::Blocks {
            block,
            instances,
            placement,
        } => blocks_generator(c, at, block, instances, placement),
        GeneratorDesc::Cloud {
            count,
            center,
            radii,
            particle_radius,
            density,
            albedo,
            ..
        } => {
            c.count(&format!("{at}.count"), *count, 1, MAX_PARTICLES as u32);
            c.finite3(&format!("{at}.center"), *center);
            positive3(c, &format!("{at}.radii"), *radii);
            radius_range(c, &format!("{at}.particle_radius"), *particle_radius, true);
            non_negative(c, &format!("{at}.density"), *density);
            c.unit_interval3(&format!("{at}.albedo"), *albedo);
        }
        GeneratorDesc::SmokeColumn {
            count,
            base,
            height,
            radius_bottom,
            radius_top,
            particle_radius,
            density,
            albedo,
            ..
        } => {
            c.count(&format!("{at}.count"), *count, 1, MAX_PARTICLES as u32);
            c.finite3(&format!("{at}.base"), *base);
            c.positive(&format!("{at}.height"), *height);
            non_negative(c, &format!("{at}.radius_bottom"), *radius_bottom);
            non_negative(c, &format!("{at}.radius_top"), *radius_top);
            radius_range(c, &format!("{at}.particle_radius"), *particle_radius, false);
            non_negative(c, &format!("{at}.density"), *density);
            c.unit_interval3(&format!("{at}.albedo"), *albedo);
        }
    }
}
