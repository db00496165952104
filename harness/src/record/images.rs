//! The files a record writes beside results.json: its AOVs as EXR and PNG under
//! `<scene>/<method>/<params slug>/`, and the error maps' scale (ARCHITECTURE §5.1).

use std::collections::BTreeMap;
use std::path::Path;

use rayon::prelude::*;

use crate::image::metrics::ToneMap;
use crate::image::{Image, io};
use crate::method::Params;

/// A filesystem-safe slug of a parameter set: `steps-128_jitter-false`.
pub fn params_slug(params: &Params) -> String {
    let s: Vec<String> = params.iter().map(|(k, v)| format!("{k}-{v}")).collect();
    let s = s.join("_");
    let s: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() {
        return "default".into();
    }
    if s.len() <= MAX_SLUG {
        return s;
    }
    // A file name is at most 255 bytes: a long slug keeps its head and ends with a digest of
    // the whole, so distinct parameter sets stay distinct.
    use sha2::Digest;
    let digest = sha2::Sha256::digest(s.as_bytes());
    let hex: String = digest[..8].iter().map(|b| format!("{b:02x}")).collect();
    format!("{}-{hex}", &s[..MAX_SLUG - 17])
}

/// The longest slug kept whole (bytes; ASCII by construction).
const MAX_SLUG: usize = 200;

/// The error that maps to the top of an error map's colour bar: a tenth of the reference's
/// 99th-percentile luminance, so 10% errors saturate.
pub fn error_scale(reference: &Image) -> f32 {
    let mut l = reference.luminance();
    l.retain(|v| v.is_finite());
    if l.is_empty() {
        return 1.0;
    }
    l.sort_by(f32::total_cmp);
    let p99 = l[((l.len() as f64 * 0.99) as usize).min(l.len() - 1)];
    (0.1 * p99).max(1e-12)
}

/// Writes the three AOVs under `out/rel_dir` as EXR and tone-mapped PNG; returns their paths
/// relative to `out` (`inscatter`, `inscatter_png`, …).
pub fn write_aovs(
    out: &Path,
    rel_dir: &str,
    inscatter: &Image,
    surface: &Image,
    total: &Image,
    tone: &ToneMap,
) -> Result<BTreeMap<String, String>, String> {
    std::fs::create_dir_all(out.join(rel_dir))
        .map_err(|e| format!("{}: {e}", out.join(rel_dir).display()))?;
    // Encoding is independent per AOV: on the cores, beside the scoring (score.rs).
    let written = [
        ("inscatter", inscatter),
        ("surface", surface),
        ("total", total),
    ]
    .par_iter()
    .map(|&(name, img)| {
        let exr = format!("{rel_dir}/{name}.exr");
        let png = format!("{rel_dir}/{name}.png");
        io::write_exr(&out.join(&exr), img)?;
        io::write_png(&out.join(&png), img, tone)?;
        Ok([(name.to_string(), exr), (format!("{name}_png"), png)])
    })
    .collect::<Result<Vec<_>, String>>()?;
    Ok(written.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::ParamValue;

    /// A parameter set whose slug would pass the 255-byte file-name limit gets a shorter one,
    /// and two such sets differing only past the cut still get different slugs.
    #[test]
    fn long_slugs_are_cut_and_stay_distinct() {
        let set = |last: i64| -> Params {
            let mut p: Params = (0..20)
                .map(|i| (format!("a_rather_long_knob_{i}"), ParamValue::Int(i)))
                .collect();
            p.insert("zz_last".into(), ParamValue::Int(last));
            p
        };
        let (a, b) = (params_slug(&set(1)), params_slug(&set(2)));
        assert!(a.len() <= MAX_SLUG && b.len() <= MAX_SLUG, "{a}");
        assert_ne!(a, b);
        let short: Params = [("steps".to_string(), ParamValue::Int(128))].into();
        assert_eq!(params_slug(&short), "steps-128");
    }
}
