//! The contact sheet: one row per material, columns painting | fit in the painted view |
//! bunny | suzanne | teapot, with words: the columns' names along the top, and above each
//! row its material's name and what it was painted from.
//!
//! ```text
//!  margin
//!     painting    fit, painted view         bunny     suzanne     teapot       header
//!  plastic  Blinn-Phong, n = 40, painted in sheet/                              title
//!  ┌──────┐ ┌──────┐          ┌──────┐ ┌──────┐ ┌──────┐
//!  │paint │ │ fit  │          │bunny │ │suzan.│ │teapot│   row 0
//!  └──────┘ └──────┘          └──────┘ └──────┘ └──────┘
//!   gutter           group gap                                                  row gap
//!  gooch  ...                                                                   title
//!  ┌──────┐ ┌──────┐          ┌──────┐ ┌──────┐ ┌──────┐
//!  │      │ │      │          │      │ │      │ │      │   row 1 ...
//! ```
//!
//! Cells hold images at their own size, unscaled: where an image is opaque the sheet's
//! pixel is the image's pixel, so a contact sheet can be checked against the renders.
//! Unpainted pixels of a painting show a dark checkerboard; the background of a render
//! shows a soft dark backdrop. Words are [`text`] labels at scale 2 on dark boxes, in the
//! margins and strips between cells, never over a picture; every position is even, so the
//! half-size sheet ([`downsample`] by 2) carries the same words at scale 1, still sharp.

use crate::error::{Error, Result};
use crate::images::text::{self, Label};
use crate::images::{Painting, Rgb};
use crate::render::Image;

/// Columns of the sheet.
pub const COLUMNS: usize = 5;
/// Outer margin, pixels.
const MARGIN: usize = 24;
/// Space between neighbouring cells of a row.
const GUTTER: usize = 8;
/// Extra space between the painted sphere (columns 0-1) and the retargets (columns 2-4).
const GROUP_GAP: usize = 24;
/// Space between one row's cells and the next row's title: more than between a title and
/// its own cells, so each title reads as its row's.
const ROW_GAP: usize = 16;
/// The labels: the font at twice its size, light on near black.
pub const LABEL: Label = Label::new(2);
/// Space between a row's title and its cells.
const TITLE_GAP: usize = 4;
/// Height of the column names and the space below them.
const HEADER: usize = LABEL.height() + 12;
/// Page colour (linear).
const PAGE: [f32; 3] = [0.006, 0.0065, 0.008];
/// The render backdrop: a vertical gradient from `BACKDROP_TOP` to `BACKDROP_BOTTOM`.
const BACKDROP_TOP: [f32; 3] = [0.040, 0.042, 0.048];
const BACKDROP_BOTTOM: [f32; 3] = [0.014, 0.015, 0.018];
/// Checkerboard of unpainted pixels: two greys, squares of `CHECK` pixels.
const CHECK_DARK: [f32; 3] = [0.018, 0.018, 0.018];
const CHECK_LIGHT: [f32; 3] = [0.034, 0.034, 0.034];
const CHECK: usize = 8;

/// Where cells and labels go on a sheet of `rows` rows of `cell` × `cell` images.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    pub rows: usize,
    pub cell: usize,
}

impl Layout {
    /// Width and height of the sheet.
    pub fn size(&self) -> (usize, usize) {
        let w = 2 * MARGIN + COLUMNS * self.cell + (COLUMNS - 1) * GUTTER + GROUP_GAP;
        let h = 2 * MARGIN
            + HEADER
            + self.rows * (LABEL.height() + TITLE_GAP + self.cell)
            + self.rows.saturating_sub(1) * ROW_GAP;
        (w, h)
    }

    /// Top-left pixel of the cell in `row`, `col`.
    pub fn origin(&self, row: usize, col: usize) -> (usize, usize) {
        let x = MARGIN + col * (self.cell + GUTTER) + if col >= 2 { GROUP_GAP } else { 0 };
        let (_, title_y) = self.title(row);
        (x, title_y + LABEL.height() + TITLE_GAP)
    }

    /// Top-left pixel of the box of `row`'s title (its material's name first).
    pub fn title(&self, row: usize) -> (usize, usize) {
        let pitch = LABEL.height() + TITLE_GAP + self.cell + ROW_GAP;
        (MARGIN, MARGIN + HEADER + row * pitch)
    }

