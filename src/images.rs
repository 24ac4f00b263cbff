//! Image files: float EXR textures in and out, and sRGB PNG output. Everything in memory is
//! linear; the sRGB transfer function is applied only at the file boundary (DESIGN.md,
//! Colour).

pub mod env;
pub mod text;
pub mod tone;

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
    let (w, h) = (w as usize, h as usize);
    if w == 0 || h == 0 || w > MAX_DECODE_SIDE || h > MAX_DECODE_SIDE || w * h > MAX_PIXELS {
        return Err(Error::format(
            path,
            format!(
                "a {w}x{h} image is outside the sizes read (1 to {MAX_DECODE_SIDE} per side and at most {MAX_PIXELS} pixels, 4096x4096)"
            ),
        ));
    }
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

/// A painting or photograph decoded to linear RGB, with its alpha mask (DESIGN.md, Colour).
///
/// - 8- and 16-bit PNG and JPEG are sRGB-encoded: each code is divided by its largest value
///   (255 or 65535, so 16-bit files keep their precision) and decoded with the sRGB transfer
///   function. Grey files are read as equal R, G and B.
/// - EXR is linear float. NaN, infinite and negative values are errors naming the pixel,
///   except negatives within [`NEGATIVE_NOISE`] of zero, which are read as 0.
///   OpenEXR stores colour premultiplied by alpha, so a pixel with $0 < \alpha < 1$ is
///   divided by $\alpha$; PNG alpha is straight and colour is taken as it is.
/// - Alpha is linear in $[0, 1]$ and only a mask: alpha 0 means "not painted", anything
///   above 0 is a sample. A file without alpha is painted everywhere.
#[derive(Clone, Debug, PartialEq)]
pub struct Painting {
    pub width: usize,
    pub height: usize,
    /// Linear RGB, row by row, row 0 at the top.
    pub pixels: Vec<[f32; 3]>,
    /// Alpha per pixel, in $[0, 1]$.
    pub alpha: Vec<f32>,
    /// Per pixel: every colour channel is at the file's largest code (255 or 65535), so the
    /// true value may have been clipped. Always false for EXR.
    pub saturated: Vec<bool>,
}

impl Painting {
    /// An opaque painting from linear RGB pixels (row 0 at the top).
    pub fn opaque(width: usize, height: usize, pixels: Vec<[f32; 3]>) -> Result<Painting> {
        check_size(width, height)?;
        if pixels.len() != width * height {
            return Err(Error::input(format!("{} pixels for a {width}x{height} painting", pixels.len())));
        }
        let n = pixels.len();
        Ok(Painting { width, height, pixels, alpha: vec![1.0; n], saturated: vec![false; n] })
    }

    /// Whether pixel index `k` (row `k / width`, column `k % width`) is painted.
    pub fn painted(&self, k: usize) -> bool {
        self.alpha[k] > 0.0
    }

    /// Read a PNG (8 or 16 bit), JPEG or EXR file. Errors name the file: unreadable (or
    /// not a regular file), corrupt or truncated (a JPEG without its end marker too), an
    /// unsupported format, NaN, infinite or negative EXR values, absurd sizes (refused from
    /// the header, before decoding: [`MAX_PIXELS`]).
    pub fn read(path: &Path) -> Result<Painting> {
        let bytes = crate::fsio::read_regular(path, crate::fsio::MAX_IMAGE_BYTES)?;
        Painting::decode(path, &bytes)
    }

