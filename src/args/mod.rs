//! Command-line arguments shared by several commands, declared once, and their checks
//! (ARCHITECTURE §8.3). Every check names the argument, the value and what is allowed. Checks
//! that need only the text are clap value parsers (clap prints them and exits 2); checks that
//! need the registry or a scene file run before any work and fail with [`Usage`], which
//! `main_with` turns into exit 2 as well.

pub mod device;
pub mod isolate;
mod usage;

pub use usage::{Usage, refuse};

use std::collections::BTreeMap;
use std::ops::RangeInclusive;
use std::path::PathBuf;

use clap::Args;
use harness::method::{Method, Params, find, parse_knob, resolve_params};

use crate::registry::Registry;

/// Each side of a resolution, px.
pub const SIDE: RangeInclusive<u32> = 1..=16384;
/// Timed frames per record (a median needs at least one sample).
pub const FRAMES: RangeInclusive<u32> = 1..=100_000;
/// Warm-up frames per record.
pub const WARMUP: RangeInclusive<u32> = 0..=100_000;
/// Seconds (time budgets, frame-time caps): one day at most.
pub const SECONDS: RangeInclusive<f64> = 0.0..=86_400.0;

/// Image size: `N` (square) or `WxH`, each side within [`SIDE`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Res {
    pub width: u32,
    pub height: u32,
}

impl Res {
    pub fn is_square(self) -> bool {
        self.width == self.height
    }
}

/// Parses `N` or `WxH` (a clap value parser).
pub fn parse_res(s: &str) -> Result<Res, String> {
    let side = |t: &str| -> Result<u32, String> {
        let v: u32 = t
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not N or WxH (e.g. 512 or 640x360)"))?;
        if !SIDE.contains(&v) {
            return Err(format!(
                "{v} is outside {}..={} px",
                SIDE.start(),
                SIDE.end()
            ));
        }
        Ok(v)
    };
    match s.split_once(['x', 'X']) {
        Some((w, h)) => Ok(Res {
            width: side(w)?,
            height: side(h)?,
        }),
        None => {
            let n = side(s)?;
            Ok(Res {
                width: n,
                height: n,
            })
        }
    }
}

/// A clap value parser for a whole number within `range`.
pub fn int_in<T>(range: RangeInclusive<T>) -> impl Fn(&str) -> Result<T, String> + Clone
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display + Copy + Send + Sync + 'static,
{
    move |s: &str| {
        let v: T = s
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not a whole number"))?;
        if !range.contains(&v) {
            return Err(format!(
                "{v} is outside {}..={}",
                range.start(),
                range.end()
            ));
        }
        Ok(v)
    }
}

pub fn parse_frames(s: &str) -> Result<u32, String> {
    int_in(FRAMES)(s)
}

pub fn parse_warmup(s: &str) -> Result<u32, String> {
    int_in(WARMUP)(s)
}

/// A finite number of seconds within [`SECONDS`].
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a number of seconds"))?;
    if !v.is_finite() || !SECONDS.contains(&v) {
        return Err(format!(
            "{v} is outside {}..={} s",
            SECONDS.start(),
            SECONDS.end()
        ));
    }
    Ok(v)
}

/// Parses "1k,4k,1M,2500" into counts, each within 1..=100M; "none" is the empty list.
pub fn parse_counts(s: &str) -> Result<Vec<usize>, String> {
    if s.trim() == "none" {
        return Ok(Vec::new());
    }
    s.split(',')
        .map(|t| {
            let t = t.trim();
            let (num, mult) = match t.chars().last() {
                Some('k' | 'K') => (&t[..t.len() - 1], 1_000.0),
                Some('m' | 'M') => (&t[..t.len() - 1], 1_000_000.0),
                _ => (t, 1.0),
            };
            let v: f64 = num
                .parse()
                .map_err(|_| format!("'{t}' is not a count (e.g. 4k, 1M, 2500)"))?;
            let n = v * mult;
            if !(1.0..=1e8).contains(&n) {
                return Err(format!("'{t}' is outside 1..=100M"));
            }
            Ok(n.round() as usize)
        })
        .collect()
}

/// Square sizes "128,256" (each within [`SIDE`]); "none" is the empty list.
pub fn parse_sizes(s: &str) -> Result<Vec<u32>, String> {
    if s.trim() == "none" {
        return Ok(Vec::new());
    }
    s.split(',')
        .map(|t| {
            let r = parse_res(t)?;
            if !r.is_square() {
                return Err(format!("'{t}': the pixel sweep takes square sizes (N)"));
            }
            Ok(r.width)
        })
        .collect()
}

