//! The reach test against brute force: a cone it declares unreachable has no sample point
//! inside the frustum, and cones that plainly meet the frustum are kept.

use super::*;
use glam::Vec3;
use scenes::CameraPose;

fn camera() -> Mat4 {
    CameraPose {
        position: Vec3::new(0.0, 1.0, 5.0),
        look_at: Vec3::new(0.0, 1.0, 0.0),
        up: Vec3::Y,
        fov_y_deg: 50.0,
        near: 0.1,
        far: 30.0,
    }
    .clip_from_world(1.0)
}

fn spot(position: Vec3, direction: Vec3, outer_deg: f32) -> LightState {
    let o = outer_deg.to_radians();
    LightState::Spot {
        position,
        direction: direction.normalize(),
        cos_inner: o.cos(),
        cos_outer: o.cos(),
        tan_outer: o.tan(),
        intensity: Vec3::ONE,
        pattern: None,
    }
}

/// Whether any point of a dense sampling of the cone (to 60 m) projects inside the frustum.
fn cone_meets_frustum(light: &LightState, m: Mat4) -> bool {
    let cone = light.spot_cone().expect("a spot light");
    let (position, direction) = (cone.apex, cone.direction);
    let half = cone.cos_outer.acos();
    let (r, u) = scenes::light::spot_frame(direction.as_dvec3());
    let (r, u) = (r.as_vec3(), u.as_vec3());
    for i in 0..=16 {
        let a = half * i as f32 / 16.0;
        for j in 0..32 {
            let phi = std::f32::consts::TAU * j as f32 / 32.0;
            let d = direction * a.cos() + (r * phi.cos() + u * phi.sin()) * a.sin();
            for s in 1..=600 {
                let p = m * (position + d * (0.1 * s as f32)).extend(1.0);
                let n = p.truncate() / p.w;
                if p.w > 0.0 && n.x.abs() <= 1.0 && n.y.abs() <= 1.0 && (0.0..=1.0).contains(&n.z) {
                    return true;
                }
            }
        }
    }
    false
}

#[test]
fn point_and_directional_lights_always_reach() {
    let m = camera();
    let point = LightState::Point {
        position: Vec3::new(0.0, 0.0, 100.0),
        intensity: Vec3::ONE,
    };
    let sun = LightState::Directional {
        direction: Vec3::Y,
        irradiance: Vec3::ONE,
    };
    assert!(reaches(&point, m) && reaches(&sun, m));
}

#[test]
fn dropped_cones_never_meet_the_frustum_and_visible_ones_are_kept() {
    let m = camera();
    let cases = [
        // Behind the camera, pointing away from the view.
        (Vec3::new(0.0, 1.0, 8.0), Vec3::Z, 30.0),
        // Above the frustum, pointing up.
        (Vec3::new(0.0, 20.0, -5.0), Vec3::Y, 20.0),
        // Inside the view, pointing anywhere.
        (Vec3::new(0.0, 1.0, 0.0), Vec3::Z, 10.0),
        (Vec3::new(0.0, 1.0, 0.0), -Vec3::Z, 10.0),
        // Behind the camera, pointing into the view.
        (Vec3::new(0.0, 1.0, 8.0), -Vec3::Z, 5.0),
        // Beside the frustum, a wide cone leaning in.
        (Vec3::new(15.0, 1.0, 0.0), Vec3::new(-0.2, 0.0, -1.0), 60.0),
    ];
    let mut dropped = 0;
    for (p, d, deg) in cases {
        let l = spot(p, d, deg);
        let meets = cone_meets_frustum(&l, m);
        if !reaches(&l, m) {
            dropped += 1;
            assert!(
                !meets,
                "a cone at {p} toward {d} meets the frustum but was dropped"
            );
        } else if !meets {
            eprintln!("kept (conservatively) a cone at {p} toward {d}");
        }
    }
    assert_eq!(dropped, 2, "the two cones facing away must be dropped");
}
