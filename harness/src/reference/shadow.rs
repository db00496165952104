//! Exact shadowed intervals of a camera ray.
//!
//! The points of the segment [0, len] of a ray that a light cannot see are shadowed by the
//! occluders that cut the *fan*: the triangle (light, ray start, ray end) for a point light, the
//! half-strip swept by the segment toward the light for directional light. Each occluder
//! triangle meets the fan's plane in a chord; the part of the chord inside the fan, projected
//! from the light onto the ray (centrally for a point light, along the light direction for
//! directional light), is exactly the interval it shadows. The union of those intervals is the
//! shadowed set — no sampling, so no thin occluder is ever missed.
//!
//! Degenerate fans (the light on the ray's line, sunlight parallel to the ray) return None and
//! the caller falls back to sampling and bisection.

use glam::DVec3;

use super::bvh::Bvh;

/// Where the light is, as the fan construction needs it.
#[derive(Clone, Copy, Debug)]
pub enum Source {
    Point(DVec3),
    /// Unit vector from the scene toward the sun, and how far shadow rays reach.
    Direction(DVec3, f64),
}

/// Shadowed sub-intervals of [0, len] (sorted, merged), or None for a degenerate fan.
pub fn shadowed(bvh: &Bvh, o: DVec3, d: DVec3, len: f64, src: Source) -> Option<Vec<(f64, f64)>> {
    let toward = match src {
        Source::Point(l) => l - o,
        Source::Direction(s, _) => s,
    };
    // In-plane basis: e1 along the ray, e2 perpendicular toward the light.
    let perp = toward - d * toward.dot(d);
    if perp.length() <= 1e-12 * toward.length().max(1e-300) {
        return None;
    }
    let e2 = perp.normalize();
    let n = d.cross(e2);
    let to2 = |p: DVec3| {
        let v = p - o;
        (v.dot(d), v.dot(e2))
    };
    // The fan's bounding box, for culling BVH nodes along with the plane test.
    let end = o + d * len;
    let (lo, hi) = match src {
        Source::Point(l) => (o.min(end).min(l), o.max(end).max(l)),
        Source::Direction(s, reach) => {
            let (a, b) = (o + s * reach, end + s * reach);
            (o.min(end).min(a).min(b), o.max(end).max(a).max(b))
        }
    };
    let plane_d = n.dot(o);
    let overlaps = |blo: DVec3, bhi: DVec3| {
        if blo.cmpgt(hi).any() || bhi.cmplt(lo).any() {
            return false;
        }
        let c = 0.5 * (blo + bhi);
        let e = 0.5 * (bhi - blo);
        (n.dot(c) - plane_d).abs() <= e.dot(n.abs()) * (1.0 + 1e-12) + 1e-12
    };
    let (lx, ly, sx, sy) = match src {
        Source::Point(l) => {
            let (x, y) = to2(l);
            (x, y, 0.0, 0.0)
        }
        Source::Direction(s, _) => (0.0, 0.0, s.dot(d), s.dot(e2)),
    };
    let is_point = matches!(src, Source::Point(_));
    let mut out: Vec<(f64, f64)> = Vec::new();
    bvh.for_each_caster(overlaps, |tri| {
        let Some((q1, q2)) = chord(tri.p, n, plane_d) else {
            return;
        };
        let (a, b) = (to2(q1), to2(q2));
        // Clip the chord to the part between the ray (y > 0) and the light (y < ly). The upper
        // bound sits a hair below ly: a clipped end point rounded onto or past ly would make the
        // projection's denominator zero or negative and flip a shadow reaching to +∞ into one
        // covering the whole ray (the black floor speckles the stress suite found). What the
        // hair excludes projects beyond 1e12·ly along the ray.
        let y_max = if is_point {
            ly * (1.0 - 1e-12)
        } else {
            f64::INFINITY
        };
        let Some((a, b)) = clip_y(a, b, 0.0, y_max) else {
            return;
        };
        let project = |(x, y): (f64, f64)| {
            if is_point {
                // Line from the light through (x, y) meets y = 0 at:
                lx + (x - lx) * ly / (ly - y)
            } else {
                x - y * sx / sy
            }
        };
        let (ta, tb) = (project(a), project(b));
        let (t0, t1) = (ta.min(tb).max(0.0), ta.max(tb).min(len));
        if t1 > t0 {
            out.push((t0, t1));
        }
    });
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, f64)> = Vec::with_capacity(out.len());
    for (a, b) in out {
        match merged.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => merged.push((a, b)),
        }
    }
    Some(merged)
}

/// The segment where triangle `p` crosses the plane n·x = plane_d, if it does (a triangle lying
/// in the plane has measure-zero effect and yields None).
fn chord(p: [DVec3; 3], n: DVec3, plane_d: f64) -> Option<(DVec3, DVec3)> {
    let s = p.map(|q| n.dot(q) - plane_d);
    if (s[0] > 0.0 && s[1] > 0.0 && s[2] > 0.0) || (s[0] < 0.0 && s[1] < 0.0 && s[2] < 0.0) {
        return None;
    }
    let mut pts: [DVec3; 3] = [DVec3::ZERO; 3];
    let mut k = 0;
    for i in 0..3 {
        let j = (i + 1) % 3;
        if s[i] == 0.0 {
            pts[k] = p[i];
            k += 1;
        } else if (s[i] < 0.0) != (s[j] < 0.0) && s[j] != 0.0 {
            pts[k] = p[i] + (p[j] - p[i]) * (s[i] / (s[i] - s[j]));
            k += 1;
        }
        if k == 3 {
            break;
        }
    }
    match k {
        2 | 3 => Some((pts[0], pts[1])),
        _ => None,
    }
}

