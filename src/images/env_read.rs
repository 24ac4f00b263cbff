//! Reading environment files (OpenEXR, Radiance `.hdr`) within a memory budget: sizes and
//! the Radiance header are checked before any pixel is decoded, an OpenEXR map is read
//! block by block and a Radiance one a scanline at a time, and a map over the renderer's
//! pixel limit is averaged down as it is read (the common 8192×4096 map becomes 4096×2048),
//! so a map is never held at full size.

use std::io::{BufRead, Read, Seek, SeekFrom};
use std::path::Path;

use image::ImageFormat;

use super::env::{Environment, MAX_RADIANCE};
use crate::error::{Error, Result};

/// Largest environment read: 8192×4096, the largest size HDRI libraries commonly publish
/// (Poly Haven's "8K"). Larger maps are refused from their header.
pub const MAX_ENV_WIDTH: usize = 8192;

/// Most pixels an environment keeps: the renderer's limit ([`super::MAX_PIXELS`],
/// 4096 × 4096). A larger map is averaged in f × f boxes until it fits.
const KEEP_PIXELS: usize = super::MAX_PIXELS;

/// Most bytes of a Radiance header, from the signature to the end of the resolution line.
/// Real headers are a few hundred bytes; the decoder keeps every header line in memory, so
/// an unbounded one (a 64 MiB file of 32 million lines took 2.6 GB) is refused.
pub const MAX_HDR_HEADER: usize = 64 << 10;

/// Values this far below zero count as negative when deciding whether a map is mostly
/// negative ([`super::NEGATIVE_NOISE`], the paintings' rounding allowance).
const NEGATIVE: f32 = super::NEGATIVE_NOISE;

/// Reads an environment from `source` (the whole file, positioned at its start); `path`
/// names it in errors.
pub(super) fn read<R: BufRead + Seek>(path: &Path, mut source: R) -> Result<Environment> {
    let mut head = Vec::with_capacity(MAX_HDR_HEADER);
    (&mut source).take(MAX_HDR_HEADER as u64).read_to_end(&mut head).map_err(|e| Error::io(path, e))?;
    source.seek(SeekFrom::Start(0)).map_err(|e| Error::io(path, e))?;
    match image::guess_format(&head) {
        Ok(ImageFormat::Hdr) => {
            check_radiance_header(&head).map_err(|reason| Error::format(path, reason))?;
            read_hdr(path, source)
        }
        Ok(ImageFormat::OpenExr) => read_exr(path, source),
        Ok(other) => Err(Error::format(
            path,
            format!("a {other:?} image is not an HDR environment (expected OpenEXR or Radiance .hdr)"),
        )),
        Err(_) => Err(Error::format(path, "not an HDR environment (expected OpenEXR or Radiance .hdr)")),
    }
}

/// The Radiance header in `head` (the file's first [`MAX_HDR_HEADER`] bytes or all of a
/// shorter file) ends, with its resolution line, inside `head`.
fn check_radiance_header(head: &[u8]) -> std::result::Result<(), String> {
    let blank = head.windows(2).position(|w| w == b"\n\n");
    let resolution_ends = blank.is_some_and(|b| head[b + 2..].contains(&b'\n'));
    if resolution_ends {
        return Ok(());
    }
    if head.len() < MAX_HDR_HEADER {
        return Err("truncated Radiance header (no resolution line)".into());
    }
    Err(format!("Radiance header longer than {} KiB (no resolution line in it); real headers are a few hundred bytes", MAX_HDR_HEADER >> 10))
}

fn corrupt(path: &Path, what: &str, e: impl std::fmt::Display) -> Error {
    Error::format(path, format!("corrupt or truncated {what}: {e}"))
}

