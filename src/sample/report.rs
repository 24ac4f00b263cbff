//! The fit report: per view, the painting, the fitted material at the same pixels, and the
//! residual, side by side (`report.png` beside a fitted material), with words.
//!
//! ```text
//!  painting          fit               residual ×4            panel names
//!  view 1: paintings/p.png in sheet/scene.gltf                 a title per view
//!  ┌──────────┐      ┌──────────┐      ┌──────────┐
//!  │          │      │          │      │          │
//!  └──────────┘      └──────────┘      └──────────┘
//!  ■ on the object, not a sample   ■ background   ▦ unpainted  legend
//!  |fit − painting|  0 ▁▂▃▄▅▆▇█ 0.25 or more
//! ```
//!
//! The fit panel is the CPU evaluation of the material (its [`Reflectance::shading`](crate::brdf::Reflectance), the reference
//! the GL factored pass is tested against) at each pixel's G-buffer query, times the
//! light that reaches the pixel: what the scene shows with the material applied. The
//! residual panel shows $4\,|\text{fit} - \text{painting}|$ per channel at the samples
//! ([`residual_colour`]); pixels on the object that are not samples (silhouette band,
//! unpainted, back-facing) are dark blue, background is black. Unpainted pixels of the
//! painting show a grey checkerboard. The legend says so, with a scale bar of the residual's
//! colours from 0 to $1/4$ (white: a quarter or more). Words are [`text`] labels in strips
//! between the panels, never over them.

use super::{PaintedView, Samples};
use crate::brdf::Reflectance;
use crate::error::Result;
use crate::factor::{errors, Errors};
use crate::images::text::{self, Label};
use crate::images::Rgb;
use crate::material::Material;

/// Gain of the residual panel.
pub const RESIDUAL_GAIN: f32 = 4.0;
/// Residual-panel colour of object pixels that are not samples.
pub const NOT_A_SAMPLE: [f32; 3] = [0.0, 0.0, 0.03];
/// Residual-panel and fit-panel colour of the background.
pub const BACKGROUND: [f32; 3] = [0.0; 3];
/// Checkerboard of a painting's unpainted pixels: two greys, squares of 8 pixels.
const CHECK: [[f32; 3]; 2] = [[0.15; 3], [0.3; 3]];
/// Page colour between the panels.
const PAGE: [f32; 3] = [0.5; 3];
/// Pixels between panels and rows.
const GAP: usize = 4;
/// The panels' names.
pub const PANELS: [&str; 3] = ["painting", "fit", "residual ×4"];

/// What the residual panel shows at a sample: $4\,|\text{fit} - \text{painting}|$ per
/// channel (a PNG clips it at 1, so errors of a quarter or more are white).
pub fn residual_colour(fit: [f32; 3], painting: [f32; 3]) -> [f32; 3] {
    [0, 1, 2].map(|c| RESIDUAL_GAIN * (fit[c] - painting[c]).abs())
}

/// Errors of `material` against each view's samples, in shading-function units (thesis
/// Table 5.4's metrics: RMS, relative RMS, max).
pub fn view_errors(samples: &Samples, views: &[PaintedView], material: &Material) -> Vec<Errors> {
    (0..views.len())
        .map(|v| {
            let (mut predicted, mut values) = (Vec::new(), Vec::new());
            for (s, &(view, _)) in samples.origin.iter().enumerate() {
                if view == v {
                    predicted.push(material.shading(&samples.pattern.queries[s]));
                    values.push(samples.values[s]);
                }
            }
            errors(&predicted, &values)
        })
        .collect()
}

/// Where things go on a report of views of at most `w` pixels across.
#[derive(Clone, Debug, PartialEq)]
struct Page {
    label: Label,
    /// Left edge of each panel (the first is the margin: where every title starts).
    panel_x: [usize; 3],
    /// Top of the panels' names, then per view the top of its title and of its panels.
    names_y: usize,
    title_y: Vec<usize>,
    panel_y: Vec<usize>,
    legend: Legend,
    /// Top-left of the legend.
    legend_at: (usize, usize),
    size: (usize, usize),
}

