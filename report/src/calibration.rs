//! An adapter's calibration (ARCHITECTURE §7.1) as the report and `compare` show it (§5.3):
//! its raster and compute throughput for the same per-pixel work as one line, and the flag
//! `compare` puts on a run whose raster-to-compute ratio is far below the other runs'. That is
//! the NVIDIA H100/H200's case (2 of 66 TPCs run pixel shaders): there a raster-bound method's
//! floor ratio, and its rank against a compute method, do not represent a graphics GPU.

use harness::gpu::Calibration;
use serde::Serialize;

/// A run is flagged when its raster-to-compute ratio is below this fraction of the median of
/// the other calibrated runs' ratios.
pub const RASTER_LIMITED_FRACTION: f64 = 0.25;

/// Why a run is flagged raster-limited.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RasterLimited {
    /// The run's raster / compute throughput.
    pub ratio: f64,
    /// The median ratio of the other calibrated runs.
    pub others_median: f64,
    pub message: String,
}

/// Per run, in order: the flag where its ratio is below [`RASTER_LIMITED_FRACTION`] × the
/// median of the others' (runs without a calibration neither flagged nor counted).
pub fn raster_limited(runs: &[(&str, Option<&Calibration>)]) -> Vec<Option<RasterLimited>> {
    let ratios: Vec<Option<f64>> = runs
        .iter()
        .map(|(_, c)| c.map(Calibration::raster_to_compute))
        .collect();
    runs.iter()
        .enumerate()
        .map(|(i, (label, _))| {
            let ratio = ratios[i]?;
            let mut others: Vec<f64> = ratios
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .filter_map(|(_, r)| *r)
                .collect();
            let others_median = median(&mut others)?;
            (ratio < RASTER_LIMITED_FRACTION * others_median).then(|| RasterLimited {
                ratio,
                others_median,
                message: message(label, ratio, others_median),
            })
        })
        .collect()
}

fn message(label: &str, ratio: f64, others_median: f64) -> String {
    format!(
        "{label} is raster-limited: its raster-to-compute throughput is {ratio:.3}, {:.0}× below \
         the other runs' median ({others_median:.2}). Raster-bound methods (fragment-shaded \
         passes) run there far slower against compute methods than on a graphics GPU, so their \
         floor ratios and their ranks against compute methods in {label} do not represent one",
        others_median / ratio
    )
}

fn median(v: &mut [f64]) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(v[n / 2]),
        _ => Some(0.5 * (v[n / 2 - 1] + v[n / 2])),
    }
}

/// The calibration as one line: "raster 1.25 Gfrag/s · compute 2.50 Ginv/s (raster/compute
/// 0.500) · memory 10.00 GB/s (GPU time, 100 ms)".
pub fn text(c: &Calibration) -> String {
    format!(
        "raster {}frag/s · compute {}inv/s (raster/compute {:.3}) · memory {}B/s ({} time, \
         {:.0} ms)",
        si(c.raster_fragments_per_s),
        si(c.compute_invocations_per_s),
        c.raster_to_compute(),
        si(c.memory_bytes_per_s),
        if c.basis == "gpu" { "GPU" } else { "wall" },
        c.ms
    )
}

/// `x` with an SI prefix, two decimals: "1.25 G".
fn si(x: f64) -> String {
    let (v, p) = [(1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k")]
        .into_iter()
        .find(|(s, _)| x >= *s)
        .map_or((x, ""), |(s, p)| (x / s, p));
    format!("{v:.2} {p}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cal(raster: f64, compute: f64) -> Calibration {
        Calibration {
            raster_fragments_per_s: raster,
            compute_invocations_per_s: compute,
            memory_bytes_per_s: 1e10,
            basis: "gpu".into(),
            ms: 100.0,
        }
    }

    /// Synthetic figures of the three adapters this project has run: lavapipe and SwiftShader
    /// shade fragments about as fast as invocations; the H200's 4 raster SMs of 132 make its
    /// ratio ~1/30. Only the H200 is flagged, with its ratio and the others' median.
    #[test]
    fn a_raster_limited_adapter_is_flagged_and_only_it() {
        let (lavapipe, swiftshader, h200) = (cal(0.9e9, 1.0e9), cal(0.6e9, 0.5e9), cal(2e11, 6e12));
        let flags = raster_limited(&[
            ("A", Some(&lavapipe)),
            ("B", Some(&h200)),
            ("C", Some(&swiftshader)),
        ]);
        assert!(flags[0].is_none() && flags[2].is_none(), "{flags:?}");
        let f = flags[1].as_ref().expect("the H200 flagged");
        assert!((f.ratio - 2e11 / 6e12).abs() < 1e-12);
        assert!((f.others_median - 0.5 * (0.9 + 1.2)).abs() < 1e-12);
        assert!(f.message.starts_with("B is raster-limited"), "{}", f.message);
    }

    /// The flag is relative: two runs of one raster-limited adapter flag neither, and a run
    /// just above the fraction of the other's ratio is not flagged while one just below is.
    #[test]
    fn the_flag_is_relative_to_the_other_runs() {
        let h200 = cal(2e11, 6e12);
        assert_eq!(
            raster_limited(&[("A", Some(&h200)), ("B", Some(&h200))]),
            vec![None, None]
        );
        let base = cal(1e9, 1e9);
        let above = cal(0.26e9, 1e9);
        let below = cal(0.24e9, 1e9);
        assert!(raster_limited(&[("A", Some(&base)), ("B", Some(&above))])[1].is_none());
        assert!(raster_limited(&[("A", Some(&base)), ("B", Some(&below))])[1].is_some());
    }

    /// A run without a calibration (written before it existed) is neither flagged nor counted.
    #[test]
    fn runs_without_a_calibration_are_left_out() {
        let h200 = cal(2e11, 6e12);
        assert_eq!(
            raster_limited(&[("A", None), ("B", Some(&h200))]),
            vec![None, None]
        );
    }

    #[test]
    fn the_text_reads_in_si_units() {
        let t = text(&cal(1.25e9, 2.5e9));
        assert_eq!(
            t,
            "raster 1.25 Gfrag/s · compute 2.50 Ginv/s (raster/compute 0.500) · memory 10.00 \
             GB/s (GPU time, 100 ms)"
        );
    }
}