    /// Decode the bytes of a PNG, JPEG or EXR file; `path` names it in errors.
    pub fn decode(path: &Path, bytes: &[u8]) -> Result<Painting> {
        if bytes.is_empty() {
            return Err(Error::format(path, "empty file"));
        }
        let format = image::guess_format(bytes)
            .map_err(|_| Error::format(path, "not a PNG, JPEG or EXR image (unrecognized content)"))?;
        if !matches!(format, ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::OpenExr) {
            return Err(Error::format(
                path,
                format!("unsupported image format {format:?}: paintings are read from PNG, JPEG or EXR"),
            ));
        }
        let img = decode_limited(path, bytes, format)?;
        let (width, height) = (img.width() as usize, img.height() as usize);
        check_size(width, height).map_err(|e| Error::format(path, e.to_string()))?;
        let n = width * height;
        let (mut pixels, mut alpha, mut saturated) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        use image::ColorType as C;
        match img.color() {
            C::L8 | C::La8 | C::Rgb8 | C::Rgba8 => {
                // 256 codes: a table of the transfer function.
                let lut: Vec<f32> = (0..256).map(|c| srgb_to_linear_f64(c as f64 / 255.0) as f32).collect();
                for p in img.to_rgba8().pixels() {
                    let [r, g, b, a] = p.0;
                    pixels.push([lut[r as usize], lut[g as usize], lut[b as usize]]);
                    alpha.push(a as f32 / 255.0);
                    saturated.push(r == u8::MAX && g == u8::MAX && b == u8::MAX);
                }
            }
            C::L16 | C::La16 | C::Rgb16 | C::Rgba16 => {
                let decode = |c: u16| srgb_to_linear_f64(c as f64 / 65535.0) as f32;
                for p in img.to_rgba16().pixels() {
                    let [r, g, b, a] = p.0;
                    pixels.push([decode(r), decode(g), decode(b)]);
                    alpha.push(a as f32 / 65535.0);
                    saturated.push(r == u16::MAX && g == u16::MAX && b == u16::MAX);
                }
            }
            C::Rgb32F | C::Rgba32F if format == ImageFormat::OpenExr => {
                for (k, p) in img.to_rgba32f().pixels().enumerate() {
                    let [r, g, b, a] = p.0;
                    let (i, j) = (k % width, k / width);
                    for (what, x) in [("red", r), ("green", g), ("blue", b), ("alpha", a)] {
                        if x.is_nan() {
                            return Err(Error::format(path, format!("pixel ({i}, {j}) has a NaN {what} value")));
                        }
                        if x.is_infinite() {
                            return Err(Error::format(path, format!("pixel ({i}, {j}) has an infinite {what} value")));
                        }
                        if x < -NEGATIVE_NOISE {
                            return Err(Error::format(path, format!("pixel ({i}, {j}) has a negative {what} value {x}")));
                        }
                    }
                    let [r, g, b, a] = [r, g, b, a].map(|x| x.max(0.0));
                    let a = a.min(1.0);
                    // Un-premultiply partially covered pixels (OpenEXR convention).
                    let s = if a > 0.0 && a < 1.0 { 1.0 / a } else { 1.0 };
                    pixels.push([r * s, g * s, b * s]);
                    alpha.push(a);
                    saturated.push(false);
                }
            }
            other => {
                return Err(Error::format(path, format!("unsupported pixel format {other:?} in a {}", format_name(format))));
            }
        }
        Ok(Painting { width, height, pixels, alpha, saturated })
    }

    /// Encode as a 16-bit sRGB PNG with alpha (values clamped to [0, 1]).
    pub fn encode_png16(&self) -> Result<Vec<u8>> {
        let mut raw = Vec::with_capacity(self.pixels.len() * 4);
        for (p, &a) in self.pixels.iter().zip(&self.alpha) {
            for &x in p {
                raw.push(encode_srgb16(x));
            }
            raw.push((a.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16);
        }
        let img = image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(self.width as u32, self.height as u32, raw)
            .ok_or_else(|| Error::input("pixel buffer does not match the painting size"))?;
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, ImageFormat::Png).map_err(|e| Error::input(format!("PNG encoding failed: {e}")))?;
        Ok(out.into_inner())
    }

