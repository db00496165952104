//! Camera impostors per direction bin (knob `camera_tiles`, a modernisation of §2.1).
//!
//! The paper renders the prototype block ONE camera impostor per frame and composites every
//! instance from it, i.e. it sees every instance along one direction. Under perspective the
//! instances are seen along directions up to the cloud's half-angle apart (±15° for
//! `cloud-blocks`), and a block that is not round looks different from each: the impostor's
//! depths and optical depths belong to another view. Here the instances' directions from the
//! eye are binned into a g × g grid over the cloud's angular extent (tangent-plane
//! coordinates about their mean direction), each bin gets its own camera tile of the prototype,
//! rendered toward the mean direction of its instances, and each instance reads its bin's tile.
//! Cost: g² × b impostor splats instead of b (b = particles per block); `camera_tiles = 1` is
//! the paper; g is capped at √blocks (mod.rs). Clusters (`instancing = clusters`) already have
//! one camera tile each.

use glam::Vec3;

/// Each direction's bin (0 .. g²) and every bin's anchor: a point along the mean direction of
/// its members from the eye (a bin without members gets the grid cell's centre direction).
pub fn bins(centres: &[Vec3], eye: Vec3, g: usize) -> (Vec<usize>, Vec<Vec3>) {
    let g = g.max(1);
    let dirs: Vec<Vec3> = centres
        .iter()
        .map(|&c| (c - eye).try_normalize().unwrap_or(Vec3::Z))
        .collect();
    let mean = dirs.iter().sum::<Vec3>().try_normalize().unwrap_or(Vec3::Z);
    let (r, u) = super::primitives::basis_of(mean);
    // Tangent-plane coordinates (the directions all lie in front of the eye's mean direction
    // for a cloud seen from outside; a direction behind it is clamped to the plane's edge).
    let plane: Vec<(f32, f32)> = dirs
        .iter()
        .map(|d| {
            let z = d.dot(mean).max(1e-3);
            (d.dot(r) / z, d.dot(u) / z)
        })
        .collect();
    let lo = plane
        .iter()
        .fold((f32::MAX, f32::MAX), |a, p| (a.0.min(p.0), a.1.min(p.1)));
    let hi = plane
        .iter()
        .fold((f32::MIN, f32::MIN), |a, p| (a.0.max(p.0), a.1.max(p.1)));
    let cell = |v: f32, lo: f32, hi: f32| {
        let f = (v - lo) / (hi - lo).max(1e-9);
        ((f * g as f32) as usize).min(g - 1)
    };
    let bin: Vec<usize> = plane
        .iter()
        .map(|&(x, y)| cell(y, lo.1, hi.1) * g + cell(x, lo.0, hi.0))
        .collect();
    let mut sum = vec![Vec3::ZERO; g * g];
    for (b, d) in bin.iter().zip(&dirs) {
        sum[*b] += *d;
    }
    let anchors = sum
        .iter()
        .enumerate()
        .map(|(b, s)| {
            let dir = s.try_normalize().unwrap_or_else(|| {
                let t = |i: usize, lo: f32, hi: f32| lo + (hi - lo) * (i as f32 + 0.5) / g as f32;
                (mean + r * t(b % g, lo.0, hi.0) + u * t(b / g, lo.1, hi.1)).normalize()
            });
            eye + dir
        })
        .collect();
    (bin, anchors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_bin_is_the_mean_direction() {
        let c = [Vec3::new(-1.0, 0.0, -10.0), Vec3::new(1.0, 0.0, -10.0)];
        let (bin, anchors) = bins(&c, Vec3::ZERO, 1);
        assert_eq!(bin, vec![0, 0]);
        assert!((anchors[0] - Vec3::NEG_Z).length() < 1e-5);
    }

    #[test]
    fn bins_split_the_view_and_anchor_at_their_members() {
        // Four centres at the corners of the view: a 2 × 2 grid gives each its own bin, whose
        // anchor is that centre's own direction.
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let c = [
            Vec3::new(-2.0, -1.0, 0.0),
            Vec3::new(2.0, -1.0, 0.0),
            Vec3::new(-2.0, 1.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
        ];
        let (bin, anchors) = bins(&c, eye, 2);
        let mut seen = bin.clone();
        seen.sort();
        assert_eq!(seen, vec![0, 1, 2, 3]);
        for (i, &b) in bin.iter().enumerate() {
            let want = (c[i] - eye).normalize();
            assert!((anchors[b] - eye - want).length() < 1e-5, "bin {b}");
        }
    }
}