    /// Top-left pixel of the box of column `col`'s name `text` (centred over the column,
    /// at an even pixel).
    pub fn header(&self, col: usize, text: &str) -> (usize, usize) {
        let (x, _) = self.origin(0, col);
        let (w, _) = LABEL.size(text);
        ((x + self.cell.saturating_sub(w) / 2) & !1, MARGIN)
    }

    /// Most characters of a label that fit in `width` pixels.
    fn chars_in(width: usize) -> usize {
        (width + LABEL.scale).saturating_sub(2 * LABEL.pad) / (text::ADVANCE * LABEL.scale)
    }
}

/// One row of the sheet: its title (the material's name, then a caption in dimmer ink) and
/// its [`COLUMNS`] tiles.
#[derive(Clone, Debug)]
pub struct Row<'a> {
    pub name: String,
    pub caption: String,
    pub tiles: Vec<Tile<'a>>,
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

/// The sheet of `rows` (each of [`COLUMNS`] tiles, all `cell` × `cell`) under the column
/// names `columns`, linear RGB. Labels too long for their place are cut with an ellipsis.
pub fn compose(cell: usize, columns: &[&str; COLUMNS], rows: &[Row]) -> Result<Rgb> {
    let layout = Layout { rows: rows.len(), cell };
    let (w, h) = layout.size();
    let mut out = Rgb::new(w, h)?;
    out.pixels.fill(PAGE);
    for (c, name) in columns.iter().enumerate() {
        let name = text::clip(name, Layout::chars_in(cell));
        let (x, y) = layout.header(c, &name);
        LABEL.draw(&mut out, x, y, &name);
    }
    for (r, row) in rows.iter().enumerate() {
        if row.tiles.len() != COLUMNS {
            return Err(Error::input(format!("contact sheet row {r} has {} tiles, not {COLUMNS}", row.tiles.len())));
        }
        let (x, y) = layout.title(r);
        let name = text::clip(&row.name, Layout::chars_in(w - MARGIN - x));
        let (name_w, _) = LABEL.draw(&mut out, x, y, &name);
        let caption = text::clip(&format!(" {}", row.caption), Layout::chars_in((w - MARGIN).saturating_sub(x + name_w)));
        LABEL.ink(text::INK_DIM).draw(&mut out, x + name_w, y, &caption);
        for (c, tile) in row.tiles.iter().enumerate() {
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

    fn row<'a>(name: &str, tiles: Vec<Tile<'a>>) -> Row<'a> {
        Row { name: name.into(), caption: "painted in sheet/".into(), tiles }
    }

    /// Whether the `scale`d glyph of `c` is at `(x, y)` of `image`: ink where its bits are
    /// set, the label's box elsewhere.
    fn glyph_at(image: &Rgb, x: usize, y: usize, c: char, scale: usize) -> bool {
        let bits = text::glyph(c);
        (0..text::GLYPH_HEIGHT * scale).all(|j| {
            (0..text::GLYPH_WIDTH * scale).all(|i| {
                let set = bits[j / scale] >> (text::GLYPH_WIDTH - 1 - i / scale) & 1 == 1;
                let want = if set { text::INK } else { text::BACKING };
                // Shrinking averages four equal values: equal within rounding.
                (0..3).all(|k| (image.pixels[(y + j) * image.width + x + i][k] - want[k]).abs() < 1e-6)
            })
        })
    }

    #[test]
    fn cells_and_labels_do_not_overlap_and_fit() {
        let layout = Layout { rows: 3, cell: 16 };
        let (w, h) = layout.size();
        let mut seen = vec![false; w * h];
        for r in 0..3 {
            for c in 0..COLUMNS {
                let (x, y) = layout.origin(r, c);
                assert!(x + 16 <= w - MARGIN && y + 16 <= h - MARGIN, "cell ({r}, {c}) in the margin");
                for j in 0..16 {
                    for i in 0..16 {
                        assert!(!seen[(y + j) * w + x + i], "cells overlap at ({r}, {c})");
                        seen[(y + j) * w + x + i] = true;
                    }
                }
            }
        }
        // Titles and column names sit on rows of pixels that no cell uses, at even pixels.
        let free = |y: usize| (0..w).all(|x| !seen[y * w + x]);
        for r in 0..3 {
            let (x, y) = layout.title(r);
            assert!((y..y + LABEL.height()).all(free), "title of row {r} over a cell");
            assert_eq!((x % 2, y % 2), (0, 0));
            assert_eq!(layout.origin(r, 0).1, y + LABEL.height() + TITLE_GAP);
        }
        let (x, y) = layout.header(3, "suzanne");
        assert!((y..y + LABEL.height()).all(free) && y + LABEL.height() < layout.title(0).1);
        assert_eq!((x % 2, y % 2, w % 2, h % 2), (0, 0, 0, 0));
        assert_eq!(layout.origin(0, 2).0 - layout.origin(0, 1).0, 16 + GUTTER + GROUP_GAP);
    }

    #[test]
    fn opaque_pixels_are_copied_and_transparent_ones_show_the_backdrop() {
        let cell = 4;
        let mut img = Image { width: cell, height: cell, pixels: vec![[0.0; 4]; cell * cell] };
        img.pixels[5] = [0.25, 0.5, 0.75, 1.0];
        let mut painting = Painting::opaque(cell, cell, vec![[0.1, 0.2, 0.3]; cell * cell]).unwrap();
        painting.alpha[0] = 0.0;
        let tiles = vec![
            Tile::Painting(&painting),
            Tile::Render(&img),
            Tile::Render(&img),
            Tile::Render(&img),
            Tile::Render(&img),
        ];
        let sheet = compose(cell, &["a", "b", "c", "d", "e"], &[row("x", tiles)]).unwrap();
        let (x, y) = Layout { rows: 1, cell }.origin(0, 3);
        assert_eq!(sheet.pixels[(y + 1) * sheet.width + x + 1], [0.25, 0.5, 0.75]);
        assert_eq!(sheet.pixels[y * sheet.width + x], BACKDROP_TOP);
        let (x, y) = Layout { rows: 1, cell }.origin(0, 0);
        assert_eq!(sheet.pixels[y * sheet.width + x], CHECK_DARK);
        assert_eq!(sheet.pixels[y * sheet.width + x + 1], [0.1, 0.2, 0.3]);
        let small = downsample(&sheet, 2).unwrap();
        assert_eq!((small.width, small.height), (sheet.width / 2, sheet.height / 2));
    }

    #[test]
    fn titles_and_column_names_are_drawn_where_the_layout_puts_them() {
        let cell = 96;
        let img = Image { width: cell, height: cell, pixels: vec![[0.0; 4]; cell * cell] };
        let rows: Vec<Row> = ["plastic", "gooch"].iter().map(|n| row(n, vec![Tile::Render(&img); COLUMNS])).collect();
        let columns = ["painting", "fit", "bunny", "suzanne, new light", "teapot"];
        let sheet = compose(cell, &columns, &rows).unwrap();
        let layout = Layout { rows: 2, cell };
        let (x, y) = LABEL.text_origin(layout.title(1).0, layout.title(1).1);
        assert!(glyph_at(&sheet, x, y, 'g', 2), "no 'g' at the start of row 1's title");
        assert!(!glyph_at(&sheet, x, y, 'p', 2), "the test tells letters apart");
        // The second letter follows one advance later.
        assert!(glyph_at(&sheet, x + text::ADVANCE * 2, y, 'o', 2));
        let (hx, hy) = layout.header(4, "teapot");
        let (hx, hy) = LABEL.text_origin(hx, hy);
        assert!(glyph_at(&sheet, hx, hy, 't', 2), "no 't' of \"teapot\" over column 4");
        // Too long for a 96-pixel column at scale 2 (7 characters fit): cut.
        let (sx, sy) = layout.header(3, "suzann…");
        let (sx, sy) = LABEL.text_origin(sx, sy);
        assert!(glyph_at(&sheet, sx, sy, 's', 2) && glyph_at(&sheet, sx + 6 * text::ADVANCE * 2, sy, '…', 2));
        // Half size: the same words at scale 1, at half the coordinates.
        let small = downsample(&sheet, 2).unwrap();
        assert!(glyph_at(&small, x / 2, y / 2, 'g', 1) && glyph_at(&small, hx / 2, hy / 2, 't', 1));
    }
}
