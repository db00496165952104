//! Compares headline-error candidates on a finished run (the analysis behind docs/ARCHITECTURE.md §4.4).
//!
//! For every ok record of `RUN/results.json` it reloads the method's and the reference's EXRs
//! from the run directory and computes, on in-scatter and total: the headline (trimmed relative
//! MAE), the trimmed relative RMSE at 0.1 %, 0.3 % and 1 % and with the light core left out,
//! the untrimmed relative RMSE (RMSE / mean, the old verdict), sqrt(relMSE) with
//! ε = 0.01·mean², SMAPE, and the light-core error; FLIP is read from the record. Then, per
//! candidate, the share of same-scene method pairs it orders as mean FLIP on total does, and
//! the pairs where the headline disagrees.
//!
//! ```text
//! cargo run --release -p harness --example headline_candidates -- RUN_DIR [REFCACHE]
//! ```
//! REFCACHE (default /work/refcache) supplies the reference's distance buffer for the light core.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use harness::image::Image;
use harness::image::headline::{difference, headline, masked_relative, smape};
use harness::image::io::read_exr;
use harness::image::metrics::{ToneMap, compare};
use harness::reference::{Settings, cache};
use harness::results::{Results, Status};
use harness::verdict::light_core_mask;

/// One record's candidate values, per AOV (0 = in-scatter, 1 = total).
struct Row {
    scene: String,
    method: String,
    trimmed: [f64; 2],
    rel_rmse: [f64; 2],
    sqrt_rel_mse: [f64; 2],
    smape: [f64; 2],
    core: [Option<f64>; 2],
    /// Relative RMSE trimmed by 0.3 % and 1 %, and 0.1 %-trimmed outside the light core.
    trim03: [f64; 2],
    trim1: [f64; 2],
    outside_core: [f64; 2],
    /// The headline: relative MAE Σ|d| / Σ|r| without the 0.1 % pixels of largest Σ_c|d_c|.
    rel_l1: [f64; 2],
    /// Smallest share of pixels that holds half the squared error (in-scatter).
    half_share: f64,
    flip_total: f64,
}

