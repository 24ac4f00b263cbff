//! Image files: float EXR textures in and out, and sRGB PNG output. Everything in memory is
//! linear; the sRGB transfer function is applied only at the file boundary (DESIGN.md,
//! Colour).

use std::io::Cursor;
use std::path::Path;

use image::{ImageFormat, Rgb32FImage};

use crate::error::{Error, Result};
use crate::util::write_atomic;

/// A linear RGB float image, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgb {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 3]>,
}

impl Rgb {
    /// A black image. Sizes of zero, or over 2^15 per side, are an error.
    pub fn new(width: usize, height: usize) -> Result<Rgb> {
        check_size(width, height)?;
        Ok(Rgb { width, height, pixels: vec![[0.0; 3]; width * height] })
    }

    /// Write as a linear float EXR, atomically.
    pub fn write_exr(&self, path: &Path) -> Result<()> {
        let flat: Vec<f32> = self.pixels.iter().flatten().copied().collect();
        let img = Rgb32FImage::from_raw(self.width as u32, self.height as u32, flat)
            .ok_or_else(|| Error::format(path, "pixel buffer does not match the image size"))?;
        let mut bytes = Cursor::new(Vec::new());
        img.write_to(&mut bytes, ImageFormat::OpenExr).map_err(|e| Error::format(path, e.to_string()))?;
        write_atomic(path, bytes.get_ref())
    }

    /// Write as an 8-bit sRGB PNG (values clamped to [0, 1]), atomically.
    pub fn write_png(&self, path: &Path) -> Result<()> {
        let bytes: Vec<u8> = self.pixels.iter().flatten().map(|&x| encode_srgb8(x)).collect();
        let img = image::RgbImage::from_raw(self.width as u32, self.height as u32, bytes)
            .ok_or_else(|| Error::format(path, "pixel buffer does not match the image size"))?;
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, ImageFormat::Png).map_err(|e| Error::format(path, e.to_string()))?;
        write_atomic(path, out.get_ref())
    }

    /// Read a linear float EXR (RGB; alpha, if any, is ignored).
    pub fn read_exr(path: &Path) -> Result<Rgb> {
        let reader = image::ImageReader::open(path).map_err(|e| Error::io(path, e))?;
        let img = reader
            .with_guessed_format()
            .map_err(|e| Error::io(path, e))?
            .decode()
            .map_err(|e| Error::format(path, format!("cannot decode: {e}")))?
            .into_rgb32f();
        let (width, height) = (img.width() as usize, img.height() as usize);
        let pixels = img.pixels().map(|p| p.0).collect();
        Ok(Rgb { width, height, pixels })
    }
}

/// Largest image side accepted anywhere.
pub const MAX_SIDE: usize = 1 << 15;

/// Reject sizes of zero or absurdly large.
pub fn check_size(width: usize, height: usize) -> Result<()> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(Error::input(format!("image size {width}x{height} is outside 1..={MAX_SIDE} per side")));
    }
    Ok(())
}

/// The sRGB transfer function, linear to encoded, both in [0, 1].
pub fn linear_to_srgb(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB transfer function, encoded to linear, both in [0, 1].
pub fn srgb_to_linear(x: f32) -> f32 {
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value as an 8-bit sRGB code (NaN becomes 0).
pub fn encode_srgb8(x: f32) -> u8 {
    let x = if x.is_nan() { 0.0 } else { x };
    (linear_to_srgb(x) * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_8_bit_code() {
        for code in 0..=255u8 {
            let lin = srgb_to_linear(code as f32 / 255.0);
            assert_eq!(encode_srgb8(lin), code);
        }
        // Reference points of the standard: 0.5 linear is code 188; 0.2140 linear is 128.
        assert_eq!(encode_srgb8(0.5), 188);
        assert!((srgb_to_linear(128.0 / 255.0) - 0.2158605).abs() < 1e-6);
    }

    #[test]
    fn exr_round_trips_float_values_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.exr");
        let img = Rgb { width: 3, height: 2, pixels: vec![[0.0, 1e-6, 123.456], [1.0, 2.0, 3.0], [0.5; 3], [7.0; 3], [1e4, 0.0, 0.25], [0.1; 3]] };
        img.write_exr(&path).unwrap();
        assert_eq!(Rgb::read_exr(&path).unwrap(), img);
    }

    #[test]
    fn corrupt_exr_is_an_error_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.exr");
        std::fs::write(&path, b"v/1\x01 definitely not an exr").unwrap();
        let e = Rgb::read_exr(&path).unwrap_err().to_string();
        assert!(e.contains("bad.exr"), "{e}");
    }
}
