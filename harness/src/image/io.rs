//! Reading and writing [`Image`]s: OpenEXR for lossless linear radiance
//! (references, method outputs), PNG for the report.
//!
//! Every writer encodes into memory first and then publishes the file
//! atomically (temporary file in the same directory, `fsync`, `rename`), so
//! an interrupted run or a concurrent reader never sees a truncated image —
//! important because cached references are reused across runs.

use super::Image;
use super::metrics::{ToneMap, quantize_u8};
use std::io::{Cursor, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Writes `img` as an uncropped, single-layer, 32-bit float RGB OpenEXR file
/// (lossless compression), row 0 at the top as EXR expects.
pub fn write_exr(path: &Path, img: &Image) -> Result<(), String> {
    use exr::prelude::{SpecificChannels, Vec2, WritableImage};

    check_len(path, img)?;
    let w = img.width as usize;
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let p = img.pixels[y * w + x];
        (p[0], p[1], p[2])
    });
    let exr_image = exr::prelude::Image::from_channels((w, img.height as usize), channels);
    let mut bytes = Cursor::new(Vec::new());
    exr_image
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| format!("encoding EXR {}: {e}", path.display()))?;
    atomic_write(path, bytes.get_ref())
}

/// Reads the first RGB(A) layer of an OpenEXR file as f32 (half and u32
/// channels are converted; alpha is ignored).
pub fn read_exr(path: &Path) -> Result<Image, String> {
    let exr_image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _channels| Image::new(size.width() as u32, size.height() as u32),
        |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            img.set(pos.x() as u32, pos.y() as u32, [r, g, b]);
        },
    )
    .map_err(|e| format!("reading EXR {}: {e}", path.display()))?;
    Ok(exr_image.layer_data.channel_data.pixels)
}

/// Writes linear `img` as an 8-bit sRGB PNG through `tone` (use the scene's
/// shared tone map so all PNGs of a scene are comparable side by side).
pub fn write_png(path: &Path, img: &Image, tone: &ToneMap) -> Result<(), String> {
    check_len(path, img)?;
    encode_png(path, img.width, img.height, &tone.to_srgb8(img))
}

/// Writes an image that is already in display space (values in `[0, 1]`,
/// sRGB-encoded, e.g. an error map or colour bar) as an 8-bit PNG. Values are
/// clamped; NaN becomes 0.
pub fn write_png_ldr(path: &Path, img: &Image) -> Result<(), String> {
    check_len(path, img)?;
    let data: Vec<u8> = img.pixels.iter().flat_map(|p| p.map(quantize_u8)).collect();
    encode_png(path, img.width, img.height, &data)
}

fn encode_png(path: &Path, width: u32, height: u32, rgb8: &[u8]) -> Result<(), String> {
    use ::image::ImageEncoder;

    let mut bytes = Vec::new();
    ::image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(rgb8, width, height, ::image::ExtendedColorType::Rgb8)
        .map_err(|e| format!("encoding PNG {}: {e}", path.display()))?;
    atomic_write(path, &bytes)
}