impl Page {
    fn new(views: &[PaintedView]) -> Page {
        let w = views.iter().map(|v| v.geometry.width).max().unwrap_or(1);
        // Words at twice the font's size where the panels are wide enough for it.
        let label = Label::new(if w >= 160 { 2 } else { 1 });
        let margin = 4 * label.scale;
        let panel_x = [0, 1, 2].map(|k| margin + k * (w + GAP));
        let mut y = margin + label.height() + GAP;
        let (mut title_y, mut panel_y) = (Vec::new(), Vec::new());
        for v in views {
            title_y.push(y);
            y += label.height() + GAP;
            panel_y.push(y);
            y += v.geometry.height + GAP;
        }
        let legend = Legend::new(label);
        let legend_at = (margin, y + GAP);
        let size = ((3 * w + 2 * GAP).max(legend.size.0) + 2 * margin, legend_at.1 + legend.size.1 + margin);
        Page { label, panel_x, names_y: margin, title_y, panel_y, legend, legend_at, size }
    }
}

/// The legend, at (0, 0): a line of swatches with what they mean, and a scale bar of the
/// residual's colours.
#[derive(Clone, Debug, PartialEq)]
struct Legend {
    label: Label,
    /// Each swatch's left edge on the first line, its colours (two: a checkerboard) and words.
    swatches: Vec<(usize, [[f32; 3]; 2], &'static str)>,
    /// Left edge, top, width and height of the scale bar.
    bar: (usize, usize, usize, usize),
    size: (usize, usize),
}

/// What the scale bar's left and right ends and its name say.
const BAR_WORDS: [&str; 3] = ["|fit − painting|", "0", "0.25 or more"];

impl Legend {
    fn new(label: Label) -> Legend {
        let h = label.height();
        let space = 4 * label.scale;
        let mut x = 0;
        let mut swatches = Vec::new();
        for (colours, words) in [
            ([NOT_A_SAMPLE; 2], "on the object, not a sample"),
            ([BACKGROUND; 2], "background"),
            (CHECK, "unpainted"),
        ] {
            swatches.push((x, colours, words));
            x += h + label.size(words).0 + 2 * space;
        }
        let line = x - 2 * space;
        let y = h + GAP;
        let bar_x = label.size(BAR_WORDS[0]).0 + space + label.size(BAR_WORDS[1]).0 + GAP;
        // 129 columns per scale step: the bar's steps are 1/128 of a quarter.
        let bar_w = 128 * label.scale + 1;
        let end = bar_x + bar_w + GAP + label.size(BAR_WORDS[2]).0;
        Legend { label, swatches, bar: (bar_x, y, bar_w, h), size: (line.max(end), y + h) }
    }

    /// The error $|\text{fit} - \text{painting}|$ the bar shows at column `i` (0 at its left).
    fn error_at(&self, i: usize) -> f32 {
        i as f32 / (self.bar.2 - 1) as f32 / RESIDUAL_GAIN
    }