const AOVS: [&str; 2] = ["inscatter", "total"];

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let run = PathBuf::from(
        args.get(1)
            .ok_or("usage: headline_candidates RUN_DIR [REFCACHE]")?,
    );
    let refcache = PathBuf::from(args.get(2).map_or("/work/refcache", |s| s.as_str()));
    let results = Results::load(&run.join("results.json"))?;
    let (w, h) = (results.run.resolution[0], results.run.resolution[1]);
    let mut rows = Vec::new();
    let mut masks: BTreeMap<String, Option<Vec<bool>>> = BTreeMap::new();
    for rec in results.records.iter().filter(|r| r.status == Status::Ok) {
        let reference = |aov: &str| {
            read_exr(
                &run.join(&rec.scene)
                    .join("reference")
                    .join(format!("{aov}.exr")),
            )
        };
        let mask = masks
            .entry(rec.scene.clone())
            .or_insert_with(|| core_mask(&rec.scene, w, h, &refcache))
            .clone();
        let mut row = Row {
            scene: rec.scene.clone(),
            method: rec.method.clone(),
            trimmed: [0.0; 2],
            rel_rmse: [0.0; 2],
            sqrt_rel_mse: [0.0; 2],
            smape: [0.0; 2],
            core: [None; 2],
            trim03: [0.0; 2],
            trim1: [0.0; 2],
            outside_core: [0.0; 2],
            half_share: 0.0,
            rel_l1: [0.0; 2],
            flip_total: rec.errors.get("total").map_or(f64::NAN, |m| m.flip_mean),
        };
        for (k, aov) in AOVS.iter().enumerate() {
            let test = read_exr(&run.join(rec.images.get(*aov).ok_or("no image")?))?;
            let r = reference(aov)?;
            let m = compare(&test, &r, &ToneMap::default())?;
            let d = difference(&test, &r);
            row.trimmed[k] = trimmed_relative(&d, &r, 0.001, 2);
            row.rel_rmse[k] = m.rel_rmse;
            row.sqrt_rel_mse[k] = m.rel_mse.sqrt();
            row.smape[k] = smape(&test, &r);
            row.core[k] = mask.as_ref().and_then(|m| masked_relative(&test, &r, m));
            row.rel_l1[k] = headline(&test, &r);
            if k == 0 {
                row.half_share = half_share(&d);
            }
            row.trim03[k] = trimmed_relative(&d, &r, 0.003, 2);
            row.trim1[k] = trimmed_relative(&d, &r, 0.01, 2);
            row.outside_core[k] = match &mask {
                Some(m) => {
                    let keep = |img: &Image| {
                        let mut out = img.clone();
                        for (p, &c) in out.pixels.iter_mut().zip(m) {
                            if c {
                                *p = [0.0; 3];
                            }
                        }
                        out
                    };
                    trimmed_relative(&keep(&d), &keep(&r), 0.001, 2)
                }
                None => row.trimmed[k],
            };
        }
        rows.push(row);
    }
    print_rows(&rows);
    type Pick = fn(&Row, usize) -> f64;
    let candidates: [(&str, Pick); 9] = [
        ("HEADLINE trimmed rel MAE", |r, k| r.rel_l1[k]),
        ("trimmed rel RMSE", |r, k| r.trimmed[k]),
        ("trimmed 0.3 %", |r, k| r.trim03[k]),
        ("trimmed 1 %", |r, k| r.trim1[k]),
        ("trimmed, core excluded", |r, k| r.outside_core[k]),
        ("rel RMSE (untrimmed)", |r, k| r.rel_rmse[k]),
        ("sqrt relMSE", |r, k| r.sqrt_rel_mse[k]),
        ("SMAPE", |r, k| r.smape[k]),
        ("light core", |r, k| r.core[k].unwrap_or(f64::NAN)),
    ];
    println!("\nagreement with mean FLIP on total over same-scene pairs (FLIP ties excluded):");
    for (name, pick) in candidates {
        for (k, aov) in AOVS.iter().enumerate() {
            let (agree, total, ties, _) = agreement(&rows, |r| pick(r, k));
            println!(
                "  {name:24} on {aov:9}: {agree}/{total} = {:.1} % ({ties} FLIP ties)",
                100.0 * agree as f64 / total.max(1) as f64
            );
        }
    }
    for (k, aov) in AOVS.iter().enumerate() {
        let (_, _, _, bad) = agreement(&rows, |r| r.rel_l1[k]);
        println!("\ndisagreeing pairs, trimmed rel MAE on {aov} vs FLIP on total:");
        for (a, b) in bad {
            let (ra, rb) = (&rows[a], &rows[b]);
            println!(
                "  {:18} {:26} vs {:26} relMAE in {:.4}/{:.4} tot {:.4}/{:.4} | trimmed-rmse in {:.4}/{:.4} tot {:.4}/{:.4} FLIP {:.5}/{:.5} relRMSE-in {:.3}/{:.3} core-in {}/{} half-err-px {:.2}%/{:.2}%",
                ra.scene,
                ra.method,
                rb.method,
                ra.rel_l1[0],
                rb.rel_l1[0],
                ra.rel_l1[1],
                rb.rel_l1[1],
                ra.trimmed[0],
                rb.trimmed[0],
                ra.trimmed[1],
                rb.trimmed[1],
                ra.flip_total,
                rb.flip_total,
                ra.rel_rmse[0],
                rb.rel_rmse[0],
                show(ra.core[0]),
                show(rb.core[0]),
                100.0 * ra.half_share,
                100.0 * rb.half_share
            );
        }
    }
    Ok(())
}