    /// Encode as a linear float EXR with alpha (colour premultiplied, as OpenEXR stores it).
    pub fn encode_exr(&self) -> Result<Vec<u8>> {
        let mut raw = Vec::with_capacity(self.pixels.len() * 4);
        for (p, &a) in self.pixels.iter().zip(&self.alpha) {
            let a = a.clamp(0.0, 1.0);
            let s = if a < 1.0 { a } else { 1.0 };
            raw.extend_from_slice(&[p[0] * s, p[1] * s, p[2] * s, a]);
        }
        let img = image::Rgba32FImage::from_raw(self.width as u32, self.height as u32, raw)
            .ok_or_else(|| Error::input("pixel buffer does not match the painting size"))?;
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, ImageFormat::OpenExr).map_err(|e| Error::input(format!("EXR encoding failed: {e}")))?;
        Ok(out.into_inner())
    }

    /// Write atomically: `.exr` as linear float, anything else as a 16-bit sRGB PNG.
    pub fn write(&self, path: &Path) -> Result<()> {
        let exr = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        let bytes = if exr { self.encode_exr() } else { self.encode_png16() }
            .map_err(|e| Error::format(path, e.to_string()))?;
        write_atomic(path, &bytes)
    }
}

fn format_name(format: ImageFormat) -> &'static str {
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
mod painting_tests {
    use super::*;

    fn painting(w: usize, h: usize) -> Painting {
        let pixels = (0..w * h).map(|k| [k as f32 / (w * h) as f32, 0.25, 1.0]).collect();
        let mut p = Painting::opaque(w, h, pixels).unwrap();
        p.alpha[0] = 0.0;
        p
    }

    #[test]
    fn png16_round_trips_within_16_bit_precision() {
        let p = painting(7, 5);
        let back = Painting::decode(Path::new("p.png"), &p.encode_png16().unwrap()).unwrap();
        assert_eq!((back.width, back.height), (7, 5));
        for (a, b) in p.pixels.iter().zip(&back.pixels) {
            for c in 0..3 {
                // One 16-bit sRGB code is at most ~1e-4 linear near 1 and far less near 0.
                assert!((a[c] - b[c]).abs() < 1e-4 * a[c].max(1e-3), "{a:?} vs {b:?}");
            }
        }
        assert_eq!(back.alpha[0], 0.0);
        assert!(back.alpha[1..].iter().all(|&a| a == 1.0));
        // (x, 0.25, 1.0): not saturated; only all-white pixels are.
        assert!(!back.saturated.iter().any(|&s| s));
    }

    #[test]
    fn eight_bit_png_decodes_with_the_srgb_curve() {
        let img = image::RgbaImage::from_raw(2, 1, vec![128, 255, 0, 255, 255, 255, 255, 0]).unwrap();
        let mut bytes = Cursor::new(Vec::new());
        img.write_to(&mut bytes, ImageFormat::Png).unwrap();
        let p = Painting::decode(Path::new("p.png"), bytes.get_ref()).unwrap();
        assert!((p.pixels[0][0] - 0.2158605).abs() < 1e-6 && p.pixels[0][1] == 1.0 && p.pixels[0][2] == 0.0);
        assert_eq!(p.alpha, vec![1.0, 0.0]);
        assert_eq!(p.saturated, vec![false, true]);
    }

    #[test]
    fn jpeg_decodes_with_the_srgb_curve_and_is_opaque() {
        let img = image::RgbImage::from_pixel(16, 16, image::Rgb([128, 64, 200]));
        let mut bytes = Cursor::new(Vec::new());
        img.write_to(&mut bytes, ImageFormat::Jpeg).unwrap();
        let p = Painting::decode(Path::new("p.jpg"), bytes.get_ref()).unwrap();
        // A flat colour survives JPEG within a code or two.
        let want = [128.0f32, 64.0, 200.0].map(|c| srgb_to_linear(c / 255.0));
        for c in 0..3 {
            assert!((p.pixels[100][c] - want[c]).abs() < 0.01, "{:?} vs {want:?}", p.pixels[100]);
        }
        assert!(p.alpha.iter().all(|&a| a == 1.0));
    }

