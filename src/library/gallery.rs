//! `LIB/gallery.png`: one row per material, the picture beside its material on the bunny
//! under its key light and under the key light turned to the other side; each row also on
//! its own as `LIB/rows/NAME.png` (what the index shows).
//!
//! A row is a label band ([`BAND`] pixels: the name and the fit's relative RMS error) over
//! three [`CELL`]-pixel squares: the picture, box-filtered to fit the square (its alpha
//! composited over [`BACKGROUND`]); the bunny under the key light; the bunny under the moved
//! light. The bunny is rendered at twice the cell and box-filtered down, for smooth edges.

use std::path::Path;

use glam::{DVec3, Quat, Vec3};

use super::Fitted;
use crate::error::{Error, Result};
use crate::gl::HeadlessContext;
use crate::images::text::Label;
use crate::images::{Painting, Rgb};
use crate::material::Material;
use crate::render::{GpuScene, Renderer};
use crate::scene::{builtin_model, frame, Light, Preset, Scene};

/// Side of a cell, pixels.
pub const CELL: usize = 128;
/// Height of a row's label band, pixels.
pub const BAND: usize = 16;
/// Cells per row: the picture and two renders.
pub const CELLS: usize = 3;
/// Behind the pictures and the renders (linear; sRGB code 39).
pub const BACKGROUND: [f32; 3] = [0.02, 0.02, 0.02];
/// How far the moved light turns from the key light about the view's vertical, degrees.
pub const TURN_DEG: f32 = 90.0;
/// Renders are drawn at this many times the cell and box-filtered down.
const SUPERSAMPLE: usize = 2;

/// Most rows in one column of the gallery: more go on in further columns to the right, so a
/// library of thousands stays within an image's 32768 pixels a side.
pub const ROWS_PER_COLUMN: usize = 200;

/// The gallery's size for `rows` materials: a column of rows ([`CELLS`] cells wide, a band
/// and a cell high) per [`ROWS_PER_COLUMN`].
pub fn size(rows: usize) -> (usize, usize) {
    (rows.div_ceil(ROWS_PER_COLUMN) * CELLS * CELL, rows.min(ROWS_PER_COLUMN) * (BAND + CELL))
}

/// Where row `k`'s top-left corner is in the gallery.
pub fn row_origin(k: usize) -> (usize, usize) {
    ((k / ROWS_PER_COLUMN) * CELLS * CELL, (k % ROWS_PER_COLUMN) * (BAND + CELL))
}

/// The moved light: `key` turned [`TURN_DEG`] about the view's vertical axis, towards the
/// other side of the picture (a light from the left moves to the right, and back).
pub fn moved_light(key: DVec3) -> Vec3 {
    let key = key.as_vec3();
    let turn = if key.x <= 0.0 { TURN_DEG } else { -TURN_DEG };
    Quat::from_rotation_y(turn.to_radians()) * key
}

/// Writes `dir/gallery.png` and `dir/rows/NAME.png` for the materials in `dir/NAME/`.
pub fn write(dir: &Path, fitted: &[Fitted]) -> Result<()> {
    let ctx = HeadlessContext::new()?;
    let mut renderer = Renderer::new(ctx.gl())?;
    let scene = bunny_scene()?;
    let mut gpu = GpuScene::upload(ctx.gl(), &scene)?;
    let rows_dir = dir.join(super::ROWS);
    std::fs::create_dir_all(&rows_dir).map_err(|e| Error::io(&rows_dir, e))?;
    let (w, h) = size(fitted.len());
    let mut gallery = Rgb::new(w, h)?;
    for (k, f) in fitted.iter().enumerate() {
        let mut row = Rgb::new(CELLS * CELL, BAND + CELL)?;
        label(&mut row, f);
        let (picture, _) = Painting::read_shrunk(&f.picture, 4 * CELL, |_, _| Ok(()))?;
        paste(&mut row, &picture_cell(&picture), 0, BAND);
        let material = Material::load(&dir.join(&f.name))?;
        let shading = renderer.upload(&material)?;
        for (c, light) in [f.light.as_vec3(), moved_light(f.light)].into_iter().enumerate() {
            let towards = scene.camera.world_from_camera.transform_vector3(light).normalize();
            gpu.light = Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 };
            let side = SUPERSAMPLE * CELL;
            let image = renderer.factored(&gpu, &shading, side, side)?;
            let over: Vec<[f32; 3]> = image.pixels.iter().map(|p| over_background([p[0], p[1], p[2]], p[3])).collect();
            let cell = Rgb { width: CELL, height: CELL, pixels: area_resample(&over, side, side, CELL, CELL) };
            paste(&mut row, &cell, (c + 1) * CELL, BAND);
        }
        let (x, y) = row_origin(k);
        paste(&mut gallery, &row, x, y);
        row.write_png(&rows_dir.join(format!("{}.png", f.name)))?;
    }
    gallery.write_png(&dir.join(super::GALLERY))
}

/// The row's label: the name and the fit's relative RMS error, clipped to the row.
fn label(row: &mut Rgb, f: &Fitted) {
    let label = Label::new(1);
    let fits = (row.width - 2 * label.pad) / crate::images::text::ADVANCE;
    let text = crate::images::text::clip(&format!("{}  rel. RMS {:.3}", f.name, f.errors.rms_relative), fits);
    label.draw(row, 0, (BAND - label.height()) / 2, &text);
}

