//! Image files: float EXR textures in and out, and sRGB PNG output. Everything in memory is
//! linear; the sRGB transfer function is applied only at the file boundary (DESIGN.md,
//! Colour).

pub mod env;
mod env_read;
mod painting;
pub mod palette;
mod rows;
pub mod text;
pub mod tone;

pub use painting::Painting;
pub use rows::Shrink;

use std::io::Cursor;
use std::path::Path;

use image::{ImageFormat, Rgb32FImage};

use crate::error::{Error, Result};
use crate::commit::write_atomic;

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

    /// Read a linear float EXR (RGB; alpha, if any, is ignored). The file is read under the
    /// file-access policy ([`crate::fsio`]) and its size checked from the header before it
    /// is decoded ([`decode_limited`]).
    pub fn read_exr(path: &Path) -> Result<Rgb> {
        let bytes = crate::fsio::read_regular(path, crate::fsio::MAX_IMAGE_BYTES)?;
        let format = image::guess_format(&bytes).map_err(|_| Error::format(path, "cannot decode: not an image"))?;
        let img = decode_limited(path, &bytes, format)?.into_rgb32f();
        let (width, height) = (img.width() as usize, img.height() as usize);
        let pixels = img.pixels().map(|p| p.0).collect();
        Ok(Rgb { width, height, pixels })
    }
}

/// Largest image side accepted anywhere.
pub const MAX_SIDE: usize = 1 << 15;

/// Most pixels of an image file that is decoded: the renderer's limit
/// (`gl::Limits::MAX_PIXELS`, 4096 × 4096), since every image read is drawn or sampled
/// against a rendered grid. Checked from the header, before any pixel is decoded, so a small
/// file claiming a huge image costs nothing.
pub const MAX_PIXELS: usize = 1 << 24;

/// Largest side of an image file that is decoded (the renderer's largest target side).
pub const MAX_DECODE_SIDE: usize = 1 << 14;

/// Most bytes the decoder may allocate for one image: a 4096² RGBA float image (256 MiB)
/// and its conversion.
const MAX_DECODE_ALLOC: u64 = 600 << 20;

/// The width and height an image file's header declares, read under the file-access policy
/// without decoding a pixel: a material's textures are sized this way before any is decoded.
pub fn header_size(path: &Path) -> Result<(usize, usize)> {
    let (file, _) = crate::fsio::open_regular(path, crate::fsio::MAX_IMAGE_BYTES)?;
    let reader = image::ImageReader::new(std::io::BufReader::new(file)).with_guessed_format().map_err(|e| Error::io(path, e))?;
    let format = reader.format().ok_or_else(|| Error::format(path, "cannot decode: not an image"))?;
    let (w, h) = reader.into_dimensions().map_err(|e| {
        let e = e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
        Error::format(path, format!("corrupt or truncated {}: {e}", format_name(format)))
    })?;
    Ok((w as usize, h as usize))
}

/// A `w` × `h` image (from its header) is one that is decoded: [`MAX_DECODE_SIDE`],
/// [`MAX_PIXELS`].
pub(crate) fn check_decode_size(path: &Path, w: usize, h: usize) -> Result<()> {
    if w == 0 || h == 0 || w > MAX_DECODE_SIDE || h > MAX_DECODE_SIDE || w * h > MAX_PIXELS {
        return Err(Error::format(
            path,
            format!(
                "a {w}x{h} image is outside the sizes read (1 to {MAX_DECODE_SIDE} per side and at most {MAX_PIXELS} pixels, 4096x4096)"
            ),
        ));
    }
    Ok(())
}

/// Decodes an image file's bytes in `format` with its size checked from the header first
/// ([`MAX_PIXELS`], [`MAX_DECODE_SIDE`]) and the decoder's allocations limited; a JPEG must
/// also be complete ([`check_jpeg_complete`]). Errors name `path`.
pub fn decode_limited(path: &Path, bytes: &[u8], format: ImageFormat) -> Result<image::DynamicImage> {
    // Decoder messages may span lines (the JPEG decoder's do): errors are one line.
    let corrupt = |e: image::ImageError| {
        let e = e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
        Error::format(path, format!("corrupt or truncated {}: {e}", format_name(format)))
    };
    let reader = || image::ImageReader::with_format(Cursor::new(bytes), format);
    let (w, h) = reader().into_dimensions().map_err(corrupt)?;
    check_decode_size(path, w as usize, h as usize)?;
    if format == ImageFormat::Jpeg {
        check_jpeg_complete(bytes).map_err(|reason| Error::format(path, format!("corrupt or truncated JPEG: {reason}")))?;
        return decode_jpeg_strict(bytes).map_err(|reason| Error::format(path, format!("corrupt or truncated JPEG: {reason}")));
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_DECODE_SIDE as u32);
    limits.max_image_height = Some(MAX_DECODE_SIDE as u32);
    limits.max_alloc = Some(MAX_DECODE_ALLOC);
    let mut r = reader();
    r.limits(limits);
    r.decode().map_err(corrupt)
}

