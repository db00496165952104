//! The reference cache's storage format: every image of a [`ReferenceImages`] in one
//! losslessly compressed file, about 8× smaller than four uncompressed f32 EXRs, so that the
//! cache of the default run at 256² and 1024² fits a bundle that travels (issue 30).
//!
//! Lossless to the bit: a loaded reference scores exactly like the freshly rendered one.
//! Reference images are smooth almost everywhere (quadrature, no Monte Carlo noise), so each
//! plane's f32 bit patterns are predicted from their neighbours (left + up − up-left, the
//! PNG/LOCO-I planar predictor, in wrapping u32 arithmetic, so any bit pattern round-trips),
//! the residuals are zigzag-coded (small either way → small unsigned), split into byte planes
//! (the high bytes of smooth data are nearly constant), and zstd-compressed. `total` is not
//! predicted from its neighbours but from `inscatter + surface` of the same pixel (in f32, rounded
//! like every stored value): its zigzag-coded bit difference from that sum is zero wherever the
//! medium has no ambient term and the reference summed in the same order, and a few units where
//! it did not. Measured on the library at 256²: 13 % of the EXRs' size (version 2).
//!
//! Optionally ([`encode`]'s `mantissa_bits` below 23) every value is first rounded to that many
//! mantissa bits: the bundle (`scripts/bundle.sh`) keeps 20, a relative rounding error of at most
//! 2⁻²¹ ≈ 4.8e-7, under half the reference's own quadrature tolerance (1e-6), whose noise fills
//! the bits dropped; it saves about a quarter of the size. Decoding returns the rounded values
//! bit for bit, and says how many bits were kept ([`Packed::mantissa_bits`]).
//!
//! File layout: `MAGIC` (its last byte the version), then width, height, plane count and (from
//! version 2) mantissa bits kept as little-endian u32, then the zstd frame. Planes: inscatter
//! R, G, B; surface R, G, B; total against (inscatter + surface) R, G, B; distance.
//!
//! Versions 1 and 2 (still read) stored `total` as the XOR with the unrounded sum, predicted from
//! its neighbours like the other planes. Under rounding that sum keeps bits the rounded `total`
//! lacks, so the XOR was noise in every pixel: a third of a 20-bit 1024² entry. Version 3 stores
//! the difference from the rounded sum, unpredicted: a 20-bit 1024² entry is about half the size.

use crate::image::Image;

use super::{ReferenceImages, ReferenceStats};

/// Version 1 (lossless, 20-byte header) and 2 (adds the mantissa bits) are still read; version 3
/// stores `total` against the rounded sum (module doc).
const MAGIC_V1: &[u8; 8] = b"SBREF\0\0\x01";
const MAGIC_V2: &[u8; 8] = b"SBREF\0\0\x02";
const MAGIC: &[u8; 8] = b"SBREF\0\0\x03";
const HEADER: usize = 24;
/// An f32's mantissa bits: keeping all of them is lossless.
pub const FULL_MANTISSA: u32 = 23;
const PLANES: usize = 10;
/// zstd level: the best ratio short of the "ultra" levels (which change little on these
/// residuals, measured on the library). A 1024² entry compresses in a few seconds, against
/// minutes to render it.
const LEVEL: i32 = 19;

/// Decoded images and how many mantissa bits they kept.
pub struct Packed {
    pub images: ReferenceImages,
    /// [`FULL_MANTISSA`] when the file is lossless.
    pub mantissa_bits: u32,
}

