//! Semantic validation: every problem in a scene description, all at once, each with the
//! field path it is about. Nothing here panics, whatever the numbers.
//!
//! Here: [`validate`], which walks the description; `checker` holds the [`Problem`] list,
//! its field tests and the limits. By what they check: [`view`] (the camera and an animated view),
//! [`medium`] (coefficients, phase, height fog, particles), [`lights`], [`shapes`] (objects'
//! transforms and shapes).

use std::path::Path;

use crate::desc::SceneDesc;

mod checker;
mod lights;
mod medium;
mod shapes;
mod view;

pub use checker::{
    MAX_COORDINATE, MAX_FAR_OVER_NEAR, MAX_PARTICLES, MIN_FLASHLIGHT_OFFSET, Problem,
};
use checker::{Checker, MAX_FRAMES, unique_frames};
use lights::light;
use medium::medium;
use shapes::{shape, transform};
use view::camera;

/// Every semantic problem of `d`. OBJ paths resolve against `base`.
pub fn validate(d: &SceneDesc, base: &Path) -> Vec<Problem> {
    let mut c = Checker { out: Vec::new() };
    camera(&mut c, d);
    medium(&mut c, &d.medium);
    if d.lights.is_empty() {
        c.push(
            "lights",
            "the scene has no light: there is nothing to render",
        );
    }
    for (i, l) in d.lights.iter().enumerate() {
        light(&mut c, &format!("lights[{i}]"), l);
    }
    for (i, o) in d.objects.iter().enumerate() {
        let p = format!("objects[{i}]");
        shape(&mut c, &format!("{p}.shape"), &o.shape, base);
        transform(&mut c, &format!("{p}.transform"), &o.transform);
        unique_frames(
            &mut c,
            &format!("{p}.keyframes"),
            "",
            o.keyframes.iter().map(|k| k.frame).enumerate(),
        );
        for (k, key) in o.keyframes.iter().enumerate() {
            c.finite(&format!("{p}.keyframes[{k}].frame"), key.frame);
            transform(
                &mut c,
                &format!("{p}.keyframes[{k}].transform"),
                &key.transform,
            );
        }
        let m = &o.material;
        c.unit_interval3(&format!("{p}.material.albedo"), m.albedo);
        if let Some(ph) = &m.phong {
            c.unit_interval3(&format!("{p}.material.phong.ks"), ph.ks);
            if !(ph.shininess.is_finite() && ph.shininess >= 1.0) {
                c.push(
                    &format!("{p}.material.phong.shininess"),
                    format!("must be a finite number ≥ 1, got {}", ph.shininess),
                );
            }
        }
    }
    c.count("frames", d.frames, 1, MAX_FRAMES);
    c.out
}