/// Smallest fraction of the pixels the headline keeps whose squared errors add up to half of
/// their total (how concentrated the error the headline sees is).
fn half_share(d: &Image) -> f64 {
    let mut e: Vec<f64> = d
        .pixels
        .iter()
        .map(|p| p.iter().map(|&c| (c as f64).powi(2)).sum())
        .collect();
    e.sort_by(|a, b| b.total_cmp(a));
    let n = e.len() as f64;
    // After the headline's trim: the pixels it keeps.
    let e = &e[(harness::verdict::TRIM_FRACTION * e.len() as f64).floor() as usize..];
    let total: f64 = e.iter().sum();
    let mut acc = 0.0;
    for (i, v) in e.iter().enumerate() {
        acc += v;
        if acc >= 0.5 * total {
            return (i + 1) as f64 / n;
        }
    }
    1.0
}

/// Trimmed relative L^power error: (Σ_K Σ_c|d_c|^p / Σ_K Σ_c|r_c|^p)^(1/p), K without the
/// `fraction` of pixels of largest Σ_c|d_c|^p (p = 2: the trimmed relative RMSE).
fn trimmed_relative(d: &Image, r: &Image, fraction: f64, power: i32) -> f64 {
    let sum = |p: &[f32; 3]| p.iter().map(|&c| (c as f64).abs().powi(power)).sum::<f64>();
    let mut px: Vec<(f64, f64)> = d
        .pixels
        .iter()
        .zip(&r.pixels)
        .map(|(a, b)| (sum(a), sum(b)))
        .collect();
    px.sort_by(|a, b| b.0.total_cmp(&a.0));
    let kept = &px[(fraction * px.len() as f64).floor() as usize..];
    let (e, s): (f64, f64) = kept.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    if s > 1e-30 {
        (e / s).powf(1.0 / power as f64)
    } else {
        0.0
    }
}

fn show(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.3}"))
}

/// The light-core mask of frame 0 of a library scene (None: no light in view or no cache).
fn core_mask(scene: &str, w: u32, h: u32, refcache: &Path) -> Option<Vec<bool>> {
    let s = scenes::library::resolve(scene).ok()?;
    let key = cache::key(&s, 0, w, h, &Settings::default());
    let r = cache::load(refcache, &key)?;
    light_core_mask(&s.frame(0), w, h, &r.distance)
}

/// (pairs ordered like FLIP, pairs compared, FLIP ties skipped, the disagreeing pairs).
fn agreement(
    rows: &[Row],
    metric: impl Fn(&Row) -> f64,
) -> (usize, usize, usize, Vec<(usize, usize)>) {
    let (mut agree, mut total, mut ties, mut bad) = (0, 0, 0, Vec::new());
    for a in 0..rows.len() {
        for b in a + 1..rows.len() {
            if rows[a].scene != rows[b].scene {
                continue;
            }
            let (fa, fb) = (rows[a].flip_total, rows[b].flip_total);
            let (ma, mb) = (metric(&rows[a]), metric(&rows[b]));
            if !(ma.is_finite() && mb.is_finite()) {
                continue;
            }
            if fa == fb {
                ties += 1;
                continue;
            }
            total += 1;
            if (fa < fb) == (ma < mb) && ma != mb {
                agree += 1;
            } else {
                bad.push((a, b));
            }
        }
    }
    (agree, total, ties, bad)
}

fn print_rows(rows: &[Row]) {
    println!(
        "{:18} {:26} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "scene",
        "method",
        "relmae-in",
        "relmae-tot",
        "head-in",
        "head-tot",
        "rel-in",
        "relmse-in",
        "smape-in",
        "flip-tot",
        "core-in",
        "core-tot"
    );
    for r in rows {
        println!(
            "{:18} {:26} {:9.4} {:9.4} {:9.4} {:9.4} {:9.4} {:9.4} {:9.4} {:9.5} {:>9} {:>9}",
            r.scene,
            r.method,
            r.rel_l1[0],
            r.rel_l1[1],
            r.trimmed[0],
            r.trimmed[1],
            r.rel_rmse[0],
            r.sqrt_rel_mse[0],
            r.smape[0],
            r.flip_total,
            show(r.core[0]),
            show(r.core[1])
        );
    }
}
