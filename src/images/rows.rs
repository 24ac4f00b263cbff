//! A painting's pixels row by row: the one conversion of file codes to linear RGB, alpha and
//! saturation ([`Painting`]'s rules), for a whole decoded image or for a picture read and
//! shrunk in passing ([`read_shrunk`]: a 4096² 16-bit PNG becomes a 512² painting without
//! ever being held at full size).

use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use image::{DynamicImage, ImageFormat};

use super::{srgb_to_linear_f64, Painting, NEGATIVE_NOISE};
use crate::error::{Error, Result};

/// One pixel as a painting holds it: linear RGB, alpha in [0, 1], and whether every colour
/// channel is at the file's largest code.
pub(super) type Texel = ([f32; 3], f32, bool);

/// The sRGB transfer function of every 8-bit code.
fn lut8() -> Vec<f32> {
    (0..256).map(|c| srgb_to_linear_f64(c as f64 / 255.0) as f32).collect()
}

/// `channels` samples (grey, grey+alpha, RGB, RGBA) as RGBA, alpha `one` where absent.
fn rgba<T: Copy>(px: &[T], one: T) -> [T; 4] {
    match *px {
        [l] => [l, l, l, one],
        [l, a] => [l, l, l, a],
        [r, g, b] => [r, g, b, one],
        [r, g, b, a, ..] => [r, g, b, a],
        [] => unreachable!("a pixel has 1 to 4 channels"),
    }
}

fn texel8(lut: &[f32], [r, g, b, a]: [u8; 4]) -> Texel {
    ([lut[r as usize], lut[g as usize], lut[b as usize]], a as f32 / 255.0, r == u8::MAX && g == u8::MAX && b == u8::MAX)
}

fn texel16([r, g, b, a]: [u16; 4]) -> Texel {
    let decode = |c: u16| srgb_to_linear_f64(c as f64 / 65535.0) as f32;
    ([decode(r), decode(g), decode(b)], a as f32 / 65535.0, r == u16::MAX && g == u16::MAX && b == u16::MAX)
}

/// A linear EXR pixel (i, j): NaN, infinite and negative values (beyond [`NEGATIVE_NOISE`])
/// are errors naming it; colour is un-premultiplied (the OpenEXR convention).
fn texel_exr(i: usize, j: usize, px: [f32; 4]) -> std::result::Result<Texel, String> {
    for (what, x) in ["red", "green", "blue", "alpha"].into_iter().zip(px) {
        if x.is_nan() {
            return Err(format!("pixel ({i}, {j}) has a NaN {what} value"));
        }
        if x.is_infinite() {
            return Err(format!("pixel ({i}, {j}) has an infinite {what} value"));
        }
        if x < -NEGATIVE_NOISE {
            return Err(format!("pixel ({i}, {j}) has a negative {what} value {x}"));
        }
    }
    let [r, g, b, a] = px.map(|x| x.max(0.0));
    let a = a.min(1.0);
    let s = if a > 0.0 && a < 1.0 { 1.0 / a } else { 1.0 };
    Ok(([r * s, g * s, b * s], a, false))
}

