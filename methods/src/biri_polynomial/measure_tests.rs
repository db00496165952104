//! Measurement (ignored by default; prints tables): the polynomial's error on whole images of
//! library scenes, per order and fit, isolated from every GPU effect. Per pixel: the camera ray,
//! its hit distance and its lit intervals from the reference's exact ray casting
//! (`harness::reference`), each lit interval integrated (a) by the polynomial of eq. 6 and (b)
//! by a 2000-point Gauss–Legendre rule in θ. Run with
//! `cargo test --release -p methods --lib biri_polynomial::measure -- --ignored --nocapture`.

use harness::reference::shadow::{Source, shadowed};
use harness::reference::world::World;
use scenes::LightState;

use super::poly::{Fit, kernel, ray_frame, segment};
use super::poly_tests::gauss;

/// One pixel: lit segments as (t, h, x0, x1) and its (θ_min, θ_max) span.
type Pixel = Vec<(f64, f64, f64, f64)>;

fn pixels(name: &str, res: u32) -> (Vec<Pixel>, f64, scenes::Phase) {
    let scene = scenes::library::resolve(name).expect("library scene");
    let frame = scene.frame(0);
    let world = World::new(&scene, &frame);
    let med = scene.medium().homogeneous().expect("homogeneous");
    let l = match frame.lights[0] {
        LightState::Point { position, .. } => position.as_dvec3(),
        _ => panic!("point light expected"),
    };
    let rays = frame.camera.rays(res, res);
    let mut out = Vec::new();
    for j in 0..res {
        for i in 0..res {
            let d = rays.direction(i, j);
            let o = rays.origin;
            let len = world
                .bvh
                .intersect(o, d, rays.near_distance(d), f64::INFINITY)
                .map(|h| h.t)
                .unwrap_or(rays.far_distance(d));
            let shadow = shadowed(&world.bvh, o, d, len, Source::Point(l)).unwrap_or_default();
            let (t, h) = ray_frame(o.to_array(), d.to_array(), l.to_array());
            let mut lit = Vec::new();
            let mut x = 0.0;
            for (a, b) in shadow.iter().copied().chain([(len, len)]) {
                if a > x {
                    lit.push((t, h, x, a));
                }
                x = x.max(b);
            }
            out.push(lit);
        }
    }
    (out, med.sigma_t.y as f64, med.phase)
}

#[test]
#[ignore]
fn measure_error_vs_order_fit_and_theta() {
    for name in ["sphere-point", "clear-fog"] {
        let (px, sigma_t, phase) = pixels(name, 64);
        let truth: Vec<f64> = px
            .iter()
            .map(|segs| {
                segs.iter()
                    .map(|&(t, h, x0, x1)| {
                        let (a, b) = (((x0 - t) / h).atan(), ((x1 - t) / h).atan());
                        (-sigma_t * t).exp() / h
                            * gauss(|th| kernel(sigma_t * h, &phase, th), a, b, 400)
                    })
                    .sum()
            })
            .collect();
        let mean = truth.iter().sum::<f64>() / truth.len() as f64;
        // θ span of a pixel: the largest |θ| its lit segments reach.
        let span: Vec<f64> = px
            .iter()
            .map(|segs| {
                segs.iter()
                    .map(|&(t, h, x0, x1)| {
                        ((x0 - t) / h).atan().abs().max(((x1 - t) / h).atan().abs())
                    })
                    .fold(0.0, f64::max)
            })
            .collect();
        let bins = [0.0, 0.8, 1.2, 1.4, 1.5, 1.58];
        println!(
            "\n{name} (64², per unit σ_s·I; rel RMSE = RMSE / mean; bins by max |θ| of the pixel's lit segments)"
        );
        println!(
            "fit       n  rel_rmse   rel_err by max|θ| bin {:?}",
            &bins[1..]
        );
        for fit in [Fit::Taylor, Fit::Chebyshev] {
            for n in 2..=8 {
                let est: Vec<f64> = px
                    .iter()
                    .map(|segs| {
                        segs.iter()
                            .map(|&(t, h, x0, x1)| segment(fit, sigma_t, &phase, n, t, h, x0, x1))
                            .sum()
                    })
                    .collect();
                let mse = est
                    .iter()
                    .zip(&truth)
                    .map(|(e, t)| (e - t) * (e - t))
                    .sum::<f64>()
                    / est.len() as f64;
                let mut by_bin = Vec::new();
                for w in bins.windows(2) {
                    let (mut num, mut den) = (0.0, 0.0);
                    for k in 0..est.len() {
                        if span[k] >= w[0] && span[k] < w[1] {
                            num += (est[k] - truth[k]).abs();
                            den += truth[k];
                        }
                    }
                    by_bin.push(if den > 0.0 {
                        format!("{:.2e}", num / den)
                    } else {
                        "-".into()
                    });
                }
                println!(
                    "{:9} {n}  {:.3e}  {}",
                    format!("{fit:?}"),
                    mse.sqrt() / mean,
                    by_bin.join(" ")
                );
            }
        }
    }
}