/// Decodes a JPEG (checked whole by [`check_jpeg_complete`]) in the decoder's strict mode. The image crate drives the same decoder
/// (zune-jpeg) leniently, as browsers do: a scan cut short, an invalid Huffman code or a
/// marker inside the scan data ends the decode quietly with the rest of the picture grey,
/// and the file "succeeds". Here each of those is an error, so a damaged painting is
/// refused instead of fitted into a worse material. What no decoder can see is a damaged
/// scan that still parses (JPEG data has no checksum, and Huffman codes resynchronize):
/// such a file decodes, with a blocky glitch, as it would anywhere else.
///
/// One more thing strict mode does not see: a scan whose data runs out at a marker is
/// finished with zero bits, which decode as flat blocks. So 64 one-bits (`FF 00`, a stuffed
/// 0xFF byte, eight times) are put before the end marker: a whole file's scan ends before
/// them (its last byte is already padded with one-bits, as the standard asks), while a scan
/// that runs short reads them, and 16 one-bits are no JPEG Huffman code: an error.
///
/// The output colours follow the image crate's choice (grey, grey with alpha, RGB and RGBA
/// kept; CMYK and YCCK converted to RGB). The size was checked from the header before this.
fn decode_jpeg_strict(bytes: &[u8]) -> std::result::Result<image::DynamicImage, String> {
    use zune_core::colorspace::ColorSpace as Z;
    let one_line = |e: zune_jpeg::errors::DecodeErrors| e.to_string().replace('"', "").split_whitespace().collect::<Vec<_>>().join(" ");
    let options = zune_core::options::DecoderOptions::default()
        .set_strict_mode(true)
        .set_max_width(MAX_DECODE_SIDE)
        .set_max_height(MAX_DECODE_SIDE);
    let eoi = bytes.windows(2).rposition(|w| w == [0xFF, 0xD9]).ok_or("no end-of-image marker")?;
    let mut padded = Vec::with_capacity(bytes.len() + 16);
    padded.extend_from_slice(&bytes[..eoi]);
    padded.extend_from_slice(&[0xFF, 0x00].repeat(8));
    padded.extend_from_slice(&bytes[eoi..]);
    let bytes = &padded[..];
    let mut headers = zune_jpeg::JpegDecoder::new_with_options(zune_core::bytestream::ZCursor::new(bytes), options);
    headers.decode_headers().map_err(one_line)?;
    let out = match headers.input_colorspace() {
        Some(c @ (Z::RGB | Z::RGBA | Z::Luma | Z::LumaA)) => c,
        _ => Z::RGB,
    };
    let (w, h) = headers.dimensions().ok_or("no image size in the header")?;
    let mut decoder = zune_jpeg::JpegDecoder::new_with_options(
        zune_core::bytestream::ZCursor::new(bytes),
        options.jpeg_set_out_colorspace(out),
    );
    let pixels = decoder.decode().map_err(one_line)?;
    let (w, h) = (w as u32, h as u32);
    let mismatch = format!("{} decoded bytes for a {w}x{h} image", pixels.len());
    let image = match out {
        Z::Luma => image::GrayImage::from_raw(w, h, pixels).map(image::DynamicImage::ImageLuma8),
        Z::LumaA => image::GrayAlphaImage::from_raw(w, h, pixels).map(image::DynamicImage::ImageLumaA8),
        Z::RGBA => image::RgbaImage::from_raw(w, h, pixels).map(image::DynamicImage::ImageRgba8),
        _ => image::RgbImage::from_raw(w, h, pixels).map(image::DynamicImage::ImageRgb8),
    };
    image.ok_or(mismatch)
}

/// A JPEG's entropy-coded data ends with the EOI marker (FF D9): the JPEG decoder fills a
/// file cut short with grey instead of failing, so a truncated file (a half-written save,
/// a broken download) is caught here. EOI must follow the last start-of-scan marker
/// (FF DA); an EOI inside an embedded thumbnail, before the scans, does not count.
pub fn check_jpeg_complete(bytes: &[u8]) -> std::result::Result<(), String> {
    let find_last = |marker: u8| bytes.windows(2).rposition(|w| w[0] == 0xFF && w[1] == marker);
    let Some(sos) = find_last(0xDA) else { return Err("no image data (no start-of-scan marker)".into()) };
    match find_last(0xD9) {
        Some(eoi) if eoi > sos => Ok(()),
        _ => Err("the file ends before its end-of-image marker".into()),
    }
}

