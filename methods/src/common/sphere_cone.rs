//! A sphere seen from a point, measured against an axis through that point: the angle of its
//! centre from the axis and its angular radius, so its nearest and farthest directions lie at
//! acos(axis · ŵ) ∓ asin(r / d). Whether a spot light's cone reaches a sphere, and how wide a
//! cone about an axis must be to hold a set of spheres (light maps, extinction grids, light
//! volumes), are both read from it.

use glam::Vec3;

/// A sphere as seen from an apex outside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereSeen {
    /// Distance from the apex to the sphere's centre (> its radius).
    pub distance: f32,
    /// Angle between the axis and the direction to the centre (radians).
    pub centre_angle: f32,
    /// Half the angle the sphere subtends, asin(r / d) (radians).
    pub angular_radius: f32,
}

impl SphereSeen {
    /// The sphere (`centre`, `radius`) seen from `apex` against the unit `axis`; None when the
    /// apex lies inside or on it (every direction meets it).
    pub fn from(apex: Vec3, axis: Vec3, centre: Vec3, radius: f32) -> Option<SphereSeen> {
        let to = centre - apex;
        let distance = to.length();
        (distance > radius).then(|| SphereSeen {
            distance,
            centre_angle: (to / distance).dot(axis).clamp(-1.0, 1.0).acos(),
            angular_radius: (radius / distance).asin(),
        })
    }

    /// The angle from the axis of the sphere's direction nearest to it (negative when the axis
    /// passes through the sphere).
    pub fn nearest(&self) -> f32 {
        self.centre_angle - self.angular_radius
    }

    /// The angle from the axis of the sphere's direction farthest from it.
    pub fn farthest(&self) -> f32 {
        self.centre_angle + self.angular_radius
    }
}

/// Whether a spot light's cone (apex, unit axis, outer half-angle) reaches into the sphere
/// (centre, radius): the apex is inside it, or its nearest direction is within the cone.
pub fn cone_reaches_sphere(apex: Vec3, axis: Vec3, outer: f32, centre: Vec3, radius: f32) -> bool {
    SphereSeen::from(apex, axis, centre, radius).is_none_or(|s| s.nearest() <= outer)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cone_test_sees_spheres_inside_and_not_behind() {
        let (apex, axis) = (Vec3::ZERO, Vec3::Z);
        let outer = 0.5;
        assert!(cone_reaches_sphere(
            apex,
            axis,
            outer,
            Vec3::new(0.0, 0.0, 5.0),
            0.1
        ));
        assert!(!cone_reaches_sphere(
            apex,
            axis,
            outer,
            Vec3::new(0.0, 0.0, -5.0),
            1.0
        ));
        // 45° off axis at distance 10: outside a 0.5 rad cone unless the radius reaches in.
        let c = Vec3::new(7.07, 0.0, 7.07);
        assert!(!cone_reaches_sphere(apex, axis, outer, c, 0.5));
        let reaching = 10.0 * (0.79 - 0.5f32).sin() + 0.2;
        assert!(cone_reaches_sphere(apex, axis, outer, c, reaching));
        // The apex inside the sphere: every cone reaches it.
        assert!(cone_reaches_sphere(
            apex,
            axis,
            0.01,
            Vec3::new(0.0, 0.5, -0.5),
            1.0
        ));
    }

    #[test]
    fn nearest_and_farthest_bracket_the_centre_by_the_angular_radius() {
        // A sphere of radius 1 at distance 2, 90° off the axis: it subtends ±30°.
        let s = SphereSeen::from(Vec3::ZERO, Vec3::Z, Vec3::new(2.0, 0.0, 0.0), 1.0).unwrap();
        let deg = |a: f32| a.to_degrees();
        assert!((deg(s.centre_angle) - 90.0).abs() < 1e-4);
        assert!(
            (deg(s.nearest()) - 60.0).abs() < 1e-4,
            "{}",
            deg(s.nearest())
        );
        assert!(
            (deg(s.farthest()) - 120.0).abs() < 1e-4,
            "{}",
            deg(s.farthest())
        );
        assert_eq!(s.distance, 2.0);
        assert!(SphereSeen::from(Vec3::ZERO, Vec3::Z, Vec3::X, 1.0).is_none());
    }
}
