//! Dominant spheres (issue 32, a modernisation; knob `dominant`): the few particles whose
//! approximation by the slices and the "over" compositing breaks down are handled exactly in
//! every pass.
//!
//! Which: in the gathering's list, every sphere that holds the eye, then every one that holds
//! a local light, then the *loose* ones ([`loose`]: optically thick, σ·2r ≥ [`THICK`], or huge,
//! r ≥ [`HUGE`] × the cloud's extent), heaviest (σ·r³) first; at most the knob's count
//! (≤ [`MAX_DOMINANT`]). On the library's clouds (σ·2r ≤ 0.36, no viewer inside) there are
//! none, and nothing changes.
//!
//! What is exact about them (blocks.wgsl, gather.wgsl):
//! - **light leg**: they are left out of every light's list (and of the light maps' extents);
//!   `light_optical_depth` adds their exact chords between the light and the point. A dense
//!   particle around a light, or the eye's, was a kink the slices interpolated across (a light
//!   inside a τ-3 particle: every slice near it wrong), and a 1 km sphere stretched the slices
//!   over 2.4 km.
//! - **eye leg**: every other primitive's in-scatter is attenuated by their exact optical depth
//!   in front of each point of its interval (the closed form split at their chord ends), with
//!   what the "over" compositing applies divided out. The paper's centre order lets a particle
//!   overlapping a dense one escape its extinction (the light deep inside a dense particle:
//!   2.2× the reference's mean) or take all of it.
//! - **their own in-scatter**: a quadrature of `THICK_NODES` nodes along their chord (in Biri's
//!   angle variable for a local light), not the closed form, whose light optical depth is linear
//!   across the interval — across a thick sphere it is not (a sphere filling the view: 1.4×).
//!
//! Limits: at most [`MAX_DOMINANT`] (the uniform's rows); a dominant sphere's own in-scatter is
//! still dimmed by the whole of every primitive composited over it (overlaps in front of it).

use glam::Vec3;
use scenes::particles::Particle;
use scenes::{LightState, Scene};

use super::primitives::Prim;

/// The most dominant spheres the uniform holds (blocks.wgsl `Pb.dominant`, two rows each).
pub const MAX_DOMINANT: usize = 8;
/// A sphere of optical diameter σ·2r at least this is thick: across it the light's optical
/// depth bends too much for the closed form, and the slices interpolate across its surface.
pub const THICK: f32 = 2.0;
/// A sphere of radius at least this times the cloud's extent is huge: it would stretch the
/// light maps' depth range (and texels) over far more than the cloud.
pub const HUGE: f32 = 0.5;

fn centre(p: &Prim) -> Vec3 {
    Vec3::new(p.center[0], p.center[1], p.center[2])
}

/// The cloud's extent (m): the 90th percentile of the particles' centre distances from their
/// centroid (0 for one particle, or every particle at one centre).
pub fn extent(ps: &[Particle]) -> f32 {
    if ps.is_empty() {
        return 0.0;
    }
    let c = ps.iter().map(|p| p.center).sum::<Vec3>() / ps.len() as f32;
    let mut d: Vec<f32> = ps.iter().map(|p| (p.center - c).length()).collect();
    d.sort_by(f32::total_cmp);
    d[(d.len() - 1) * 9 / 10]
}

/// Whether a sphere of `radius` (m) and extinction `density` (1/m) is loose: thick, or huge
/// for a cloud of `extent` (a degenerate extent, 0, makes nothing huge).
pub fn loose(radius: f32, density: f32, extent: f32) -> bool {
    density * 2.0 * radius >= THICK || huge(radius, extent)
}

/// Whether a sphere of `radius` (m) is huge for a cloud of `extent` (never for extent 0).
pub fn huge(radius: f32, extent: f32) -> bool {
    extent > 0.0 && radius >= HUGE * extent
}

/// Whether any frame of `scene` can have a dominant sphere: a loose particle, or a particle
/// holding the camera or a local light in some frame. Without, the shaders are built without
/// their code (passes.rs `Modes::dominant`).
pub fn possible(scene: &Scene, ps: &[Particle]) -> bool {
    let extent = extent(ps);
    ps.iter().any(|p| loose(p.radius, p.density, extent)) || viewer_inside(scene, ps, |_| true)
}