/// The 4-neighbours of pixel `k` (index `j * width + i`) in a grid of `len` pixels,
/// `width` to a row: left, right, up, down, those that exist.
pub fn neighbours4(k: usize, width: usize, len: usize) -> impl Iterator<Item = usize> {
    let (i, j, rows) = (k % width, k / width, len / width);
    [(i > 0).then(|| k - 1), (i + 1 < width).then(|| k + 1), (j > 0).then(|| k - width), (j + 1 < rows).then(|| k + width)]
        .into_iter()
        .flatten()
}

/// The 8-neighbours of pixel `k` (index `j * width + i`) in a grid of `len` pixels,
/// `width` to a row: those that exist.
pub fn neighbours8(k: usize, width: usize, len: usize) -> impl Iterator<Item = usize> {
    let (i, j, rows) = ((k % width) as i64, (k / width) as i64, (len / width) as i64);
    [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)]
        .into_iter()
        .map(move |(di, dj)| (i + di, j + dj))
        .filter(move |&(x, y)| x >= 0 && y >= 0 && x < width as i64 && y < rows)
        .map(move |(x, y)| y as usize * width + x as usize)
}

/// The 8-connected components of `mask` (a grid `width` to a row), each as its pixels.
pub fn components(mask: &[bool], width: usize) -> Vec<Vec<usize>> {
    let len = mask.len();
    let mut seen = vec![false; len];
    let mut stack = Vec::new();
    let mut out = Vec::new();
    for start in 0..len {
        if !mask[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        let mut component = Vec::new();
        while let Some(k) = stack.pop() {
            component.push(k);
            for n in neighbours8(k, width, len) {
                if mask[n] && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            }
        }
        out.push(component);
    }
    out
}

/// Clears the 8-connected components of `mask` (a grid `width` to a row) smaller than
/// `least` pixels.
pub fn drop_small_components(mask: &mut [bool], width: usize, least: usize) {
    for component in components(mask, width) {
        if component.len() < least {
            for k in component {
                mask[k] = false;
            }
        }
    }
}

/// EXR values this little below zero are filtering round-off (Blender's bundled MatCaps
/// have them, down to -0.0017), read as 0; anything more negative is an error.
pub const NEGATIVE_NOISE: f32 = 0.01;

/// Reject sizes of zero or absurdly large.
pub fn check_size(width: usize, height: usize) -> Result<()> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(Error::input(format!("image size {width}x{height} is outside 1..={MAX_SIDE} per side")));
    }
    Ok(())
}

/// Rec. 709 luminance weights of linear RGB.
pub const REC709: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Rec. 709 luminance of linear RGB.
pub fn luminance(c: [f64; 3]) -> f64 {
    REC709[0] * c[0] + REC709[1] * c[1] + REC709[2] * c[2]
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

pub(crate) fn format_name(format: ImageFormat) -> &'static str {
    match format {
        ImageFormat::Png => "PNG",
        ImageFormat::Jpeg => "JPEG",
        ImageFormat::OpenExr => "EXR",
        _ => "image",
    }
}

/// The sRGB transfer function, encoded to linear, in `f64` (16-bit codes keep their
/// precision).
pub fn srgb_to_linear_f64(x: f64) -> f64 {
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value as a 16-bit sRGB code (NaN becomes 0).
pub fn encode_srgb16(x: f32) -> u16 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) as f64 };
    let e = if x <= 0.003_130_8 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
    (e * 65535.0 + 0.5) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_neighbours_stay_on_the_grid_and_small_components_go() {
        // A 4x3 grid: a corner has 3 neighbours, an edge pixel 5, an inner one 8.
        assert_eq!(neighbours8(0, 4, 12).collect::<Vec<_>>(), vec![1, 4, 5]);
        assert_eq!(neighbours8(1, 4, 12).count(), 5);
        assert_eq!(neighbours8(5, 4, 12).collect::<Vec<_>>(), vec![0, 1, 2, 4, 6, 8, 9, 10]);
        // A diagonal pair (0, 5) is one component of 2; pixel 3 alone is one of 1.
        let mut mask = vec![true, false, false, true, false, true, false, false, false, false, false, false];
        drop_small_components(&mut mask, 4, 2);
        assert_eq!(mask, vec![true, false, false, false, false, true, false, false, false, false, false, false]);
    }

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