    #[test]
    fn exr_is_linear_and_bad_values_are_errors_naming_the_pixel() {
        let mut p = painting(4, 3);
        p.pixels[5] = [2.5, 0.0, 1e-3];
        let back = Painting::decode(Path::new("p.exr"), &p.encode_exr().unwrap()).unwrap();
        assert_eq!(back.pixels[5], [2.5, 0.0, 1e-3]);
        assert_eq!(back.alpha[0], 0.0);
        for (bad, what) in [(f32::NAN, "NaN"), (f32::INFINITY, "infinite"), (-1.0, "negative")] {
            let mut q = painting(4, 3);
            q.pixels[6][1] = bad;
            // Write the raw value (encode_exr would pass it through unchanged).
            let e = Painting::decode(Path::new("bad.exr"), &q.encode_exr().unwrap()).unwrap_err().to_string();
            assert!(e.contains("bad.exr") && e.contains(what) && e.contains("(2, 1)"), "{e}");
        }
        // Filtering round-off just below zero (Blender's MatCaps) reads as 0.
        let mut q = painting(4, 3);
        q.pixels[6] = [-0.0017, 0.5, -1e-6];
        let back = Painting::decode(Path::new("q.exr"), &q.encode_exr().unwrap()).unwrap();
        assert_eq!(back.pixels[6], [0.0, 0.5, 0.0]);
    }

    #[test]
    fn corrupt_truncated_and_foreign_files_are_one_line_errors() {
        let good = painting(16, 16).encode_png16().unwrap();
        let cases: Vec<(&str, Vec<u8>)> = vec![
            ("empty.png", vec![]),
            ("text.png", b"hello, not an image".to_vec()),
            ("cut.png", good[..good.len() / 2].to_vec()),
            ("cut.exr", painting(16, 16).encode_exr().unwrap()[..200].to_vec()),
        ];
        for (name, bytes) in cases {
            let e = Painting::decode(Path::new(name), &bytes).unwrap_err().to_string();
            assert!(e.contains(name) && !e.contains('\n'), "{e}");
        }
        let e = Painting::read(Path::new("/nonexistent/p.png")).unwrap_err().to_string();
        assert!(e.contains("/nonexistent/p.png"), "{e}");
    }

    /// A JPEG cut short decodes to grey in the decoder; it is refused here, whole ones pass.
    #[test]
    fn truncated_jpegs_are_refused() {
        let img = image::RgbImage::from_fn(64, 64, |x, y| image::Rgb([(x * 4) as u8, (y * 4) as u8, 128]));
        let mut bytes = Cursor::new(Vec::new());
        img.write_to(&mut bytes, ImageFormat::Jpeg).unwrap();
        let good = bytes.into_inner();
        assert!(Painting::decode(Path::new("p.jpg"), &good).is_ok());
        for cut in [good.len() - 2, good.len() * 3 / 4, good.len() / 2] {
            let e = Painting::decode(Path::new("cut.jpg"), &good[..cut]).unwrap_err().to_string();
            assert!(e.starts_with("cut.jpg: corrupt or truncated JPEG"), "{cut}: {e}");
        }
    }

    /// A small PNG whose header claims 13000²: refused from the header, before decoding.
    #[test]
    fn image_bombs_are_refused_from_the_header() {
        let e = Painting::decode(Path::new("bomb.png"), &png_header_only(13000, 13000)).unwrap_err().to_string();
        assert!(e.contains("bomb.png: a 13000x13000 image is outside the sizes read"), "{e}");
        let e = Painting::decode(Path::new("wide.png"), &png_header_only(20000, 1)).unwrap_err().to_string();
        assert!(e.contains("20000x1"), "{e}");
    }

    /// An 8-bit RGB PNG of `w` × `h` whose data is a few bytes of nothing: what a decoder
    /// would allocate for is only in the header.
    pub(crate) fn png_header_only(w: u32, h: u32) -> Vec<u8> {
        let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut chunk = |kind: &[u8], data: &[u8]| {
            let mut body = kind.to_vec();
            body.extend_from_slice(data);
            out.extend_from_slice(&(data.len() as u32).to_be_bytes());
            out.extend_from_slice(&body);
            out.extend_from_slice(&crc32(&body).to_be_bytes());
        };
        let mut ihdr = w.to_be_bytes().to_vec();
        ihdr.extend_from_slice(&h.to_be_bytes());
        ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
        chunk(b"IHDR", &ihdr);
        chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0x00]);
        chunk(b"IEND", &[]);
        out
    }

    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = 0xFFFF_FFFFu32;
        for &b in bytes {
            c ^= b as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 { 0xEDB8_8320 ^ (c >> 1) } else { c >> 1 };
            }
        }
        !c
    }
}
