//! Linear floating-point RGB images: the common currency between the CPU
//! reference renderer, the GPU methods, the metrics and the report.
//!
//! Images hold *linear radiance* (not display values) so that error metrics
//! can be computed on physically meaningful quantities; display encoding
//! happens only in [`metrics::ToneMap`] and in the PNG writers in [`io`].

pub mod colormap;
pub mod flip;
pub mod headline;
pub mod io;
pub mod lag;
pub mod metrics;

/// Rec.709 / sRGB luminance weights for linear RGB.
pub const REC709_LUMA: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// Luminance of one linear RGB triple (Rec.709 weights).
#[inline]
pub fn luminance_of(rgb: [f32; 3]) -> f32 {
    REC709_LUMA[0] * rgb[0] + REC709_LUMA[1] * rgb[1] + REC709_LUMA[2] * rgb[2]
}

/// A linear-radiance RGB image, row-major, row 0 at the TOP, f32 per channel.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    /// A black image of the given size.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![[0.0; 3]; width as usize * height as usize],
        }
    }

    /// Number of pixels (`width * height`).
    #[inline]
    pub fn len(&self) -> usize {
        self.pixels.len()
    }

    /// True for a 0×N or N×0 image.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.pixels.is_empty()
    }

    #[inline]
    fn index(&self, x: u32, y: u32) -> usize {
        // Explicit check: an out-of-range x would otherwise silently wrap
        // into the next row instead of panicking.
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) out of bounds for {}x{} image",
            self.width,
            self.height
        );
        y as usize * self.width as usize + x as usize
    }

    /// The pixel at column `x`, row `y` (row 0 is the top). Panics if out of bounds.
    #[inline]
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[self.index(x, y)]
    }

    /// Overwrites the pixel at column `x`, row `y`. Panics if out of bounds.
    #[inline]
    pub fn set(&mut self, x: u32, y: u32, v: [f32; 3]) {
        let i = self.index(x, y);
        self.pixels[i] = v;
    }

    /// Per-pixel Rec.709 luminance (0.2126 R + 0.7152 G + 0.0722 B), row-major.
    pub fn luminance(&self) -> Vec<f32> {
        self.pixels.iter().map(|&p| luminance_of(p)).collect()
    }

    /// Builds an image from tightly packed RGBA f32 data (e.g. a GPU
    /// `Rgba32Float` readback with the row padding already removed).
    /// Alpha is dropped; rows are expected top-first, as wgpu returns them.
    ///
    /// Panics if `data` holds fewer than `width * height * 4` floats, because
    /// a short readback is a programming error, not a recoverable condition.
    pub fn from_rgba_f32(width: u32, height: u32, data: &[f32]) -> Self {
        let n = width as usize * height as usize;
        assert!(
            data.len() >= n * 4,
            "from_rgba_f32: {}x{} image needs {} floats, got {}",
            width,
            height,
            n * 4,
            data.len()
        );
        let pixels = data[..n * 4]
            .chunks_exact(4)
            .map(|p| [p[0], p[1], p[2]])
            .collect();
        Self {
            width,
            height,
            pixels,
        }
    }

    /// Mean over all pixels and all three channels, accumulated in f64 so
    /// that large images do not lose precision. Returns 0 for an empty image.
    pub fn mean(&self) -> f64 {
        if self.pixels.is_empty() {
            return 0.0;
        }
        let sum: f64 = self
            .pixels
            .iter()
            .map(|p| p[0] as f64 + p[1] as f64 + p[2] as f64)
            .sum();
        sum / (3.0 * self.pixels.len() as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn get_set_row_major_top_first() {
        let mut img = Image::new(3, 2);
        img.set(2, 1, [1.0, 2.0, 3.0]);
        assert_eq!(img.pixels[5], [1.0, 2.0, 3.0]);
        assert_eq!(img.get(2, 1), [1.0, 2.0, 3.0]);
        assert_eq!(img.get(0, 0), [0.0; 3]);
    }

    #[test]
    #[should_panic(expected = "out of bounds")]
    fn get_out_of_bounds_panics() {
        let img = Image::new(3, 2);
        let _ = img.get(3, 0);
    }

    #[test]
    fn from_rgba_drops_alpha_and_keeps_order() {
        let data: Vec<f32> = (0..2 * 2 * 4).map(|i| i as f32).collect();
        let img = Image::from_rgba_f32(2, 2, &data);
        assert_eq!(img.get(0, 0), [0.0, 1.0, 2.0]);
        assert_eq!(img.get(1, 0), [4.0, 5.0, 6.0]);
        assert_eq!(img.get(0, 1), [8.0, 9.0, 10.0]);
        assert_eq!(img.get(1, 1), [12.0, 13.0, 14.0]);
    }

    #[test]
    fn luminance_and_mean() {
        let mut img = Image::new(2, 1);
        img.set(0, 0, [1.0, 0.0, 0.0]);
        img.set(1, 0, [0.0, 1.0, 1.0]);
        let l = img.luminance();
        assert!((l[0] - 0.2126).abs() < 1e-7);
        assert!((l[1] - (0.7152 + 0.0722)).abs() < 1e-7);
        assert!((img.mean() - 3.0 / 6.0).abs() < 1e-12);
        // White has unit luminance: the weights must sum to 1.
        assert!((luminance_of([1.0; 3]) - 1.0).abs() < 1e-6);
    }
}