/// Calls `sink` with each row of a decoded image, converted ([`Painting`]'s rules); `format`
/// is the file's (float pixels are read only from EXR). Errors name `path`.
pub(super) fn each_row(path: &Path, img: &DynamicImage, format: ImageFormat, mut sink: impl FnMut(usize, &[Texel])) -> Result<()> {
    let width = img.width() as usize;
    let lut = lut8();
    let eight = |px: &[u8], _, _| Ok(texel8(&lut, rgba(px, u8::MAX)));
    let sixteen = |px: &[u16], _, _| Ok(texel16(rgba(px, u16::MAX)));
    let float = |px: &[f32], i, j| texel_exr(i, j, rgba(px, 1.0));
    let exr = format == ImageFormat::OpenExr;
    let rows = match img {
        DynamicImage::ImageLuma8(b) => convert_rows(b.as_raw(), width, 1, eight, &mut sink),
        DynamicImage::ImageLumaA8(b) => convert_rows(b.as_raw(), width, 2, eight, &mut sink),
        DynamicImage::ImageRgb8(b) => convert_rows(b.as_raw(), width, 3, eight, &mut sink),
        DynamicImage::ImageRgba8(b) => convert_rows(b.as_raw(), width, 4, eight, &mut sink),
        DynamicImage::ImageLuma16(b) => convert_rows(b.as_raw(), width, 1, sixteen, &mut sink),
        DynamicImage::ImageLumaA16(b) => convert_rows(b.as_raw(), width, 2, sixteen, &mut sink),
        DynamicImage::ImageRgb16(b) => convert_rows(b.as_raw(), width, 3, sixteen, &mut sink),
        DynamicImage::ImageRgba16(b) => convert_rows(b.as_raw(), width, 4, sixteen, &mut sink),
        DynamicImage::ImageRgb32F(b) if exr => convert_rows(b.as_raw(), width, 3, float, &mut sink),
        DynamicImage::ImageRgba32F(b) if exr => convert_rows(b.as_raw(), width, 4, float, &mut sink),
        other => {
            return Err(Error::format(
                path,
                format!("unsupported pixel format {:?} in a {}", other.color(), super::format_name(format)),
            ));
        }
    };
    rows.map_err(|e| Error::format(path, e))
}

/// `samples` (rows of `width` pixels of `channels` samples) through `texel`, a row at a time.
fn convert_rows<T>(
    samples: &[T],
    width: usize,
    channels: usize,
    texel: impl Fn(&[T], usize, usize) -> std::result::Result<Texel, String>,
    sink: &mut impl FnMut(usize, &[Texel]),
) -> std::result::Result<(), String> {
    let mut row = Vec::with_capacity(width);
    for (j, line) in samples.chunks_exact(width * channels).enumerate() {
        row.clear();
        for (i, px) in line.chunks_exact(channels).enumerate() {
            row.push(texel(px, i, j)?);
        }
        sink(j, &row);
    }
    Ok(())
}

/// A painting box-filtered by an integer factor as its rows arrive, so that its longer
/// side is at most a given one: colours weighted by alpha, alpha averaged, saturated where
/// the whole box is. Rows and columns past the last whole box are dropped.
pub struct Shrink {
    f: usize,
    out: Painting,
    /// Alpha-weighted colour sums of each box.
    colour: Vec<[f32; 3]>,
}

impl Shrink {
    /// The factor a `width` × `height` picture is divided by to fit `max_side`.
    pub fn factor(width: usize, height: usize, max_side: usize) -> usize {
        width.max(height).div_ceil(max_side.max(1)).max(1)
    }

    /// Shrinks a `width` × `height` picture to fit `max_side` ([`Shrink::factor`]).
    pub fn new(width: usize, height: usize, max_side: usize) -> Shrink {
        let f = Shrink::factor(width, height, max_side);
        let (w, h) = (width / f, height / f);
        let out = Painting { width: w, height: h, pixels: vec![[0.0; 3]; w * h], alpha: vec![0.0; w * h], saturated: vec![true; w * h] };
        let colour = if f == 1 { Vec::new() } else { vec![[0.0; 3]; w * h] };
        Shrink { f, out, colour }
    }

    /// The factor it shrinks by.
    pub fn f(&self) -> usize {
        self.f
    }

    /// Row `j` of the picture.
    pub fn row(&mut self, j: usize, row: &[Texel]) {
        let (f, w) = (self.f, self.out.width);
        let y = j / f;
        if y >= self.out.height {
            return;
        }
        for (i, &(rgb, a, sat)) in row.iter().enumerate().take(w * f) {
            let k = y * w + i / f;
            if f == 1 {
                (self.out.pixels[k], self.out.alpha[k], self.out.saturated[k]) = (rgb, a, sat);
                continue;
            }
            for (sum, x) in self.colour[k].iter_mut().zip(rgb) {
                *sum += x * a;
            }
            self.out.alpha[k] += a;
            self.out.saturated[k] &= sat;
        }
    }

    /// The shrunk painting.
    pub fn finish(mut self) -> Painting {
        if self.f > 1 {
            let area = (self.f * self.f) as f32;
            for ((p, a), c) in self.out.pixels.iter_mut().zip(&mut self.out.alpha).zip(&self.colour) {
                *p = if *a > 0.0 { c.map(|x| x / *a) } else { [0.0; 3] };
                *a /= area;
            }
        }
        self.out
    }
}

