//! A synthetic run directory for the report's tests and `scripts/report-screenshot.sh`: a
//! given results.json plus small generated images at every path it names (and the scenes'
//! references), so the report can be built and looked at without a GPU.
//!
//! The images are plausible rather than real: a glow around a "light" for the in-scatter, a
//! disc for the surface, and each method's image the reference with a tilt as large as the
//! record's in-scatter relative RMSE, so the error maps differ visibly between records.

use std::path::Path;

use anyhow::{Result, anyhow};
use harness::image::colormap::error_map;
use harness::image::io::{write_exr, write_png};
use harness::image::metrics::ToneMap;
use harness::image::{Image, io::write_png_ldr};
use harness::results::Results;

/// Edge length (px) of the generated images.
pub const SIZE: u32 = 32;

/// The three AOVs of the reference of a scene; `seed` moves the light between scenes.
fn reference(seed: f32) -> [Image; 3] {
    let mut ins = Image::new(SIZE, SIZE);
    let mut surf = Image::new(SIZE, SIZE);
    let (lx, ly) = (0.35 + 0.3 * seed, 0.4);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let (u, v) = (
                (x as f32 + 0.5) / SIZE as f32,
                (y as f32 + 0.5) / SIZE as f32,
            );
            let r2 = (u - lx).powi(2) + (v - ly).powi(2);
            let glow = 0.02 / (0.01 + r2);
            ins.set(x, y, [glow, glow * 0.9, glow * 0.8]);
            let disc = ((u - 0.5).powi(2) + (v - 0.75).powi(2) < 0.04) as u8 as f32;
            surf.set(x, y, [0.4 * disc, 0.3 * disc, 0.2 * disc]);
        }
    }
    let total = add(&ins, &surf);
    [ins, surf, total]
}

fn add(a: &Image, b: &Image) -> Image {
    let mut out = a.clone();
    for (o, q) in out.pixels.iter_mut().zip(&b.pixels) {
        *o = [o[0] + q[0], o[1] + q[1], o[2] + q[2]];
    }
    out
}

/// The reference with a horizontal tilt of relative size `err`.
fn perturbed(img: &Image, err: f32) -> Image {
    let mut out = img.clone();
    for y in 0..img.height {
        for x in 0..img.width {
            let k = 1.0 + err * (2.0 * x as f32 / img.width as f32 - 1.0) * 1.7;
            out.set(x, y, img.get(x, y).map(|c| c * k));
        }
    }
    out
}

/// Writes `results_json` as `dir/results.json` and an image at every path it names.
pub fn write(dir: &Path, results_json: &str) -> Result<Results> {
    let results: Results =
        serde_json::from_str(results_json).map_err(|e| anyhow!("fixture results.json: {e}"))?;
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("results.json"), results_json)?;
    let err = |e: String| anyhow!(e);
    let mut scenes: Vec<&str> = Vec::new();
    for r in &results.records {
        if !scenes.contains(&r.scene.as_str()) {
            scenes.push(&r.scene);
        }
    }
    for (i, scene) in scenes.iter().enumerate() {
        let refs = reference(i as f32);
        let tone = ToneMap::auto(&refs[2]);
        let rd = dir.join(scene).join("reference");
        std::fs::create_dir_all(&rd)?;
        for (name, img) in ["inscatter", "surface", "total"].iter().zip(&refs) {
            write_png(&rd.join(format!("{name}.png")), img, &tone).map_err(err)?;
            write_exr(&rd.join(format!("{name}.exr")), img).map_err(err)?;
        }
        for r in results.records.iter().filter(|r| &r.scene == scene) {
            let e = r.errors.get("inscatter").map(|m| m.rel_rmse).unwrap_or(0.0) as f32;
            let [ins, surf, _] = &refs;
            let ins_t = perturbed(ins, e);
            let total_t = add(&ins_t, surf);
            for (key, rel) in &r.images {
                let path = dir.join(rel);
                if let Some(parent) = path.parent() {
                    std::fs::create_dir_all(parent)?;
                }
                let scale = |aov: &str| {
                    r.counters
                        .get(&format!("{aov}_error_scale"))
                        .copied()
                        .unwrap_or(1.0) as f32
                };
                match key.as_str() {
                    "inscatter_error" => {
                        write_png_ldr(&path, &error_map(&ins_t, ins, scale("inscatter")))
                    }
                    "total_error" => {
                        write_png_ldr(&path, &error_map(&total_t, &refs[2], scale("total")))
                    }
                    k => {
                        let img = match k.trim_end_matches("_png") {
                            "inscatter" => &ins_t,
                            "surface" => surf,
                            _ => &total_t,
                        };
                        if rel.ends_with(".exr") {
                            write_exr(&path, img)
                        } else {
                            write_png(&path, img, &tone)
                        }
                    }
                }
                .map_err(err)?;
            }
        }
    }
    Ok(results)
}
