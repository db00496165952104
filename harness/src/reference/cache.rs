//! The reference cache: images keyed by a SHA-256 of everything that determines them (the
//! scene description, its meshes, the frame, the resolution, the settings and the renderer's
//! version). An entry that fails to read back whole is ignored and recomputed, never trusted.
//! Entries are stored losslessly packed ([`super::pack`]).

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::{ReferenceImages, ReferenceStats, Settings, pack};
use crate::image::{Image, io};

/// Bump when the reference's output changes for the same inputs.
pub const REFERENCE_VERSION: u32 = 2;

pub fn key(
    scene: &scenes::Scene,
    frame: u32,
    width: u32,
    height: u32,
    settings: &Settings,
) -> String {
    let mut h = Sha256::new();
    h.update(format!("scatterbench-reference v{REFERENCE_VERSION}\n").as_bytes());
    h.update(
        serde_json::to_string(&scene.desc)
            .unwrap_or_default()
            .as_bytes(),
    );
    for m in &scene.meshes {
        for p in &m.positions {
            for c in p.to_array() {
                h.update(c.to_le_bytes());
            }
        }
        for n in &m.normals {
            for c in n.to_array() {
                h.update(c.to_le_bytes());
            }
        }
        for t in &m.indices {
            for c in t {
                h.update(c.to_le_bytes());
            }
        }
    }
    h.update(format!("\nframe {frame} res {width}x{height} settings {settings:?}").as_bytes());
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

fn entry(dir: &Path, key: &str) -> PathBuf {
    dir.join(key)
}

/// The file holding an entry's images ([`super::pack`]); stats.json beside it.
const IMAGES: &str = "images.sbref";

/// The cached images, or None if absent or unreadable. Entries written before the packed
/// format (four EXRs) are still read.
pub fn load(dir: &Path, key: &str) -> Option<ReferenceImages> {
    let e = entry(dir, key);
    let stats: ReferenceStats =
        serde_json::from_str(&std::fs::read_to_string(e.join("stats.json")).ok()?).ok()?;
    let images = match std::fs::read(e.join(IMAGES)) {
        Ok(bytes) => pack::decode(&bytes).ok()?.images,
        Err(_) => load_exrs(&e)?,
    };
    Some(ReferenceImages { stats, ..images })
}

/// An entry of the first format: inscatter, surface, total and distance (in R) as EXRs.
fn load_exrs(e: &Path) -> Option<ReferenceImages> {
    let inscatter = io::read_exr(&e.join("inscatter.exr")).ok()?;
    let surface = io::read_exr(&e.join("surface.exr")).ok()?;
    let total = io::read_exr(&e.join("total.exr")).ok()?;
    let dist = io::read_exr(&e.join("distance.exr")).ok()?;
    let same = |a: &Image| a.width == total.width && a.height == total.height;
    if !(same(&inscatter) && same(&surface) && same(&dist)) {
        return None;
    }
    Some(ReferenceImages {
        distance: dist.pixels.iter().map(|p| p[0]).collect(),
        inscatter,
        surface,
        total,
        stats: ReferenceStats::default(),
    })
}

/// Stores images under the key, losslessly (written atomically; stats last, so a partial entry
/// has no stats.json and is never loaded).
pub fn store(dir: &Path, key: &str, r: &ReferenceImages) -> Result<(), String> {
    store_rounded(dir, key, r, pack::FULL_MANTISSA)
}

/// [`store`] with every value rounded to `mantissa_bits` ([`pack`]); the bits kept are noted in
/// the entry's stats (`mantissa_bits`).
pub fn store_rounded(
    dir: &Path,
    key: &str,
    r: &ReferenceImages,
    mantissa_bits: u32,
) -> Result<(), String> {
    let e = entry(dir, key);
    std::fs::create_dir_all(&e)
        .map_err(|err| format!("{}: cannot create cache directory: {err}", e.display()))?;
    let _ = std::fs::remove_file(e.join("stats.json"));
    crate::fsutil::write_atomic(&e.join(IMAGES), &pack::encode(r, mantissa_bits)?)?;
    let stats = ReferenceStats {
        mantissa_bits: (mantissa_bits < pack::FULL_MANTISSA).then_some(mantissa_bits),
        ..r.stats.clone()
    };
    crate::fsutil::write_atomic(
        &e.join("stats.json"),
        serde_json::to_string_pretty(&stats)
            .unwrap_or_default()
            .as_bytes(),
    )
}

/// Renders through the cache.
pub fn render_cached(
    dir: Option<&Path>,
    scene: &scenes::Scene,
    frame: u32,
    width: u32,
    height: u32,
    settings: Settings,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(ReferenceImages, bool), String> {
    let k = key(scene, frame, width, height, &settings);
    if let Some(d) = dir
        && let Some(hit) = load(d, &k)
    {
        return Ok((hit, true));
    }
    let r = super::render(scene, frame, width, height, settings, progress)?;
    if let Some(d) = dir {
        store(d, &k, &r)?;
    }
    Ok((r, false))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An entry of the first format (four EXRs, the distance in R) still loads, unchanged.
    #[test]
    fn entries_of_the_exr_format_still_load() {
        let dir = crate::testing::temp_dir("cache-exr-format");
        let e = entry(&dir, "k");
        std::fs::create_dir_all(&e).unwrap();
        let img = |k: f32| Image {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| [k + i as f32, 2.0 * k, 0.5]).collect(),
        };
        for (name, k) in [
            ("inscatter", 1.0),
            ("surface", 2.0),
            ("total", 3.0),
            ("distance", 7.0),
        ] {
            io::write_exr(&e.join(format!("{name}.exr")), &img(k)).unwrap();
        }
        std::fs::write(
            e.join("stats.json"),
            "{\"seconds\": 1.5, \"settings\": null, \"threads\": 2}",
        )
        .unwrap();
        let r = load(&dir, "k").expect("the old entry loads");
        assert_eq!(r.inscatter.pixels, img(1.0).pixels);
        assert_eq!(r.total.pixels, img(3.0).pixels);
        assert_eq!(
            r.distance,
            (0..6).map(|i| 7.0 + i as f32).collect::<Vec<_>>()
        );
        assert_eq!(r.stats.seconds, 1.5);
    }
}