/// A Radiance file, decoded a scanline at a time into the averaged map: its header by the
/// image crate's decoder (checked first: [`check_radiance_header`]), its pixels here.
fn read_hdr<R: BufRead + Seek>(path: &Path, mut source: R) -> Result<Environment> {
    use image::ImageDecoder;
    let header = image::codecs::hdr::HdrDecoder::new(&mut source).map_err(|e| corrupt(path, "Radiance .hdr", e))?;
    let (w, h) = header.dimensions();
    drop(header);
    let (w, h) = (w as usize, h as usize);
    let mut boxes = Boxes::new(w, h).map_err(|e| Error::format(path, e))?;
    let mut line = vec![[0u8; 4]; w];
    for y in 0..h {
        read_scanline(&mut source, &mut line).map_err(|e| corrupt(path, "Radiance .hdr", format!("scanline {y}: {e}")))?;
        for (x, &rgbe) in line.iter().enumerate() {
            boxes.add(x, y, rgbe_to_rgb(rgbe));
        }
    }
    boxes.finish().map_err(|e| Error::format(path, e))
}

/// An RGBE pixel as linear RGB: mantissas × $2^{e - 136}$ (128 for the exponent's bias, 8
/// for the mantissa's bits), 0 where $e = 0$; as the image crate decodes it.
fn rgbe_to_rgb([r, g, b, e]: [u8; 4]) -> [f32; 3] {
    if e == 0 {
        return [0.0; 3];
    }
    let scale = f32::exp2(e as f32 - 136.0);
    [r, g, b].map(|c| c as f32 * scale)
}

/// One scanline of RGBE pixels: Ward's run-length encoding per component (a scanline that
/// starts 2, 2, then under 128), or else the older pixel runs. The same rules as the image
/// crate's decoder, which reads the whole image at once.
fn read_scanline(r: &mut impl Read, line: &mut [[u8; 4]]) -> std::result::Result<(), String> {
    let first = read4(r)?;
    if first[0] == 2 && first[1] == 2 && first[2] < 128 {
        for c in 0..4 {
            read_component(r, line, c)?;
        }
        return Ok(());
    }
    read_old_runs(r, first, line)
}

fn read4(r: &mut impl Read) -> std::result::Result<[u8; 4], String> {
    let mut b = [0u8; 4];
    r.read_exact(&mut b).map_err(|e| e.to_string())?;
    Ok(b)
}

/// Component `c` of every pixel of `line`: counts above 128 are runs of one value, others
/// that many literal values.
fn read_component(r: &mut impl Read, line: &mut [[u8; 4]], c: usize) -> std::result::Result<(), String> {
    let (width, mut x) = (line.len(), 0);
    let mut buf = [0u8; 128];
    while x < width {
        let mut count = [0u8; 1];
        r.read_exact(&mut count).map_err(|e| e.to_string())?;
        let (n, run) = if count[0] > 128 { ((count[0] - 128) as usize, true) } else { (count[0] as usize, false) };
        if n == 0 || x + n > width {
            return Err(format!("a run of {n} at pixel {x} of a {width}-pixel scanline"));
        }
        let values = &mut buf[..if run { 1 } else { n }];
        r.read_exact(values).map_err(|e| e.to_string())?;
        for k in 0..n {
            line[x + k][c] = values[if run { 0 } else { k }];
        }
        x += n;
    }
    Ok(())
}

/// The older encoding: pixels, where (1, 1, 1, n) repeats the previous pixel n times, and
/// consecutive markers multiply by 256 each.
fn read_old_runs(r: &mut impl Read, first: [u8; 4], line: &mut [[u8; 4]]) -> std::result::Result<(), String> {
    let marker = |p: [u8; 4]| (p[..3] == [1, 1, 1]).then_some(p[3] as usize);
    if marker(first).is_some() {
        return Err("the scanline starts with a run".into());
    }
    let width = line.len();
    line[0] = first;
    let (mut x, mut multiplier, mut previous) = (1, 1usize, first);
    while x < width {
        let pixel = read4(r)?;
        match marker(pixel) {
            Some(n) => {
                let n = n.saturating_mul(multiplier);
                multiplier = multiplier.saturating_mul(256);
                if x + n > width {
                    return Err(format!("a run of {n} at pixel {x} of a {width}-pixel scanline"));
                }
                line[x..x + n].fill(previous);
                x += n;
            }
            None => {
                multiplier = 1;
                previous = pixel;
                line[x] = pixel;
                x += 1;
            }
        }
    }
    Ok(())
}