/// Reads the picture at `path` (PNG, JPEG, EXR) box-filtered to at most `max_side` pixels a
/// side ([`Shrink`]), and the factor it was shrunk by. `check` sees the picture's size
/// before any pixel is decoded. A non-interlaced PNG is decoded a row at a time, so its
/// full-size pixels are never held: a 4096² 16-bit PNG costs a row, not 0.5 GB.
pub fn read_shrunk(path: &Path, max_side: usize, check: impl FnOnce(usize, usize) -> Result<()>) -> Result<(Painting, usize)> {
    let (file, _) = crate::fsio::open_regular(path, crate::fsio::MAX_IMAGE_BYTES)?;
    let mut source = BufReader::new(file);
    let head = source.fill_buf().map_err(|e| Error::io(path, e))?;
    if image::guess_format(head).ok() == Some(ImageFormat::Png) {
        let interlaced = png_is_interlaced(path, &mut source)?;
        source.seek(SeekFrom::Start(0)).map_err(|e| Error::io(path, e))?;
        if !interlaced {
            return png_shrunk(path, source, max_side, check);
        }
    }
    let mut bytes = Vec::new();
    source.take(crate::fsio::MAX_IMAGE_BYTES + 1).read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
    let (format, img) = super::painting::decode_image(path, &bytes)?;
    drop(bytes);
    let (width, height) = (img.width() as usize, img.height() as usize);
    check(width, height)?;
    let mut shrink = Shrink::new(width, height, max_side);
    each_row(path, &img, format, |j, row| shrink.row(j, row))?;
    let f = shrink.f();
    Ok((shrink.finish(), f))
}

fn corrupt_png(path: &Path, e: png::DecodingError) -> Error {
    Error::format(path, format!("corrupt or truncated PNG: {}", e.to_string().split_whitespace().collect::<Vec<_>>().join(" ")))
}

/// Whether the PNG in `source` is interlaced (Adam7 rows come in passes, not in order).
fn png_is_interlaced(path: &Path, source: &mut BufReader<std::fs::File>) -> Result<bool> {
    let reader = png::Decoder::new(source.by_ref()).read_info().map_err(|e| corrupt_png(path, e))?;
    Ok(reader.info().interlaced)
}

/// A non-interlaced PNG decoded a row at a time into a [`Shrink`].
fn png_shrunk(path: &Path, source: BufReader<std::fs::File>, max_side: usize, check: impl FnOnce(usize, usize) -> Result<()>) -> Result<(Painting, usize)> {
    let mut decoder = png::Decoder::new(source);
    // Palettes, grey under 8 bits and tRNS become 8-bit grey or colour with alpha.
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| corrupt_png(path, e))?;
    let (width, height) = (reader.info().width as usize, reader.info().height as usize);
    super::check_decode_size(path, width, height)?;
    check(width, height)?;
    let (colour, depth) = reader.output_color_type();
    let channels = colour.samples();
    let lut = lut8();
    let mut shrink = Shrink::new(width, height, max_side);
    let mut row = Vec::with_capacity(width);
    for j in 0..height {
        let data = reader.next_row().map_err(|e| corrupt_png(path, e))?.ok_or_else(|| {
            Error::format(path, format!("corrupt or truncated PNG: image data ends after row {j} of {height}"))
        })?;
        row.clear();
        if depth == png::BitDepth::Sixteen {
            row.extend(data.data().chunks_exact(2 * channels).map(|px| {
                let mut s = [0u16; 4];
                for (k, b) in px.chunks_exact(2).enumerate() {
                    s[k] = u16::from_be_bytes([b[0], b[1]]);
                }
                texel16(rgba(&s[..channels], u16::MAX))
            }));
        } else {
            row.extend(data.data().chunks_exact(channels).map(|px| texel8(&lut, rgba(px, u8::MAX))));
        }
        shrink.row(j, &row);
    }
    let f = shrink.f();
    Ok((shrink.finish(), f))
}