/// `--res`: the image size. Each command sets its own default (`mut_arg` in `lib.rs`).
#[derive(Args, Clone, Debug)]
pub struct Size {
    /// Image size: N (square) or WxH, each side 1..=16384.
    #[arg(long, default_value = "512", value_parser = parse_res)]
    pub res: Res,
}

/// `--frames` and `--warmup` of a command that times records (defaults: `run`'s; others set
/// theirs with `mut_arg` in `lib.rs`).
#[derive(Args, Clone, Debug)]
pub struct Frames {
    /// Timed frames per record, 1..=100000.
    #[arg(long, default_value = "10", value_parser = parse_frames)]
    pub frames: u32,
    /// Warm-up frames per record, 0..=100000.
    #[arg(long, default_value = "3", value_parser = parse_warmup)]
    pub warmup: u32,
}

/// `--methods`: which registered methods.
#[derive(Args, Clone, Debug)]
pub struct MethodList {
    /// Comma-separated method ids, or "all".
    #[arg(long, default_value = "all")]
    pub methods: String,
}

/// `--resume`.
#[derive(Args, Clone, Debug)]
pub struct Resume {
    /// Continue the run in --out, skipping finished records.
    #[arg(long)]
    pub resume: bool,
}

/// `--paired-floor` of a command that times records (ARCHITECTURE §4.5).
#[derive(Args, Clone, Debug)]
pub struct PairedFloor {
    /// Time the floor (no-scatter at the record's shadow-map settings) within every record,
    /// one floor frame before each of the record's frames, and take each record's floor ratio
    /// from that pair (ARCHITECTURE §4.5): ratios that do not depend on where in the run a
    /// record was measured (a GPU's drifting clock, a shared machine's load). no-scatter must
    /// be among the methods run.
    #[arg(long)]
    pub paired_floor: bool,
}

impl PairedFloor {
    /// The floor method's id for `RecordSettings::paired_floor` where the flag is given.
    pub fn method(&self) -> Option<String> {
        self.paired_floor
            .then(|| report::analysis::FLOOR_METHOD.to_string())
    }
}

/// Where a command writes its run and finds the reference cache.
#[derive(Args, Clone, Debug)]
pub struct Output {
    /// Output directory (default results/<run-id>, prefixed by the command for reproduce,
    /// scaling and stress).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Reference cache directory (shared by runs; ARCHITECTURE §9.1).
    #[arg(long, default_value = "results/cache")]
    pub cache: PathBuf,
}

impl Output {
    /// `--out`, or `results/<default_name>`.
    pub fn dir(&self, default_name: &str) -> PathBuf {
        self.out
            .clone()
            .unwrap_or_else(|| PathBuf::from("results").join(default_name))
    }
}

/// Refuses `--resume` on a directory without a results.json, and a fresh run into one that
/// already holds one is left to the caller.
pub fn check_resume(resume: bool, out: &std::path::Path) -> anyhow::Result<()> {
    if resume && !out.join("results.json").exists() {
        return refuse(format!(
            "--resume: {} has no results.json to continue",
            out.display()
        ));
    }
    Ok(())
}

/// Refuses an output directory that already holds a results.json (commands that cannot
/// continue a run).
pub fn check_fresh(out: &std::path::Path) -> anyhow::Result<()> {
    if out.join("results.json").exists() {
        return refuse(format!(
            "--out: {} already holds a results.json; pass a new directory",
            out.display()
        ));
    }
    Ok(())
}

/// The ids of the registry, for messages.
fn method_ids(registry: Registry) -> String {
    registry
        .iter()
        .map(|e| e.id())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Entries of `registry` named by `--methods` (comma-separated, or "all"); unknown ids are
/// refused with the valid ones.
pub fn pick_methods(spec: &str, registry: Registry) -> anyhow::Result<Vec<&'static dyn Method>> {
    if spec == "all" {
        return Ok(registry.to_vec());
    }
    spec.split(',')
        .map(|id| match find(registry, id.trim()) {
            Some(e) => Ok(e),
            None => refuse(format!(
                "--methods: unknown method '{id}'; valid methods are {}, all",
                method_ids(registry)
            )),
        })
        .collect()
}