/// An OpenEXR file, read block by block into the averaged map (never whole at full size).
fn read_exr<R: BufRead + Seek>(path: &Path, mut source: R) -> Result<Environment> {
    use exr::prelude::{ReadChannels, ReadLayers};
    let meta = exr::meta::MetaData::read_from_buffered(&mut source, false).map_err(|e| corrupt(path, "EXR", e))?;
    for header in &meta.headers {
        Boxes::check_size(header.layer_size.width(), header.layer_size.height()).map_err(|e| Error::format(path, e))?;
    }
    source.seek(SeekFrom::Start(0)).map_err(|e| Error::io(path, e))?;
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .rgba_channels(
            |size, _| Boxes::new(size.width(), size.height()),
            |boxes, at, (r, g, b, _): (f32, f32, f32, f32)| {
                if let Ok(boxes) = boxes {
                    boxes.add(at.x(), at.y(), [r, g, b]);
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(source)
        .map_err(|e| corrupt(path, "EXR", e))?;
    image.layer_data.channel_data.pixels.and_then(Boxes::finish).map_err(|e| Error::format(path, e))
}

/// A map being read: each value checked as it arrives, and averaged into f × f boxes so
/// that at most [`KEEP_PIXELS`] are kept.
pub(super) struct Boxes {
    width: usize,
    height: usize,
    f: usize,
    out_width: usize,
    out_height: usize,
    sums: Vec<[f32; 3]>,
    /// The first value refused (not finite, or over [`MAX_RADIANCE`]).
    bad: Option<String>,
    /// Pixels with a channel below −[`NEGATIVE`].
    negative: usize,
}

impl Boxes {
    /// Errors: no pixels, not 2:1, larger than [`MAX_ENV_WIDTH`].
    pub(super) fn check_size(width: usize, height: usize) -> std::result::Result<(), String> {
        if width == 0 || height == 0 {
            return Err(format!("a {width}x{height} environment has no pixels"));
        }
        if width != 2 * height {
            return Err(format!(
                "the environment is {width}x{height}; an equirectangular map is exactly twice as wide as high"
            ));
        }
        if width > MAX_ENV_WIDTH {
            return Err(format!(
                "the environment is {width}x{height}; at most {MAX_ENV_WIDTH}x{} is read",
                MAX_ENV_WIDTH / 2
            ));
        }
        Ok(())
    }

    /// A map of `width` × `height` pixels to be read ([`Boxes::check_size`]).
    pub(super) fn new(width: usize, height: usize) -> std::result::Result<Boxes, String> {
        Boxes::check_size(width, height)?;
        let f = (1..).find(|f| (width / f) * (height / f) <= KEEP_PIXELS).expect("f = width fits");
        // 2:1 kept exactly: a row of an odd-height map loses its last column pair.
        let out_height = height / f;
        let out_width = 2 * out_height;
        let sums = vec![[0.0; 3]; out_width * out_height];
        Ok(Boxes { width, height, f, out_width, out_height, sums, bad: None, negative: 0 })
    }

    /// Pixel (x, y) of the file. Negative values add as 0 (codec ringing: [`Environment::new`]).
    pub(super) fn add(&mut self, x: usize, y: usize, rgb: [f32; 3]) {
        if rgb.iter().any(|&v| !v.is_finite() || v > MAX_RADIANCE) {
            if self.bad.is_none() {
                let v = rgb.into_iter().find(|&v| !v.is_finite() || v > MAX_RADIANCE).unwrap_or(f32::NAN);
                self.bad = Some(format!(
                    "pixel ({x}, {y}) has radiance {v}; an environment needs finite values up to {MAX_RADIANCE}"
                ));
            }
            return;
        }
        if rgb.iter().any(|&v| v < -NEGATIVE) {
            self.negative += 1;
        }
        let (i, j) = (x / self.f, y / self.f);
        if i < self.out_width && j < self.out_height {
            let sum = &mut self.sums[j * self.out_width + i];
            for (s, v) in sum.iter_mut().zip(rgb) {
                *s += v.max(0.0);
            }
        }
    }

    /// The averaged map. Errors: a refused value, or a map mostly negative (radiance never
    /// is: such a file is a difference or a log image, not light).
    pub(super) fn finish(self) -> std::result::Result<Environment, String> {
        if let Some(bad) = self.bad {
            return Err(bad);
        }
        let total = self.width * self.height;
        if self.negative * 2 > total {
            return Err(format!(
                "{:.0}% of the environment's pixels are negative; radiance is never negative (small negative codec ringing is read as 0, a mostly negative map is refused)",
                100.0 * self.negative as f64 / total as f64
            ));
        }
        let scale = 1.0 / (self.f * self.f) as f32;
        let pixels = self.sums.into_iter().map(|s| s.map(|v| v * scale)).collect();
        Ok(Environment { width: self.out_width, height: self.out_height, pixels })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    /// A Radiance header for a `w` × `h` image.
    fn header(w: usize, h: usize) -> Vec<u8> {
        format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes()
    }

    #[test]
    fn radiance_scanlines_decode_as_the_image_crate_decodes_them() {
        let (w, h) = (64usize, 32usize);
        let pixels: Vec<image::Rgb<f32>> =
            (0..w * h).map(|k| image::Rgb([(k % 7) as f32 * 0.3, (k / w) as f32 * 10.0, if k % 5 == 0 { 0.0 } else { 1e-3 * k as f32 }])).collect();
        let mut bytes = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut bytes).encode(&pixels, w, h).unwrap();
        let ours = read(Path::new("t.hdr"), Cursor::new(&bytes)).unwrap();
        let theirs = image::load_from_memory_with_format(&bytes, ImageFormat::Hdr).unwrap().into_rgb32f();
        assert_eq!((ours.width, ours.height), (w, h));
        assert!(ours.pixels.iter().zip(theirs.pixels()).all(|(a, b)| *a == b.0));
    }

    #[test]
    fn old_radiance_runs_repeat_the_previous_pixel() {
        // Row 0: one pixel, then a run of 7; row 1: two pixels, a run of 2 and a run of
        // 1 × 256 would overflow the row; rows 2 and 3: eight literal pixels each.
        let mut bytes = header(8, 4);
        bytes.extend_from_slice(&[128, 64, 32, 129, 1, 1, 1, 7]);
        let mut bad = bytes.clone();
        bytes.extend_from_slice(&[10, 20, 30, 128, 40, 50, 60, 128, 1, 1, 1, 6]);
        bytes.extend_from_slice(&[128, 128, 128, 128].repeat(16));
        let env = read(Path::new("t.hdr"), Cursor::new(&bytes)).unwrap();
        assert!(env.pixels[..8].iter().all(|p| *p == [1.0, 0.5, 0.25]), "{:?}", &env.pixels[..8]);
        assert_eq!(env.pixels[8], [10.0 / 256.0, 20.0 / 256.0, 30.0 / 256.0]);
        assert!(env.pixels[9..16].iter().all(|p| *p == [40.0 / 256.0, 50.0 / 256.0, 60.0 / 256.0]));
        assert!(env.pixels[16..].iter().all(|p| *p == [0.5; 3]));
        bad.extend_from_slice(&[10, 20, 30, 128, 1, 1, 1, 2, 1, 1, 1, 1]);
        let e = read(Path::new("t.hdr"), Cursor::new(&bad)).unwrap_err().to_string();
        assert_eq!(e, "t.hdr: corrupt or truncated Radiance .hdr: scanline 1: a run of 256 at pixel 3 of a 8-pixel scanline");
    }

    #[test]
    fn radiance_headers_end_within_their_bound() {
        assert!(check_radiance_header(&header(8, 4)).is_ok());
        assert_eq!(check_radiance_header(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n").unwrap_err(), "truncated Radiance header (no resolution line)");
        let long = [&b"#?RADIANCE\n"[..], &b"x\n".repeat(MAX_HDR_HEADER)].concat();
        assert!(check_radiance_header(&long[..MAX_HDR_HEADER]).unwrap_err().starts_with("Radiance header longer than 64 KiB"));
    }
}