    fn draw(&self, out: &mut Rgb, x0: usize, y0: usize) {
        let (label, h) = (self.label, self.label.height());
        for &(x, colours, words) in &self.swatches {
            for j in 0..h {
                for i in 0..h {
                    // A swatch of two colours is the checkerboard, at the panel's own size.
                    text::fill(out, x0 + x + i, y0 + j, 1, 1, colours[(i / 8 + j / 8) % 2]);
                }
            }
            label.draw(out, x0 + x + h + GAP, y0, words);
        }
        let (bx, by, bw, bh) = self.bar;
        let (w, _) = label.draw(out, x0, y0 + by, BAR_WORDS[0]);
        label.draw(out, x0 + w + 4 * label.scale, y0 + by, BAR_WORDS[1]);
        for i in 0..bw {
            let e = self.error_at(i);
            text::fill(out, x0 + bx + i, y0 + by, 1, bh, residual_colour([e; 3], [0.0; 3]));
        }
        label.draw(out, x0 + bx + bw + GAP, y0 + by, BAR_WORDS[2]);
    }
}

/// The report image (linear RGB): the panels' names, then per view its title and painting
/// | fit | residual, then the legend.
pub fn image(views: &[PaintedView], material: &Material) -> Result<Rgb> {
    let page = Page::new(views);
    let mut out = Rgb::new(page.size.0, page.size.1)?;
    out.pixels.fill(PAGE);
    let label = page.label;
    for (x, name) in page.panel_x.iter().zip(PANELS) {
        label.draw(&mut out, *x, page.names_y, name);
    }
    for (n, view) in views.iter().enumerate() {
        let g = &view.geometry;
        let p = &view.painting;
        let title = format!("view {}: {} in {}", n + 1, view.name, view.source);
        let room = page.size.0 - 2 * page.panel_x[0];
        let fits = (room + label.scale).saturating_sub(2 * label.pad) / (text::ADVANCE * label.scale);
        label.draw(&mut out, page.panel_x[0], page.title_y[n], &text::clip(&title, fits));
        let top = page.panel_y[n];
        for j in 0..g.height {
            for i in 0..g.width {
                let k = j * g.width + i;
                let painted = if p.painted(k) { p.pixels[k] } else { CHECK[(i / 8 + j / 8) % 2] };
                let (fit, residual) = match g.pixels[k] {
                    None => (BACKGROUND, BACKGROUND),
                    Some(px) => {
                        let s = material.shading(&px.query);
                        let fit = [0, 1, 2].map(|c| (s[c] * px.light[c]) as f32);
                        let residual =
                            if g.usable[k] && p.painted(k) { residual_colour(fit, p.pixels[k]) } else { NOT_A_SAMPLE };
                        (fit, residual)
                    }
                };
                let row = (top + j) * out.width;
                for (x, colour) in page.panel_x.iter().zip([painted, fit, residual]) {
                    out.pixels[row + x + i] = colour;
                }
            }
        }
    }
    page.legend.draw(&mut out, page.legend_at.0, page.legend_at.1);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factor::Query;
    use crate::images::Painting;
    use crate::material::Kind;
    use crate::sample::{Geometry, PixelGeometry};
    use glam::DVec3;

    /// A `w` × `w` view whose left half is object and right half background; of the
    /// object, column 0 is not usable (a silhouette band) and row 0 is unpainted. Its painting
    /// is `value` everywhere.
    fn view(w: usize, value: f32) -> PaintedView {
        let px = PixelGeometry { query: Query::at(DVec3::Z, DVec3::Z), position: None, light: [1.0; 3] };
        let pixels = (0..w * w).map(|k| (k % w < w / 2).then_some(px)).collect();
        let usable = (0..w * w).map(|k| k % w < w / 2 && k % w > 0).collect();
        let geometry = Geometry { width: w, height: w, pixels, usable, left_out: 0, has_uv: false };
        let mut painting = Painting::opaque(w, w, vec![[value; 3]; w * w]).unwrap();
        painting.alpha[..w].fill(0.0);
        PaintedView { name: "paintings/p.png".into(), source: "sheet/scene.gltf".into(), geometry, painting }
    }

    /// A material that shades everything black: the fit is 0, the residual 4 × the painting.
    fn black() -> Material {
        Material::new(Kind::Uniform, vec![])
    }

    fn at(img: &Rgb, x: usize, y: usize) -> [f32; 3] {
        img.pixels[y * img.width + x]
    }

    #[test]
    fn the_legend_scale_runs_from_black_to_white_as_the_residual_panel_does() {
        let error = 0.05;
        let views = [view(200, error)];
        let img = image(&views, &black()).unwrap();
        let page = Page::new(&views);
        let legend = &page.legend;
        let (bx, by, bw, bh) = legend.bar;
        let (x0, y0) = (page.legend_at.0 + bx, page.legend_at.1 + by);
        // Along the bar: grey, never darker to the right, from black (no error) to white (a
        // quarter).
        let bar: Vec<[f32; 3]> = (0..bw).map(|i| at(&img, x0 + i, y0 + bh / 2)).collect();
        assert!(bar.iter().all(|p| p[0] == p[1] && p[1] == p[2]), "the bar is not grey");
        assert!(bar.windows(2).all(|w| w[1][0] >= w[0][0]), "the bar is not monotone: {bar:?}");
        assert_eq!((bar[0][0], bar[bw - 1][0]), (0.0, 1.0));
        assert!(bar.windows(2).filter(|w| w[1][0] > w[0][0]).count() == bw - 1, "the bar has flat steps");
        // A sample with |fit − painting| = 0.05 shows the bar's colour at 0.05 / 0.25 of its
        // width (the fit is black, the painting 0.05).
        let residual = at(&img, page.panel_x[2] + 50, page.panel_y[0] + 50);
        let i = (error / 0.25 * (bw - 1) as f32).round() as usize;
        assert!((residual[0] - bar[i][0]).abs() <= 1.0 / (bw - 1) as f32, "panel {residual:?}, bar {:?} at {i}", bar[i]);
        assert!((legend.error_at(i) - error).abs() < 1e-3);
        // The swatches are the colours the residual panel uses: not a sample (column 0 of the
        // object) and background (the right half).
        let swatch = |n: usize| at(&img, page.legend_at.0 + legend.swatches[n].0 + 2, page.legend_at.1 + 2);
        assert_eq!(at(&img, page.panel_x[2], page.panel_y[0] + 50), NOT_A_SAMPLE);
        assert_eq!(swatch(0), NOT_A_SAMPLE);
        assert_eq!(at(&img, page.panel_x[2] + 150, page.panel_y[0] + 50), BACKGROUND);
        assert_eq!(swatch(1), BACKGROUND);
        assert_eq!(at(&img, page.panel_x[0] + 50, page.panel_y[0]), swatch(2), "unpainted checkerboard");
    }

    #[test]
    fn panels_and_views_are_named_above_them() {
        let views = [view(200, 0.1), view(200, 0.2)];
        let img = image(&views, &black()).unwrap();
        let page = Page::new(&views);
        let label = page.label;
        assert_eq!(label.scale, 2);
        let glyph_at = |x: usize, y: usize, c: char| -> bool {
            let (x, y) = label.text_origin(x, y);
            let bits = text::glyph(c);
            (0..text::GLYPH_HEIGHT * 2).all(|j| {
                (0..text::GLYPH_WIDTH * 2).all(|i| {
                    let set = bits[j / 2] >> (text::GLYPH_WIDTH - 1 - i / 2) & 1 == 1;
                    at(&img, x + i, y + j) == if set { text::INK } else { text::BACKING }
                })
            })
        };
        let y = page.names_y;
        assert!(glyph_at(page.panel_x[0], y, 'p') && glyph_at(page.panel_x[1], y, 'f'));
        assert!(glyph_at(page.panel_x[2], y, 'r') && !glyph_at(page.panel_x[2], y, 'p'));
        assert!(glyph_at(page.panel_x[0], page.title_y[1], 'v'));
        // "view 2": the sixth character.
        assert!(glyph_at(page.panel_x[0] + 5 * text::ADVANCE * 2, page.title_y[1], '2'));
        // Names and titles end above the panels they name.
        assert!(y + label.height() <= page.title_y[0] && page.title_y[1] + label.height() <= page.panel_y[1]);
        assert!(page.panel_y[0] + 200 <= page.title_y[1]);
        assert!(page.panel_y[1] + 200 <= page.legend_at.1);
    }

    #[test]
    fn small_views_get_small_words_and_a_page_wide_enough_for_the_legend() {
        let views = [view(40, 0.1)];
        let img = image(&views, &black()).unwrap();
        let page = Page::new(&views);
        assert_eq!(page.label.scale, 1);
        assert!(img.width >= page.legend.size.0 && img.width > 3 * 40 + 2 * GAP);
        assert_eq!((img.width, img.height), page.size);
    }
}
