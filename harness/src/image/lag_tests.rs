//! Tests of `lag.rs` on synthetic sequences whose lag and flicker are known by construction.

use super::*;
use crate::image::headline::Temporal;
use crate::testing::Lcg;

/// Frame k of a moving pattern: a wave travelling half a radian per frame (values 0.2–1.0).
fn moving(k: usize) -> Image {
    let (w, h) = (40u32, 32u32);
    let mut img = Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let phase = 0.3 * x as f32 + 0.1 * y as f32 + 0.5 * k as f32;
            let v = 0.6 + 0.4 * phase.sin();
            img.set(x, y, [v, 0.5 * v + 0.2, 1.0 - 0.5 * v]);
        }
    }
    img
}

fn figures(
    frames: usize,
    shown: impl Fn(usize) -> Image,
    reference: impl Fn(usize) -> Image,
) -> LagFigures {
    let mut lf = LagFlicker::default();
    for k in 0..frames {
        lf.push(&shown(k), &reference(k));
    }
    lf.value().expect("two or more frames")
}

fn with_noise(img: &Image, amplitude: f32, rng: &mut Lcg) -> Image {
    Image {
        pixels: img
            .pixels
            .iter()
            .map(|p| p.map(|c| c + amplitude * (2.0 * rng.uniform() as f32 - 1.0)))
            .collect(),
        ..img.clone()
    }
}

#[test]
fn an_exact_method_reads_no_lag_and_no_flicker() {
    let f = figures(8, moving, moving);
    assert_eq!(f.lag_frames, 0.0);
    assert_eq!(f.flicker, Some(0.0));
}

#[test]
fn a_method_one_frame_late_reads_one_frame_of_lag_and_no_flicker() {
    let f = figures(8, |k| moving(k.saturating_sub(1)), moving);
    assert!((f.lag_frames - 1.0).abs() < 0.02, "{f:?}");
    assert!(f.flicker.unwrap() < 1e-6, "{f:?}");
    // Two frames late reads two.
    let f = figures(8, |k| moving(k.saturating_sub(2)), moving);
    assert!((f.lag_frames - 2.0).abs() < 0.02, "{f:?}");
}

#[test]
fn a_half_blend_of_this_frame_and_the_last_reads_half_a_frame() {
    let blend = |k: usize| {
        let (a, b) = (moving(k), moving(k.saturating_sub(1)));
        Image {
            pixels: a
                .pixels
                .iter()
                .zip(&b.pixels)
                .map(|(p, q)| [0, 1, 2].map(|c| 0.5 * p[c] + 0.5 * q[c]))
                .collect(),
            ..a.clone()
        }
    };
    let f = figures(8, blend, moving);
    assert!((f.lag_frames - 0.5).abs() < 0.02, "{f:?}");
    assert!(f.flicker.unwrap() < 1e-6, "{f:?}");
}

#[test]
fn fresh_noise_every_frame_is_flicker_not_lag() {
    let mut rng = Lcg(34);
    let noisy: Vec<Image> = (0..8)
        .map(|k| with_noise(&moving(k), 0.05, &mut rng))
        .collect();
    let f = figures(8, |k| noisy[k].clone(), moving);
    assert!(f.lag_frames < 0.1, "{f:?}");
    let flicker = f.flicker.unwrap();
    assert!(flicker > 0.02, "{f:?}");
}

#[test]
fn on_a_static_scene_lag_is_zero_and_flicker_is_the_temporal_figure() {
    let still = moving(0);
    let mut rng = Lcg(5);
    let noisy: Vec<Image> = (0..6).map(|_| with_noise(&still, 0.03, &mut rng)).collect();
    let f = figures(6, |k| noisy[k].clone(), |_| still.clone());
    assert_eq!(f.lag_frames, 0.0);
    let mut t = Temporal::default();
    for img in &noisy {
        t.push(img, &still);
    }
    let temporal = t.value().unwrap();
    assert!(
        (f.flicker.unwrap() - temporal).abs() < 1e-12,
        "{f:?} vs {temporal}"
    );
}

#[test]
fn fewer_than_two_frames_have_no_figures_and_short_runs_look_back_only_as_far_as_they_can() {
    let mut lf = LagFlicker::default();
    assert_eq!(lf.value(), None);
    lf.push(&moving(0), &moving(0));
    assert_eq!(lf.value(), None);
    // Two frames, the second showing the first: one frame of lag is the furthest it can see.
    lf.push(&moving(0), &moving(1));
    let f = lf.value().unwrap();
    assert!((f.lag_frames - 1.0).abs() < 1e-9, "{f:?}");
    assert_eq!(
        f.flicker, None,
        "no pair of frames reaches back a whole frame"
    );
}