/// Guards the writers against a hand-built `Image` whose `pixels` does not
/// match its size, which would otherwise panic deep inside an encoder.
fn check_len(path: &Path, img: &Image) -> Result<(), String> {
    let expected = img.width as usize * img.height as usize;
    if img.pixels.len() != expected || expected == 0 {
        return Err(format!(
            "cannot write {}: image is {}x{} but holds {} pixels",
            path.display(),
            img.width,
            img.height,
            img.pixels.len()
        ));
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically: a uniquely named temporary file next
/// to `path` (same directory, hence same filesystem, so `rename` is atomic),
/// flushed to disk before being renamed over the destination.
fn atomic_write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    // Unique per process and per call, so concurrent writers (rayon tasks or
    // two benchmark processes) never share a temporary file.
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp: PathBuf = {
        let mut name = path
            .file_name()
            .ok_or_else(|| format!("cannot write {}: not a file path", path.display()))?
            .to_os_string();
        name.push(format!(".tmp{}-{n}", std::process::id()));
        path.with_file_name(name)
    };

    let result = (|| -> std::io::Result<()> {
        let mut file = std::fs::File::create(&tmp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        // Best effort: do not leave debris behind; the original error is
        // the one worth reporting.
        let _ = std::fs::remove_file(&tmp);
        format!("writing {}: {e}", path.display())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh, empty directory under the system temp dir, removed on drop.
    struct TempDir(PathBuf);
    impl TempDir {
        fn new(tag: &str) -> Self {
            static N: AtomicU64 = AtomicU64::new(0);
            let dir = std::env::temp_dir().join(format!(
                "scatterbench-image-{tag}-{}-{}",
                std::process::id(),
                N.fetch_add(1, Ordering::Relaxed)
            ));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            Self(dir)
        }
    }
    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn awkward_image() -> Image {
        let specials = [
            0.0,
            -0.0,
            1.0e-40, // subnormal
            f32::MIN_POSITIVE,
            f32::MAX,
            -f32::MAX,
            f32::EPSILON,
            1.0 / 3.0,
            -2.5,
            65504.0 + 1.0 / 64.0, // just past the f16 range: must not be squashed to half
            1.0e30,
            std::f32::consts::PI,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::from_bits(0x7fc0_1234), // NaN with a payload
        ];
        let mut img = Image::new(7, 5);
        let mut k = 0usize;
        for y in 0..5 {
            for x in 0..7 {
                let v = |i: usize| {
                    specials[(k * 3 + i) % specials.len()]
                        * if (x + y) % 4 == 3 { 0.7 } else { 1.0 }
                };
                img.set(x, y, [v(0), v(1), v(2)]);
                k += 1;
            }
        }
        img
    }

    #[test]
    fn exr_round_trip_is_bit_exact() {
        let dir = TempDir::new("exr");
        let path = dir.0.join("awkward.exr");
        let img = awkward_image();
        write_exr(&path, &img).unwrap();
        let back = read_exr(&path).unwrap();
        assert_eq!((back.width, back.height), (7, 5));
        for (i, (a, b)) in img.pixels.iter().zip(&back.pixels).enumerate() {
            for c in 0..3 {
                assert_eq!(
                    a[c].to_bits(),
                    b[c].to_bits(),
                    "pixel {i} channel {c}: wrote {} read {}",
                    a[c],
                    b[c]
                );
            }
        }
        // Only the final file remains: the temporary was renamed away.
        let names: Vec<_> = std::fs::read_dir(&dir.0)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("awkward.exr")]);
    }

    #[test]
    fn png_has_right_size_and_values() {
        let dir = TempDir::new("png");
        let path = dir.0.join("img.png");
        let mut img = Image::new(6, 3);
        img.set(5, 0, [f32::NAN, 0.0, 0.0]);
        img.set(0, 2, [1.0; 3]);
        write_png(&path, &img, &ToneMap::default()).unwrap();
        let back = ::image::open(&path).unwrap().into_rgb8();
        assert_eq!(back.dimensions(), (6, 3));
        assert_eq!(back.get_pixel(0, 0).0, [0, 0, 0]);
        assert_eq!(
            back.get_pixel(5, 0).0,
            [255, 0, 255],
            "NaN must show as magenta"
        );
        // 1.0 → Reinhard 0.5 → sRGB 0.7354 → 187.5… → 188.
        assert_eq!(back.get_pixel(0, 2).0, [188, 188, 188]);

        // Overwriting an existing file works (rename over the destination).
        write_png_ldr(&path, &Image::new(2, 9)).unwrap();
        let back = ::image::open(&path).unwrap().into_rgb8();
        assert_eq!(back.dimensions(), (2, 9));
    }

    #[test]
    fn errors_mention_the_path() {
        let dir = TempDir::new("err");
        let missing = dir.0.join("no-such-dir").join("x.exr");
        let err = write_exr(&missing, &Image::new(2, 2)).unwrap_err();
        assert!(err.contains("no-such-dir"), "{err}");
        let err = read_exr(&missing).unwrap_err();
        assert!(err.contains("x.exr"), "{err}");
        let bad = Image {
            width: 3,
            height: 3,
            pixels: vec![[0.0; 3]; 2],
        };
        let err = write_png(&dir.0.join("bad.png"), &bad, &ToneMap::default()).unwrap_err();
        assert!(err.contains("bad.png") && err.contains("3x3"), "{err}");
    }
}
