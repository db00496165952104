//! The in-place image comparison of each scene: which images the page ships, and how.
//!
//! Per scene the viewer holds the reference and, per method, the record the matrix shows
//! (its best configuration under the verdict metric). Each image is shipped inside the page
//! as linear radiance so the page can read out pixel values and draw error maps itself:
//!
//! **Encoding (precision).** Each channel value `v` is stored as the IEEE half float of
//! `v · 2^-k`, where `2^k` is a per-image power-of-two scale chosen so the brightest finite
//! value stays below 2^14 (no overflow at a visible light); a power of two loses nothing, so
//! the read-out has half-float precision: relative error ≤ 2^-11 ≈ 0.049 % for values whose
//! scaled magnitude is ≥ 2^-14, absolute ≤ 2^-25 · 2^k below that; NaN and ±Inf survive.
//! Layout: three planes (R, G, B) of row-major half bits, each delta-coded along its rows
//! (difference from the left neighbour, mod 2^16; smooth images give small deltas), stored as
//! all low bytes then all high bytes, zlib-compressed, base64 in a `<script type=
//! "application/octet-stream">` element; the page inflates it with `DecompressionStream`.

use std::io::Write;

use flate2::Compression;
use flate2::write::ZlibEncoder;
use half::f16;
use harness::image::Image;
use serde::Serialize;

/// Largest scaled magnitude allowed: half floats overflow at 65504; 2^14 keeps a margin.
const MAX_SCALED: f32 = 16384.0;

/// One shipped image.
#[derive(Serialize, Clone)]
pub struct Shipped {
    /// HTML id of the data element.
    pub id: String,
    pub width: u32,
    pub height: u32,
    /// Exponent `k` of the per-image scale 2^k.
    pub scale_log2: i32,
    /// base64 of the zlib stream.
    pub data: String,
}

/// The power-of-two exponent whose scale keeps every finite |value| / 2^k ≤ [`MAX_SCALED`].
pub fn scale_log2(img: &Image) -> i32 {
    let max = img
        .pixels
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold(0.0f32, |m, v| m.max(v.abs()));
    if max <= MAX_SCALED {
        0
    } else {
        (max / MAX_SCALED).log2().ceil() as i32
    }
}

/// The delta-coded, byte-split half-float planes (before compression).
pub fn planes(img: &Image, scale_log2: i32) -> Vec<u8> {
    let (w, h) = (img.width as usize, img.height as usize);
    let n = 3 * w * h;
    let inv = (-scale_log2 as f32).exp2();
    let mut out = vec![0u8; 2 * n];
    let (lo, hi) = out.split_at_mut(n);
    let mut i = 0;
    for c in 0..3 {
        for y in 0..h {
            let mut prev: u16 = 0;
            for x in 0..w {
                let bits = f16::from_f32(img.pixels[y * w + x][c] * inv).to_bits();
                let d = bits.wrapping_sub(prev);
                prev = bits;
                lo[i] = d as u8;
                hi[i] = (d >> 8) as u8;
                i += 1;
            }
        }
    }
    out
}

/// Encodes `img` for the page under the element id `id`.
pub fn ship(id: String, img: &Image) -> Shipped {
    let k = scale_log2(img);
    let mut z = ZlibEncoder::new(Vec::new(), Compression::best());
    // Writing to a Vec cannot fail.
    let _ = z.write_all(&planes(img, k));
    let bytes = z.finish().unwrap_or_default();
    Shipped {
        id,
        width: img.width,
        height: img.height,
        scale_log2: k,
        data: base64(&bytes),
    }
}

/// Standard base64 with padding (RFC 4648), what `atob` reads.
pub fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for (j, shift) in [18, 12, 6, 0].iter().enumerate() {
            if j <= chunk.len() {
                out.push(A[(n >> shift & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (raw, enc) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(raw.as_bytes()), enc);
        }
    }

    /// Decoding the planes the way the page does gives back the half-float values.
    #[test]
    fn planes_round_trip_to_half_precision() {
        let mut img = Image::new(5, 3);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            let v = 0.001 * (i as f32 + 1.0).powi(3);
            *p = [v, v * 0.5, 1e-7 * i as f32];
        }
        img.pixels[7] = [70000.0, f32::NAN, -2.5];
        let k = scale_log2(&img);
        assert_eq!(k, 3, "70000 / 2^3 = 8750 ≤ 2^14 and 2^2 would leave 17500");
        let bytes = planes(&img, k);
        let n = bytes.len() / 2;
        let (w, h) = (5usize, 3usize);
        let mut i = 0;
        for c in 0..3 {
            for y in 0..h {
                let mut acc: u16 = 0;
                for x in 0..w {
                    acc = acc.wrapping_add(bytes[i] as u16 | (bytes[n + i] as u16) << 8);
                    let got = f16::from_bits(acc).to_f32() * (k as f32).exp2();
                    let want = img.pixels[y * w + x][c];
                    if want.is_nan() {
                        assert!(got.is_nan());
                    } else {
                        let tol = want.abs() * 2f32.powi(-11) + 2f32.powi(-25 + k);
                        assert!((got - want).abs() <= tol, "{c} {x} {y}: {got} vs {want}");
                    }
                    i += 1;
                }
            }
        }
    }
}