/// Whether in some frame of `scene` the camera or a local light lies inside one of `ps` that
/// `counts`.
pub fn viewer_inside(scene: &Scene, ps: &[Particle], counts: impl Fn(&Particle) -> bool) -> bool {
    (0..scene.frame_count()).any(|f| {
        let frame = scene.frame(f);
        let lights = frame
            .lights
            .iter()
            .filter(|l| !matches!(l, LightState::Directional { .. }))
            .filter_map(LightState::position);
        let viewers: Vec<Vec3> = std::iter::once(frame.camera.position)
            .chain(lights)
            .collect();
        ps.iter()
            .filter(|p| counts(p))
            .any(|p| viewers.iter().any(|&v| (p.center - v).length() < p.radius))
    })
}

/// Indices into `gather` of its dominant spheres (see the module doc), at most `most`.
pub fn pick(gather: &[Prim], eye: Vec3, lights: &[Vec3], extent: f32, most: usize) -> Vec<usize> {
    let holds = |p: &Prim, x: Vec3| (centre(p) - x).length() < p.center[3];
    let rank = |p: &Prim| {
        if p.extra[1] >= 0.0 {
            None
        } else if holds(p, eye) {
            Some(0)
        } else if lights.iter().any(|&l| holds(p, l)) {
            Some(1)
        } else if loose(p.center[3], p.albedo[3], extent) {
            Some(2)
        } else {
            None
        }
    };
    let mass = |p: &Prim| p.albedo[3] * p.center[3].powi(3);
    let mut found: Vec<(usize, u8)> = gather
        .iter()
        .enumerate()
        .filter_map(|(i, p)| rank(p).map(|r| (i, r)))
        .collect();
    found.sort_by(|a, b| {
        a.1.cmp(&b.1)
            .then(mass(&gather[b.0]).total_cmp(&mass(&gather[a.0])))
    });
    found.truncate(most.min(MAX_DOMINANT));
    found.into_iter().map(|(i, _)| i).collect()
}

/// The uniform's rows for `picked` (indices into `gather`): per sphere its centre and radius,
/// then its extinction σ (1/m) and its index in the gathering's list.
pub fn rows(gather: &[Prim], picked: &[usize]) -> [[f32; 4]; 2 * MAX_DOMINANT] {
    let mut out = [[0.0; 4]; 2 * MAX_DOMINANT];
    for (j, &i) in picked.iter().enumerate() {
        out[2 * j] = gather[i].center;
        out[2 * j + 1] = [gather[i].albedo[3], i as f32, 0.0, 0.0];
    }
    out
}

/// `list` without the spheres of `dominant` (matched by centre and radius).
pub fn without(list: &[Prim], dominant: &[Prim]) -> Vec<Prim> {
    let is_dominant = |p: &Prim| p.extra[1] < 0.0 && dominant.iter().any(|d| d.center == p.center);
    list.iter().filter(|p| !is_dominant(p)).copied().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball(c: Vec3, r: f32, density: f32) -> Prim {
        Prim {
            center: [c.x, c.y, c.z, r],
            albedo: [1.0, 1.0, 1.0, density],
            extra: [1.0, -1.0, -1.0, 0.0],
        }
    }

    /// The eye's sphere first, then a light's, then loose ones by mass; thin small spheres
    /// and blocks never; the cap holds; `without` drops exactly the picked spheres.
    #[test]
    fn picks_holders_then_loose_spheres() {
        let mut block = ball(Vec3::ZERO, 5.0, 1.0);
        block.extra[1] = 0.0;
        let gather = vec![
            ball(Vec3::new(5.0, 0.0, 0.0), 0.2, 0.5),  // thin, small
            ball(Vec3::new(0.0, 3.0, 0.0), 0.5, 3.0),  // thick (σ·2r = 3)
            ball(Vec3::new(0.0, 0.0, 9.0), 0.5, 0.1),  // holds the light
            block,                                     // a block holding the eye: never
            ball(Vec3::new(0.1, 0.0, 0.0), 0.3, 0.2),  // holds the eye
            ball(Vec3::new(0.0, -3.0, 0.0), 0.6, 2.0), // thick, heavier
        ];
        let light = [Vec3::new(0.0, 0.0, 9.2)];
        assert_eq!(pick(&gather, Vec3::ZERO, &light, 4.0, 8), vec![4, 2, 5, 1]);
        assert_eq!(pick(&gather, Vec3::ZERO, &light, 4.0, 2), vec![4, 2]);
        assert_eq!(
            pick(&gather, Vec3::ZERO, &light, 4.0, 0),
            Vec::<usize>::new()
        );
        let dominant = [gather[4], gather[2]];
        assert_eq!(without(&gather, &dominant).len(), gather.len() - 2);
        // Huge: radius 2 against an extent of 4 (HUGE × 4 = 2); not for a degenerate extent.
        assert!(loose(2.0, 0.01, 4.0) && !loose(2.0, 0.01, 0.0) && !loose(1.9, 0.01, 4.0));
    }
}
