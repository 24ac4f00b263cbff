//! The contact sheet: one row per material, columns painting | fit on the painted sphere |
//! bunny | suzanne | teapot. No text, so no font: the order is the documentation.
//!
//! ```text
//!  margin                      group gap
//!  ┌──────┐ ┌──────┐          ┌──────┐ ┌──────┐ ┌──────┐
//!  │paint │ │ fit  │          │bunny │ │suzan.│ │teapot│   row 0
//!  └──────┘ └──────┘          └──────┘ └──────┘ └──────┘
//!   gutter
//!  ┌──────┐ ┌──────┐          ┌──────┐ ┌──────┐ ┌──────┐
//!  │      │ │      │          │      │ │      │ │      │   row 1 ...
//! ```
//!
//! Cells hold images at their own size, unscaled: where an image is opaque the sheet's
//! pixel is the image's pixel, so a contact sheet can be checked against the renders.
//! Unpainted pixels of a painting show a dark checkerboard; the background of a render
//! shows a soft dark backdrop.

use crate::error::{Error, Result};
use crate::images::{Painting, Rgb};
use crate::render::Image;

/// Columns of the sheet.
pub const COLUMNS: usize = 5;
/// Outer margin, pixels.
const MARGIN: usize = 24;
/// Space between neighbouring cells.
const GUTTER: usize = 8;
/// Extra space between the painted sphere (columns 0-1) and the retargets (columns 2-4).
const GROUP_GAP: usize = 24;
/// Page colour (linear).
const PAGE: [f32; 3] = [0.006, 0.0065, 0.008];
/// The render backdrop: a vertical gradient from `BACKDROP_TOP` to `BACKDROP_BOTTOM`.
const BACKDROP_TOP: [f32; 3] = [0.040, 0.042, 0.048];
const BACKDROP_BOTTOM: [f32; 3] = [0.014, 0.015, 0.018];
/// Checkerboard of unpainted pixels: two greys, squares of `CHECK` pixels.
const CHECK_DARK: [f32; 3] = [0.018, 0.018, 0.018];
const CHECK_LIGHT: [f32; 3] = [0.034, 0.034, 0.034];
const CHECK: usize = 8;

/// Where cells go on a sheet of `rows` rows of `cell` × `cell` images.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub rows: usize,
    pub cell: usize,
}

impl Layout {
    /// Width and height of the sheet.
    pub fn size(&self) -> (usize, usize) {
        let w = 2 * MARGIN + COLUMNS * self.cell + (COLUMNS - 1) * GUTTER + GROUP_GAP;
        let h = 2 * MARGIN + self.rows * self.cell + self.rows.saturating_sub(1) * GUTTER;
        (w, h)
    }

    /// Top-left pixel of the cell in `row`, `col`.
    pub fn origin(&self, row: usize, col: usize) -> (usize, usize) {
        let x = MARGIN + col * (self.cell + GUTTER) + if col >= 2 { GROUP_GAP } else { 0 };
        let y = MARGIN + row * (self.cell + GUTTER);
        (x, y)
    }
}

/// What a cell shows.
#[derive(Clone, Copy, Debug)]
pub enum Tile<'a> {
    /// A painting: its alpha-0 pixels show the checkerboard.
    Painting(&'a Painting),
    /// A render: its background (alpha 0) shows the backdrop.
    Render(&'a Image),
}

impl Tile<'_> {
    fn size(&self) -> (usize, usize) {
        match self {
            Tile::Painting(p) => (p.width, p.height),
            Tile::Render(r) => (r.width, r.height),
        }
    }

    /// The colour and coverage at pixel `k`.
    fn at(&self, k: usize) -> ([f32; 3], f32) {
        match self {
            Tile::Painting(p) => (p.pixels[k], p.alpha[k].clamp(0.0, 1.0)),
            Tile::Render(r) => {
                let [red, g, b, a] = r.pixels[k];
                ([red, g, b], a.clamp(0.0, 1.0))
            }
        }
    }
}

fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [0, 1, 2].map(|c| a[c] * (1.0 - t) + b[c] * t)
}