/// The bunny seen from the front (a little above, as the standard views); its light is set
/// per render.
fn bunny_scene() -> Result<Scene> {
    let preset = Preset { name: "library", description: "", view_azimuth_deg: 0.0, view_elevation_deg: 10.0, light_in_view: [0.0, 0.0, 1.0] };
    Ok(frame(builtin_model("bunny")?, &preset, 1.0))
}

/// The picture in a [`CELL`]² square: box-filtered to fit (aspect kept, centred), its
/// alpha composited over [`BACKGROUND`].
pub fn picture_cell(p: &Painting) -> Rgb {
    let over: Vec<[f32; 3]> = p.pixels.iter().zip(&p.alpha).map(|(c, &a)| over_background(*c, a)).collect();
    let scale = CELL as f64 / p.width.max(p.height) as f64;
    let (w, h) = (((p.width as f64 * scale).round() as usize).clamp(1, CELL), ((p.height as f64 * scale).round() as usize).clamp(1, CELL));
    let fitted = area_resample(&over, p.width, p.height, w, h);
    let mut cell = Rgb { width: CELL, height: CELL, pixels: vec![BACKGROUND; CELL * CELL] };
    paste(&mut cell, &Rgb { width: w, height: h, pixels: fitted }, (CELL - w) / 2, (CELL - h) / 2);
    cell
}

fn over_background(c: [f32; 3], a: f32) -> [f32; 3] {
    [0, 1, 2].map(|k| c[k] * a + BACKGROUND[k] * (1.0 - a))
}

/// `src` (`sw` × `sh`) resampled to `dw` × `dh` by area: each output pixel is the mean of
/// the source area it covers, partial pixels weighted by the part covered.
pub fn area_resample(src: &[[f32; 3]], sw: usize, sh: usize, dw: usize, dh: usize) -> Vec<[f32; 3]> {
    let xs = spans(sw, dw);
    let ys = spans(sh, dh);
    let mut out = vec![[0.0f32; 3]; dw * dh];
    for (j, ycov) in ys.iter().enumerate() {
        for (i, xcov) in xs.iter().enumerate() {
            let mut sum = [0.0f64; 3];
            let mut weight = 0.0f64;
            for &(y, wy) in ycov {
                for &(x, wx) in xcov {
                    let c = src[y * sw + x];
                    let w = wx * wy;
                    (0..3).for_each(|k| sum[k] += w * c[k] as f64);
                    weight += w;
                }
            }
            out[j * dw + i] = sum.map(|s| (s / weight) as f32);
        }
    }
    out
}

/// Per output pixel of a `d`-pixel axis over an `s`-pixel one, the source pixels it covers
/// and by how much.
fn spans(s: usize, d: usize) -> Vec<Vec<(usize, f64)>> {
    let step = s as f64 / d as f64;
    (0..d)
        .map(|i| {
            let (a, b) = (i as f64 * step, (i + 1) as f64 * step);
            let first = a.floor() as usize;
            let last = (b.ceil() as usize).min(s);
            (first..last).map(|x| (x, (b.min(x as f64 + 1.0) - a.max(x as f64)).max(0.0))).filter(|&(_, w)| w > 0.0).collect()
        })
        .collect()
}

/// Copies `src` into `dst` with its top-left at (`x`, `y`), clipped to `dst`.
fn paste(dst: &mut Rgb, src: &Rgb, x: usize, y: usize) {
    for j in 0..src.height.min(dst.height.saturating_sub(y)) {
        for i in 0..src.width.min(dst.width.saturating_sub(x)) {
            dst.pixels[(y + j) * dst.width + x + i] = src.pixels[j * src.width + i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_resampling_averages_what_each_pixel_covers() {
        // Three pixels into two: the middle one splits in halves.
        let src = [[0.0; 3], [3.0; 3], [6.0; 3]];
        let out = area_resample(&src, 3, 1, 2, 1);
        assert!((out[0][0] - 1.0).abs() < 1e-6 && (out[1][0] - 5.0).abs() < 1e-6, "{out:?}");
        // Upscaling repeats.
        assert_eq!(area_resample(&[[1.0; 3], [2.0; 3]], 2, 1, 4, 1), [[1.0; 3], [1.0; 3], [2.0; 3], [2.0; 3]]);
    }

    #[test]
    fn a_long_gallery_goes_on_in_columns() {
        assert_eq!(size(3), (CELLS * CELL, 3 * (BAND + CELL)));
        assert_eq!(size(450), (3 * CELLS * CELL, ROWS_PER_COLUMN * (BAND + CELL)));
        assert_eq!(row_origin(201), (CELLS * CELL, BAND + CELL));
        assert!(size(10_000).1 <= 1 << 15);
    }

    #[test]
    fn the_moved_light_goes_to_the_other_side() {
        let m = moved_light(DVec3::new(-0.5, 0.5, 0.7).normalize());
        assert!(m.x > 0.5 && m.z > 0.0, "{m}");
        let m = moved_light(DVec3::new(0.0, 0.0, 1.0));
        assert!((m - Vec3::X).length() < 1e-5, "{m}");
    }
}