/// The images as one compressed byte string (see the module doc), each value rounded to
/// `mantissa_bits` (1..=23; 23 is lossless).
pub fn encode(r: &ReferenceImages, mantissa_bits: u32) -> Result<Vec<u8>, String> {
    if !(1..=FULL_MANTISSA).contains(&mantissa_bits) {
        return Err(format!(
            "mantissa bits {mantissa_bits} outside 1..={FULL_MANTISSA}"
        ));
    }
    let (w, h) = (r.total.width, r.total.height);
    let n = w as usize * h as usize;
    if [&r.inscatter, &r.surface]
        .iter()
        .any(|i| i.pixels.len() != n)
        || r.distance.len() != n
    {
        return Err(format!(
            "reference images of different sizes (total {w}x{h})"
        ));
    }
    let rounded;
    let r = if mantissa_bits < FULL_MANTISSA {
        rounded = round_images(r, mantissa_bits);
        &rounded
    } else {
        r
    };
    let mut residuals = Vec::with_capacity(PLANES * n);
    for img in [&r.inscatter, &r.surface] {
        for c in 0..3 {
            let plane: Vec<u32> = img.pixels.iter().map(|p| p[c].to_bits()).collect();
            residuals.extend(predict(&plane, w as usize));
        }
    }
    residuals.extend(total_residuals(r, mantissa_bits));
    let distance: Vec<u32> = r.distance.iter().map(|d| d.to_bits()).collect();
    residuals.extend(predict(&distance, w as usize));
    let packed = zstd::bulk::compress(&byte_planes(&residuals), LEVEL)
        .map_err(|e| format!("compressing the reference: {e}"))?;
    let mut out = Vec::with_capacity(packed.len() + HEADER);
    out.extend_from_slice(MAGIC);
    for v in [w, h, PLANES as u32, mantissa_bits] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&packed);
    Ok(out)
}

/// The images back, bit for bit as encoded; an error says what is wrong with the bytes.
pub fn decode(bytes: &[u8]) -> Result<Packed, String> {
    let version = match bytes.get(..8) {
        Some(m) if m == MAGIC => 3,
        Some(m) if m == MAGIC_V2 => 2,
        Some(m) if m == MAGIC_V1 => 1,
        _ => return Err("not a scatterbench reference (bad magic or too short)".into()),
    };
    let header_len = if version == 1 { 20 } else { HEADER };
    let header = bytes.get(..header_len).ok_or("header cut short")?;
    let word = |k: usize| u32::from_le_bytes(header[8 + 4 * k..12 + 4 * k].try_into().unwrap());
    let (w, h, planes) = (word(0), word(1), word(2) as usize);
    let mantissa_bits = if version >= 2 { word(3) } else { FULL_MANTISSA };
    if planes != PLANES {
        return Err(format!("{planes} planes, expected {PLANES}"));
    }
    if !(1..=FULL_MANTISSA).contains(&mantissa_bits) {
        return Err(format!(
            "mantissa bits {mantissa_bits} outside 1..={FULL_MANTISSA}"
        ));
    }
    let n = w as usize * h as usize;
    let len = PLANES * n * 4;
    let raw = zstd::bulk::decompress(&bytes[header_len..], len)
        .map_err(|e| format!("decompressing the reference: {e}"))?;
    if raw.len() != len {
        return Err(format!("{} bytes of image data, expected {len}", raw.len()));
    }
    let residuals = from_byte_planes(&raw);
    // Version 3 stores the total planes (6..9) unpredicted (module doc).
    let plane = |k: usize| {
        let stored = &residuals[k * n..(k + 1) * n];
        if version >= 3 && (6..9).contains(&k) {
            stored.iter().map(|&r| unzigzag(r)).collect()
        } else {
            unpredict(stored, w as usize)
        }
    };
    let rgb = |k: usize| {
        let (r, g, b) = (plane(k), plane(k + 1), plane(k + 2));
        let pixels = (0..n)
            .map(|i| [r[i], g[i], b[i]].map(f32::from_bits))
            .collect();
        Image {
            width: w,
            height: h,
            pixels,
        }
    };
    let mut images = ReferenceImages {
        inscatter: rgb(0),
        surface: rgb(3),
        total: rgb(6),
        distance: plane(9).into_iter().map(f32::from_bits).collect(),
        stats: ReferenceStats::default(),
    };
    for i in 0..n {
        for c in 0..3 {
            let stored = images.total.pixels[i][c].to_bits();
            images.total.pixels[i][c] = f32::from_bits(if version < 3 {
                stored ^ sum_bits(&images, i, c, FULL_MANTISSA)
            } else {
                stored.wrapping_add(sum_bits(&images, i, c, mantissa_bits))
            });
        }
    }
    Ok(Packed {
        images,
        mantissa_bits,
    })
}