/// Clips segment ab (2-D) to y_min ≤ y ≤ y_max.
fn clip_y(
    a: (f64, f64),
    b: (f64, f64),
    y_min: f64,
    y_max: f64,
) -> Option<((f64, f64), (f64, f64))> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let dy = b.1 - a.1;
    for (bound, lower) in [(y_min, true), (y_max, false)] {
        if !bound.is_finite() {
            continue;
        }
        if dy == 0.0 {
            let inside = if lower { a.1 >= bound } else { a.1 <= bound };
            if !inside {
                return None;
            }
            continue;
        }
        let t = (bound - a.1) / dy;
        // Entering or leaving the half-plane as t grows.
        let entering = if lower { dy > 0.0 } else { dy < 0.0 };
        if entering {
            t0 = t0.max(t)
        } else {
            t1 = t1.min(t)
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| (a.0 + (b.0 - a.0) * t, a.1 + dy * t);
    Some((at(t0), at(t1)))
}

#[cfg(test)]
mod tests {
    use super::super::bvh::Tri;
    use super::*;

    #[test]
    fn a_thin_bar_between_ray_and_light_shadows_its_projection() {
        // Light at (0, 10, 0); a 0.02 m wide horizontal slab at y = 5 spanning x in [0.99, 1.01];
        // the ray runs along the x axis. The slab's shadow on y = 0 is x in [1.98, 2.02].
        let z = 5.0;
        let quad = |x0: f64, x1: f64| {
            let (a, b, c, d) = (
                DVec3::new(x0, 5.0, -z),
                DVec3::new(x1, 5.0, -z),
                DVec3::new(x1, 5.0, z),
                DVec3::new(x0, 5.0, z),
            );
            vec![
                Tri {
                    p: [a, b, c],
                    casts_shadow: true,
                },
                Tri {
                    p: [a, c, d],
                    casts_shadow: true,
                },
            ]
        };
        let bvh = Bvh::build(quad(0.99, 1.01));
        let s = shadowed(
            &bvh,
            DVec3::ZERO,
            DVec3::X,
            10.0,
            Source::Point(DVec3::new(0.0, 10.0, 0.0)),
        )
        .unwrap();
        assert_eq!(s.len(), 1);
        assert!(
            (s[0].0 - 1.98).abs() < 1e-12 && (s[0].1 - 2.02).abs() < 1e-12,
            "{s:?}"
        );
        // Sunlight straight down: the shadow is the slab itself.
        let s = shadowed(
            &bvh,
            DVec3::ZERO,
            DVec3::X,
            10.0,
            Source::Direction(DVec3::Y, 100.0),
        )
        .unwrap();
        assert!(
            (s[0].0 - 0.99).abs() < 1e-12 && (s[0].1 - 1.01).abs() < 1e-12,
            "{s:?}"
        );
        // A slab beyond the light casts nothing on the ray.
        let above = Bvh::build(
            quad(0.99, 1.01)
                .into_iter()
                .map(|mut t| {
                    t.p = t.p.map(|p| p + DVec3::new(0.0, 7.0, 0.0));
                    t
                })
                .collect(),
        );
        assert!(
            shadowed(
                &above,
                DVec3::ZERO,
                DVec3::X,
                10.0,
                Source::Point(DVec3::new(0.0, 10.0, 0.0))
            )
            .unwrap()
            .is_empty()
        );
    }

    /// Regression: on fence-spot at 96², pixel (33, 85) hits the floor, and the floor's chord in
    /// that pixel's fan reaches the light's height beyond the light; rounding there used to flip
    /// a shadow at +∞ into one covering the whole ray. Checked against ray-cast visibility.
    #[test]
    fn a_chord_reaching_the_lights_height_does_not_shadow_the_whole_ray() {
        let scene = scenes::library::resolve("fence-spot").unwrap();
        let frame = scene.frame(0);
        let world = super::super::world::World::new(&scene, &frame);
        let rays = frame.camera.rays(96, 96);
        let light = frame.lights[0].position().unwrap().as_dvec3();
        let d = rays.direction(33, 85);
        let len = world
            .bvh
            .intersect(rays.origin, d, rays.near_distance(d), rays.far_distance(d))
            .unwrap()
            .t;
        let sh = shadowed(&world.bvh, rays.origin, d, len, Source::Point(light)).unwrap();
        for k in 1..200 {
            let t = len * k as f64 / 200.0;
            let x = rays.origin + d * t;
            let to = light - x;
            let blocked = world
                .bvh
                .occluded(x, to.normalize(), 1e-9, to.length() - 1e-9);
            let inside = sh.iter().any(|&(a, b)| t > a + 1e-6 && t < b - 1e-6);
            let near_end = sh
                .iter()
                .any(|&(a, b)| (t - a).abs() < 1e-6 || (t - b).abs() < 1e-6);
            assert!(
                near_end || inside == blocked,
                "t = {t}: intervals {sh:?}, ray cast says blocked = {blocked}"
            );
        }
    }
}
