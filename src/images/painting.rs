//! Paintings and photographs: decoded to linear RGB with an alpha mask (DESIGN.md, Colour).

use std::io::Cursor;
use std::path::Path;

use image::ImageFormat;

use super::{check_size, decode_limited, encode_srgb16};
use crate::commit::write_atomic;
use crate::error::{Error, Result};

/// A painting or photograph decoded to linear RGB, with its alpha mask (DESIGN.md, Colour).
///
/// - 8- and 16-bit PNG and JPEG are sRGB-encoded: each code is divided by its largest value
///   (255 or 65535, so 16-bit files keep their precision) and decoded with the sRGB transfer
///   function. Grey files are read as equal R, G and B.
/// - EXR is linear float. NaN, infinite and negative values are errors naming the pixel,
///   except negatives within [`super::NEGATIVE_NOISE`] of zero, which are read as 0.
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

/// The format of a painting file's bytes (PNG, JPEG or EXR) and its decoded image
/// ([`decode_limited`]). Errors name `path`.
pub(super) fn decode_image(path: &Path, bytes: &[u8]) -> Result<(ImageFormat, image::DynamicImage)> {
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
    Ok((format, decode_limited(path, bytes, format)?))
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
    /// the header, before decoding: [`super::MAX_PIXELS`]).
    pub fn read(path: &Path) -> Result<Painting> {
        let bytes = crate::fsio::read_regular(path, crate::fsio::MAX_IMAGE_BYTES)?;
        Painting::decode(path, &bytes)
    }

    /// Decode the bytes of a PNG, JPEG or EXR file; `path` names it in errors.
    pub fn decode(path: &Path, bytes: &[u8]) -> Result<Painting> {
        let (format, img) = decode_image(path, bytes)?;
        let (width, height) = (img.width() as usize, img.height() as usize);
        check_size(width, height).map_err(|e| Error::format(path, e.to_string()))?;
        let n = width * height;
        let mut p = Painting { width, height, pixels: Vec::with_capacity(n), alpha: Vec::with_capacity(n), saturated: Vec::with_capacity(n) };
        super::rows::each_row(path, &img, format, |_, row| {
            for &(rgb, a, sat) in row {
                p.pixels.push(rgb);
                p.alpha.push(a);
                p.saturated.push(sat);
            }
        })?;
        Ok(p)
    }

    /// Reads the picture at `path` box-filtered to at most `max_side` pixels a side, and the
    /// factor it was shrunk by, never holding it at full size where the format allows
    /// ([`super::rows::read_shrunk`]); `check` sees its size before any pixel is decoded.
    pub fn read_shrunk(path: &Path, max_side: usize, check: impl FnOnce(usize, usize) -> Result<()>) -> Result<(Painting, usize)> {
        super::rows::read_shrunk(path, max_side, check)
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

#[cfg(test)]
mod painting_tests {
    use super::*;
    use crate::images::srgb_to_linear;

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