/// Every value of every image rounded to `bits` mantissa bits.
fn round_images(r: &ReferenceImages, bits: u32) -> ReferenceImages {
    let image = |i: &Image| Image {
        width: i.width,
        height: i.height,
        pixels: i.pixels.iter().map(|p| p.map(|v| round(v, bits))).collect(),
    };
    ReferenceImages {
        inscatter: image(&r.inscatter),
        surface: image(&r.surface),
        total: image(&r.total),
        distance: r.distance.iter().map(|&d| round(d, bits)).collect(),
        stats: r.stats.clone(),
    }
}

/// `v` rounded to the nearest value with `bits` mantissa bits (ties to even). Non-finite values
/// and those that would round past the largest finite f32 are kept as they are.
pub fn round(v: f32, bits: u32) -> f32 {
    let drop = FULL_MANTISSA - bits;
    if drop == 0 || !v.is_finite() {
        return v;
    }
    let b = v.to_bits();
    let half = (1u32 << (drop - 1)) - 1 + ((b >> drop) & 1);
    let r = f32::from_bits(((b + half) >> drop) << drop);
    if r.is_finite() { r } else { v }
}

/// The bits of `inscatter + surface` at pixel `i`, channel `c`, rounded to `bits` mantissa bits
/// like the stored `total`: what `total` is predicted by.
fn sum_bits(r: &ReferenceImages, i: usize, c: usize, bits: u32) -> u32 {
    round(r.inscatter.pixels[i][c] + r.surface.pixels[i][c], bits).to_bits()
}

/// `total`'s three planes as stored (version 3): each value's zigzag-coded bit difference from
/// the rounded `inscatter + surface` of its pixel. `r` is already rounded to `bits`.
fn total_residuals(r: &ReferenceImages, bits: u32) -> Vec<u32> {
    let n = r.total.pixels.len();
    (0..3)
        .flat_map(|c| {
            (0..n).map(move |i| {
                zigzag(
                    r.total.pixels[i][c]
                        .to_bits()
                        .wrapping_sub(sum_bits(r, i, c, bits)),
                )
            })
        })
        .collect()
}

/// The planar predictor's zigzag-coded residuals of a row-major plane of width `w`.
fn predict(plane: &[u32], w: usize) -> Vec<u32> {
    (0..plane.len())
        .map(|i| zigzag(plane[i].wrapping_sub(prediction(plane, i, w))))
        .collect()
}

/// Inverts [`predict`]: each value from its residual and the already decoded neighbours.
fn unpredict(residuals: &[u32], w: usize) -> Vec<u32> {
    let mut plane = vec![0u32; residuals.len()];
    for i in 0..residuals.len() {
        plane[i] = unzigzag(residuals[i]).wrapping_add(prediction(&plane, i, w));
    }
    plane
}

/// left + up − up-left where all three exist, else the one neighbour that does (or 0).
fn prediction(plane: &[u32], i: usize, w: usize) -> u32 {
    let (x, y) = (i % w, i / w);
    match (x > 0, y > 0) {
        (true, true) => plane[i - 1]
            .wrapping_add(plane[i - w])
            .wrapping_sub(plane[i - w - 1]),
        (true, false) => plane[i - 1],
        (false, true) => plane[i - w],
        (false, false) => 0,
    }
}

fn zigzag(v: u32) -> u32 {
    let s = v as i32;
    ((s << 1) ^ (s >> 31)) as u32
}

fn unzigzag(v: u32) -> u32 {
    (v >> 1) ^ (v & 1).wrapping_neg()
}

/// Byte k of every word, for k = 0..4 in turn.
fn byte_planes(words: &[u32]) -> Vec<u8> {
    (0..4)
        .flat_map(|k| words.iter().map(move |w| w.to_le_bytes()[k]))
        .collect()
}