/// Scenes named by `--scenes` (library names, variants, or .json paths, comma-separated, or
/// "all" for the library); unknown names and invalid files are refused.
pub fn pick_scenes(spec: &str) -> anyhow::Result<Vec<scenes::Scene>> {
    let names: Vec<String> = if spec == "all" {
        scenes::library::names()
            .into_iter()
            .map(String::from)
            .collect()
    } else {
        spec.split(',').map(|s| s.trim().to_string()).collect()
    };
    names.iter().map(|n| scene(n)).collect()
}

/// One scene by name, variant or path (ARCHITECTURE §8.2); refused with [`Usage`].
pub fn scene(name: &str) -> anyhow::Result<scenes::Scene> {
    scenes::library::resolve(name).or_else(refuse)
}

/// `--param METHOD.KNOB=VALUE` items → per-method overrides, each checked against the
/// method's knobs (name, type, choices) and refused with [`Usage`]. METHOD is looked up in
/// `registry` and must be one of `chosen`.
pub fn parse_overrides(
    items: &[String],
    chosen: &[&dyn Method],
    registry: Registry,
) -> anyhow::Result<BTreeMap<String, Params>> {
    let mut out: BTreeMap<String, Params> = BTreeMap::new();
    for item in items {
        let bad = |why: String| refuse(format!("--param '{item}': {why}"));
        let Some((method, knob, value)) = item
            .split_once('=')
            .and_then(|(lhs, v)| lhs.split_once('.').map(|(m, k)| (m, k, v)))
        else {
            return bad("expected METHOD.KNOB=VALUE".into());
        };
        let Some(entry) = find(registry, method) else {
            return bad(format!(
                "unknown method '{method}'; valid methods are {}",
                method_ids(registry)
            ));
        };
        if !chosen.iter().any(|e| e.id() == entry.id()) {
            return bad(format!("method '{method}' is not in --methods"));
        }
        // Unknown knob, wrong type or out of range: the message names the knob, the value
        // and what is allowed.
        let v = match parse_knob(entry, knob, value) {
            Ok(v) => v,
            Err(e) => return bad(e.to_string()),
        };
        out.entry(entry.id().to_string())
            .or_default()
            .insert(knob.to_string(), v);
    }
    // Every method's full parameter set must resolve (names, types, choices, ranges) before
    // any work starts.
    for (id, overrides) in &out {
        let entry = find(registry, id).expect("found above");
        if let Err(e) = resolve_params(entry, overrides) {
            return refuse(format!("--param {id}: {e}"));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolutions_parse_and_refuse_out_of_range_sides() {
        assert_eq!(
            parse_res("640x360"),
            Ok(Res {
                width: 640,
                height: 360
            })
        );
        assert_eq!(parse_res("16").map(|r| (r.width, r.height)), Ok((16, 16)));
        assert!(parse_res("0").unwrap_err().contains("1..=16384"));
        assert!(parse_res("16385x2").unwrap_err().contains("16385"));
        assert!(parse_res("abc").is_err());
        assert!(parse_res("").is_err());
    }

    #[test]
    fn counts_parse_with_suffixes_and_refuse_junk() {
        assert_eq!(
            parse_counts("1k, 4K,2500,1M").unwrap(),
            vec![1000, 4000, 2500, 1_000_000]
        );
        assert_eq!(parse_counts("1.5k").unwrap(), vec![1500]);
        assert!(parse_counts("none").unwrap().is_empty());
        assert!(parse_counts("abc").is_err());
        assert!(parse_counts("0").is_err());
        assert!(parse_counts("").is_err());
    }

    #[test]
    fn numbers_outside_their_range_are_refused() {
        assert!(parse_frames("0").unwrap_err().contains("1..=100000"));
        assert_eq!(parse_frames("1"), Ok(1));
        assert_eq!(parse_warmup("0"), Ok(0));
        assert!(parse_warmup("-1").is_err());
        assert!(parse_seconds("-0.5").unwrap_err().contains("0..=86400"));
        assert!(parse_seconds("NaN").is_err());
        assert!(parse_seconds("inf").is_err());
        assert_eq!(parse_seconds("0"), Ok(0.0));
        assert!(parse_sizes("128,64x32").unwrap_err().contains("square"));
        assert_eq!(parse_sizes("32,48"), Ok(vec![32, 48]));
    }
}