/// The sheet of `rows` (each of [`COLUMNS`] tiles, all `cell` × `cell`), linear RGB.
pub fn compose(cell: usize, rows: &[Vec<Tile>]) -> Result<Rgb> {
    let layout = Layout { rows: rows.len(), cell };
    let (w, h) = layout.size();
    let mut out = Rgb::new(w, h)?;
    out.pixels.fill(PAGE);
    for (r, row) in rows.iter().enumerate() {
        if row.len() != COLUMNS {
            return Err(Error::input(format!("contact sheet row {r} has {} tiles, not {COLUMNS}", row.len())));
        }
        for (c, tile) in row.iter().enumerate() {
            if tile.size() != (cell, cell) {
                let (tw, th) = tile.size();
                return Err(Error::input(format!("contact sheet tile ({r}, {c}) is {tw}x{th}, not {cell}x{cell}")));
            }
            let (x0, y0) = layout.origin(r, c);
            for j in 0..cell {
                let backdrop = mix(BACKDROP_TOP, BACKDROP_BOTTOM, j as f32 / (cell - 1).max(1) as f32);
                for i in 0..cell {
                    let (colour, alpha) = tile.at(j * cell + i);
                    let under = match tile {
                        Tile::Painting(_) if (i / CHECK + j / CHECK) % 2 == 0 => CHECK_DARK,
                        Tile::Painting(_) => CHECK_LIGHT,
                        Tile::Render(_) => backdrop,
                    };
                    // Opaque pixels are copied exactly (no rounding through the mix).
                    out.pixels[(y0 + j) * w + x0 + i] = if alpha >= 1.0 { colour } else { mix(under, colour, alpha) };
                }
            }
        }
    }
    Ok(out)
}

/// `image` shrunk by an integer `factor`: each output pixel is the mean of a
/// `factor` × `factor` block (in linear light, so edges stay the right brightness).
pub fn downsample(image: &Rgb, factor: usize) -> Result<Rgb> {
    let factor = factor.max(1);
    let (w, h) = (image.width / factor, image.height / factor);
    let mut out = Rgb::new(w.max(1), h.max(1))?;
    let n = (factor * factor) as f32;
    for j in 0..h {
        for i in 0..w {
            let mut sum = [0.0f32; 3];
            for dj in 0..factor {
                for di in 0..factor {
                    let p = image.pixels[(j * factor + dj) * image.width + i * factor + di];
                    for c in 0..3 {
                        sum[c] += p[c];
                    }
                }
            }
            out.pixels[j * out.width + i] = sum.map(|s| s / n);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_do_not_overlap_and_fit() {
        let layout = Layout { rows: 3, cell: 16 };
        let (w, h) = layout.size();
        let mut seen = vec![false; w * h];
        for r in 0..3 {
            for c in 0..COLUMNS {
                let (x, y) = layout.origin(r, c);
                assert!(x + 16 <= w - MARGIN + 1 && y + 16 <= h - MARGIN + 1);
                for j in 0..16 {
                    for i in 0..16 {
                        assert!(!seen[(y + j) * w + x + i], "cells overlap at ({r}, {c})");
                        seen[(y + j) * w + x + i] = true;
                    }
                }
            }
        }
        assert_eq!(layout.origin(0, 2).0 - layout.origin(0, 1).0, 16 + GUTTER + GROUP_GAP);
    }

    #[test]
    fn opaque_pixels_are_copied_and_transparent_ones_show_the_backdrop() {
        let cell = 4;
        let mut img = Image { width: cell, height: cell, pixels: vec![[0.0; 4]; cell * cell] };
        img.pixels[5] = [0.25, 0.5, 0.75, 1.0];
        let mut painting = Painting::opaque(cell, cell, vec![[0.1, 0.2, 0.3]; cell * cell]).unwrap();
        painting.alpha[0] = 0.0;
        let row = vec![
            Tile::Painting(&painting),
            Tile::Render(&img),
            Tile::Render(&img),
            Tile::Render(&img),
            Tile::Render(&img),
        ];
        let sheet = compose(cell, &[row]).unwrap();
        let (x, y) = Layout { rows: 1, cell }.origin(0, 3);
        assert_eq!(sheet.pixels[(y + 1) * sheet.width + x + 1], [0.25, 0.5, 0.75]);
        assert_eq!(sheet.pixels[y * sheet.width + x], BACKDROP_TOP);
        let (x, y) = Layout { rows: 1, cell }.origin(0, 0);
        assert_eq!(sheet.pixels[y * sheet.width + x], CHECK_DARK);
        assert_eq!(sheet.pixels[y * sheet.width + x + 1], [0.1, 0.2, 0.3]);
        let small = downsample(&sheet, 2).unwrap();
        assert_eq!((small.width, small.height), (sheet.width / 2, sheet.height / 2));
    }
}