fn from_byte_planes(bytes: &[u8]) -> Vec<u32> {
    let n = bytes.len() / 4;
    (0..n)
        .map(|i| u32::from_le_bytes([bytes[i], bytes[n + i], bytes[2 * n + i], bytes[3 * n + i]]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator, so the test needs no dependency.
    fn xorshift(state: &mut u64) -> u64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        *state
    }

    fn images(w: u32, h: u32, value: &mut dyn FnMut(u32, u32, usize) -> f32) -> ReferenceImages {
        let img = |value: &mut dyn FnMut(u32, u32, usize) -> f32, k: usize| Image {
            width: w,
            height: h,
            pixels: (0..w * h)
                .map(|i| [0, 1, 2].map(|c| value(i % w, i / w, 3 * k + c)))
                .collect(),
        };
        let (inscatter, surface) = (img(value, 0), img(value, 1));
        let mut total = img(value, 2);
        // Like the reference: mostly inscatter + surface, an ambient term in one corner.
        for (i, p) in total.pixels.iter_mut().enumerate() {
            if i % (w as usize) >= 3 {
                *p = [0, 1, 2].map(|c| inscatter.pixels[i][c] + surface.pixels[i][c]);
            }
        }
        ReferenceImages {
            distance: (0..w * h).map(|i| value(i % w, i / w, 9)).collect(),
            inscatter,
            surface,
            total,
            stats: ReferenceStats::default(),
        }
    }

    fn same_bits(a: &ReferenceImages, b: &ReferenceImages) -> bool {
        let bits =
            |i: &Image| -> Vec<u32> { i.pixels.iter().flatten().map(|v| v.to_bits()).collect() };
        bits(&a.inscatter) == bits(&b.inscatter)
            && bits(&a.surface) == bits(&b.surface)
            && bits(&a.total) == bits(&b.total)
            && a.distance.iter().map(|d| d.to_bits()).collect::<Vec<_>>()
                == b.distance.iter().map(|d| d.to_bits()).collect::<Vec<_>>()
            && (a.total.width, a.total.height) == (b.total.width, b.total.height)
    }

    #[test]
    fn any_bit_pattern_round_trips_exactly() {
        // NaNs, infinities, negative zeros, denormals: every u32 is a valid input.
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let r = images(37, 23, &mut |_, _, _| {
            f32::from_bits(xorshift(&mut s) as u32)
        });
        let back = decode(&encode(&r, FULL_MANTISSA).unwrap()).unwrap();
        assert!(same_bits(&r, &back.images));
        assert_eq!(back.mantissa_bits, FULL_MANTISSA);
    }

    #[test]
    fn smooth_images_round_trip_and_shrink() {
        let r = images(128, 96, &mut |x, y, k| {
            let (x, y) = (x as f32 / 128.0, y as f32 / 96.0);
            (1.0 + k as f32) * (-(x * x + 0.5 * y)).exp() / (0.1 + x + y)
        });
        let packed = encode(&r, FULL_MANTISSA).unwrap();
        assert!(same_bits(&r, &decode(&packed).unwrap().images));
        let raw = 128 * 96 * 4 * PLANES;
        assert!(
            packed.len() * 3 < raw,
            "{} bytes for {raw} raw: the predictor should leave little to store",
            packed.len()
        );
    }

    #[test]
    fn damaged_bytes_are_refused_not_misread() {
        let r = images(16, 16, &mut |x, y, k| (x + y) as f32 + k as f32);
        let packed = encode(&r, FULL_MANTISSA).unwrap();
        assert!(decode(&packed[..packed.len() - 5]).is_err(), "truncated");
        assert!(decode(&packed[..10]).is_err(), "header only");
        let mut wrong_size = packed.clone();
        wrong_size[8] ^= 1; // width 16 → 17: the data no longer fits
        assert!(decode(&wrong_size).is_err(), "size mismatch");
        let mut not_ours = packed;
        not_ours[0] = b'X';
        assert!(decode(&not_ours).is_err(), "magic");
    }

    #[test]
    fn rounding_keeps_its_bound_and_decodes_to_the_rounded_values() {
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let r = images(31, 17, &mut |_, _, _| {
            // Positive values over 20 decades, like radiance.
            let u = (xorshift(&mut s) >> 11) as f64 / (1u64 << 53) as f64;
            10f64.powf(-10.0 + 20.0 * u) as f32
        });
        let bits = 20;
        let back = decode(&encode(&r, bits).unwrap()).unwrap();
        assert_eq!(back.mantissa_bits, bits);
        let bound = 2f64.powi(-(bits as i32) - 1);
        let pairs = r.inscatter.pixels.iter().zip(&back.images.inscatter.pixels);
        for (a, b) in pairs.flat_map(|(a, b)| a.iter().zip(b)) {
            let rel = ((*a as f64) - (*b as f64)).abs() / (*a as f64);
            assert!(rel <= bound, "{a} → {b}: {rel:e} > {bound:e}");
            assert_eq!(b.to_bits() & ((1 << (FULL_MANTISSA - bits)) - 1), 0, "{b}");
        }
        // total is stored against the rounded inscatter + surface, so it decodes exactly to
        // its own rounded value.
        let total = |i: usize| round(r.total.pixels[i][1], bits);
        assert_eq!(back.images.total.pixels[5][1], total(5));
        assert_eq!(
            round(1.0 + 3.0 * f32::EPSILON, 21),
            1.0 + 4.0 * f32::EPSILON,
            "ties to even"
        );
        assert_eq!(round(f32::MAX, 20), f32::MAX, "never rounds to infinity");
    }

    #[test]
    fn a_rounded_total_costs_almost_nothing_next_to_its_rounded_sum() {
        // Rounding inscatter, surface and total separately leaves the rounded sum within a unit
        // or two in the last kept place of the rounded total (|a + b − (ã + b̃)| ≤ ½ ulp(a) +
        // ½ ulp(b) for positive a, b): the stored residuals are 0 or tiny, except where the
        // ambient term makes total differ from the sum (the images' first 3 columns).
        let (w, h, bits) = (64u32, 48u32, 20);
        let r = images(w, h, &mut |x, y, k| {
            let (x, y) = (x as f32 / 64.0, y as f32 / 48.0);
            (1.0 + k as f32) * (-(x * x + 0.7 * y)).exp() / (0.13 + x + y)
        });
        let residuals = total_residuals(&round_images(&r, bits), bits);
        let no_ambient = |i: usize| i % (w * h) as usize % w as usize >= 3;
        let kept: Vec<u32> = (0..residuals.len())
            .filter(|&i| no_ambient(i))
            .map(|i| residuals[i])
            .collect();
        // Two units of the last kept bit, zigzag-coded.
        let two_units = 4 << (FULL_MANTISSA - bits);
        assert!(
            kept.iter().all(|&z| z <= two_units),
            "{:?}",
            kept.iter().max()
        );
        let zeros = kept.iter().filter(|&&z| z == 0).count();
        assert!(zeros * 2 > kept.len(), "{zeros} of {} exact", kept.len());
        let back = decode(&encode(&r, bits).unwrap()).unwrap();
        assert!(same_bits(&round_images(&r, bits), &back.images));
    }

    #[test]
    fn version_2_files_still_decode() {
        // Version 2 stored total as the XOR with the unrounded sum, predicted like the others.
        let r = images(19, 11, &mut |x, y, k| {
            0.5 + (x * 7 + y * 3 + k as u32) as f32 / 97.0
        });
        let n = 19 * 11;
        let mut planes: Vec<Vec<u32>> = Vec::new();
        for img in [&r.inscatter, &r.surface] {
            for c in 0..3 {
                planes.push(img.pixels.iter().map(|p| p[c].to_bits()).collect());
            }
        }
        for c in 0..3 {
            let xor = |i: usize| {
                let sum = r.inscatter.pixels[i][c] + r.surface.pixels[i][c];
                r.total.pixels[i][c].to_bits() ^ sum.to_bits()
            };
            planes.push((0..n).map(xor).collect());
        }
        planes.push(r.distance.iter().map(|d| d.to_bits()).collect());
        let residuals: Vec<u32> = planes.iter().flat_map(|p| predict(p, 19)).collect();
        let mut bytes = MAGIC_V2.to_vec();
        for v in [19u32, 11, PLANES as u32, FULL_MANTISSA] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes.extend(zstd::bulk::compress(&byte_planes(&residuals), 3).unwrap());
        assert!(same_bits(&r, &decode(&bytes).unwrap().images));
    }

    #[test]
    fn zigzag_inverts_on_extremes() {
        for v in [0, 1, 2, u32::MAX, u32::MAX - 1, 1 << 31, (1 << 31) - 1] {
            assert_eq!(unzigzag(zigzag(v)), v);
        }
    }
}
