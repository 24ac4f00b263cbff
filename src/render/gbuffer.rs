//! The G-buffer (per pixel: coverage, position, local-frame $l$ and $v$, frame, uv) and what
//! is derived from it on the host: the coverage mask and the coloring-book outline.

use glam::{DVec2, DVec3, Vec2, Vec3, Vec4};

use super::Image;
use crate::factor::Query;

/// One pixel of the G-buffer. Everything is what the factored shader computes at the pixel
/// centre (same vertex stage, same `surface()` code), in `f32`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GPixel {
    /// The pixel centre sees the object (and every value below is finite).
    pub hit: bool,
    /// World position.
    pub position: Vec3,
    /// Unit direction toward the light, local frame (x tangent, y bitangent, z normal).
    pub l: Vec3,
    /// Unit direction toward the viewer, local frame.
    pub v: Vec3,
    /// The light's falloff at this point: $1/d^2$ for point lights, 1 for directional ones.
    /// Colour × intensity is not included.
    pub falloff: f32,
    /// Eye-space depth: distance from the camera along its forward axis.
    pub depth: f32,
    /// World-space unit shading normal (interpolated, normalized).
    pub normal: Vec3,
    /// World-space unit tangent (orthogonalized against the normal) and bitangent sign.
    pub tangent: Vec4,
    /// The triangle's world-space plane normal, turned toward the shading normal.
    pub face_normal: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
}

impl GPixel {
    /// The sample this pixel makes, in `f64` (directions renormalized).
    pub fn query(&self) -> Option<Query> {
        self.hit.then(|| Query {
            l: self.l.as_dvec3().normalize_or(DVec3::Z),
            v: self.v.as_dvec3().normalize_or(DVec3::Z),
            uv: DVec2::new(self.uv.x as f64, self.uv.y as f64),
        })
    }
}

/// A `width` × `height` G-buffer, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct GBuffer {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<GPixel>,
}

/// Interior lines (creases, occlusion contours) shorter than this fraction of the image's
/// larger side are dropped: on scanned meshes, triangle noise at grazing angles draws short
/// dashes inside the silhouette that are no part of the shape (the bunny showed a dozen).
const SHORT_LINE: f32 = 0.025;

/// Clears the interior line pixels (`line` and not `outer`) of 8-connected components
/// smaller than `min_len` pixels.
fn drop_short_interior(line: &mut [bool], outer: &[bool], w: usize, min_len: usize) {
    let mut interior: Vec<bool> = line.iter().zip(outer).map(|(&l, &o)| l && !o).collect();
    crate::images::drop_small_components(&mut interior, w, min_len);
    for ((l, &o), &keep) in line.iter_mut().zip(outer).zip(&interior) {
        if !o {
            *l &= keep;
        }
    }
}

/// How the outline is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineStyle {
    /// Line width in pixels. An edge lies between two neighbouring pixels; width 1 draws the
    /// pixel on the object's side (the near side for creases and occlusions), width 2 both,
    /// wider lines grow from there by $(w - 2)/2$ pixels on each side.
    pub width: usize,
    /// Two neighbouring pixels whose triangles' planes meet at more than this angle
    /// (radians) are split by a crease line.
    pub crease_angle: f32,
    /// Two neighbouring pixels are split by an occlusion line when one lies off the other's
    /// triangle plane by more than this fraction of their distance (a depth jump).
    pub depth_jump: f32,
}

impl Default for OutlineStyle {
    fn default() -> Self {
        OutlineStyle { width: 2, crease_angle: 60f32.to_radians(), depth_jump: 0.6 }
    }
}

impl GBuffer {
    /// The pixel at column `i`, row `j` (row 0 at the top).
    pub fn at(&self, i: usize, j: usize) -> &GPixel {
        &self.pixels[j * self.width + i]
    }

    /// Number of pixels that see the object.
    pub fn coverage(&self) -> usize {
        self.pixels.iter().filter(|p| p.hit).count()
    }

    /// The coverage mask: white (1) where the pixel centre sees the object, black (0)
    /// elsewhere; alpha 1.
    pub fn mask(&self) -> Image {
        let pixels = self.pixels.iter().map(|p| if p.hit { [1.0; 4] } else { [0.0, 0.0, 0.0, 1.0] }).collect();
        Image { width: self.width, height: self.height, pixels }
    }

    /// Which pixels carry a line: silhouettes (object against background), creases and
    /// occlusion contours, per `style` ([`LineTracer`] over all rows).
    pub fn lines(&self, style: &OutlineStyle) -> Vec<bool> {
        let mut tracer = LineTracer::new(self.width, self.height, *style);
        tracer.push(&self.pixels);
        tracer.finish()
    }

    /// The coloring-book page (thesis 4.1): black lines on white, alpha 1.
    pub fn outline(&self, style: &OutlineStyle) -> Image {
        let pixels = self.lines(style).into_iter().map(|l| if l { [0.0, 0.0, 0.0, 1.0] } else { [1.0; 4] }).collect();
        Image { width: self.width, height: self.height, pixels }
    }
}

/// Finds the outline's lines ([`GBuffer::lines`]) from the G-buffer's rows given in order,
/// a band at a time: a line lies between two 4-neighbours, so a row is traced as soon as the
/// row below it has come. What it keeps is two bitmaps of the image and one row of pixels,
/// never the whole G-buffer (16 GPixels per line bit): a 4096² sheet's lines need 34 MB,
/// not 1.7 GB.
pub struct LineTracer {
    style: OutlineStyle,
    cos_crease: f32,
    width: usize,
    height: usize,
    line: Vec<bool>,
    /// Pixels whose line is a silhouette (or the image border), which always stays.
    outer: Vec<bool>,
    /// The last row pushed, not yet traced (it waits for the row below), and its index.
    pending: Vec<GPixel>,
    next_row: usize,
}

impl LineTracer {
    pub fn new(width: usize, height: usize, style: OutlineStyle) -> LineTracer {
        let n = width * height;
        LineTracer { style, cos_crease: style.crease_angle.cos(), width, height, line: vec![false; n], outer: vec![false; n], pending: Vec::new(), next_row: 0 }
    }

    /// The next whole rows of the G-buffer, top to bottom (rows past the last are ignored).
    pub fn push(&mut self, rows: &[GPixel]) {
        let w = self.width;
        for row in rows.chunks_exact(w) {
            if self.next_row >= self.height {
                return;
            }
            if self.next_row > 0 {
                let above = std::mem::take(&mut self.pending);
                self.trace_row(self.next_row - 1, &above, Some(row));
                self.pending = above;
            }
            self.pending.clear();
            self.pending.extend_from_slice(row);
            self.next_row += 1;
        }
    }

    /// Traces the last row, drops short interior dashes and widens the lines: the line
    /// bitmap, row 0 at the top (rows never pushed carry no line).
    pub fn finish(mut self) -> Vec<bool> {
        if self.next_row > 0 {
            let last = std::mem::take(&mut self.pending);
            self.trace_row(self.next_row - 1, &last, None);
        }
        let (w, h) = (self.width, self.height);
        drop_short_interior(&mut self.line, &self.outer, w, (w.max(h) as f32 * SHORT_LINE).round() as usize);
        let grow = self.style.width.saturating_sub(2) / 2;
        if grow > 0 {
            self.line = dilate(&self.line, w, h, grow);
        }
        self.line
    }

    /// The lines of row `j` with its right and lower neighbours (`below`: row `j + 1`).
    fn trace_row(&mut self, j: usize, row: &[GPixel], below: Option<&[GPixel]>) {
        let (w, h) = (self.width, self.height);
        for i in 0..w {
            let a = j * w + i;
            // Pixels on the image border that see the object close the silhouette.
            if row[i].hit && (i == 0 || j == 0 || i + 1 == w || j + 1 == h) {
                self.line[a] = true;
                self.outer[a] = true;
            }
            if i + 1 < w {
                self.edge((a, &row[i]), (a + 1, &row[i + 1]));
            }
            if let Some(below) = below {
                self.edge((a, &row[i]), (a + w, &below[i]));
            }
        }
    }

    /// An edge between neighbouring pixels `a` and `b` (silhouette, crease or depth jump)
    /// puts a line on the pixel on the object's / near side, and with width 2 or more on
    /// the other one too.
    fn edge(&mut self, (a, pa): (usize, &GPixel), (b, pb): (usize, &GPixel)) {
        let style = &self.style;
        let near_far = match (pa.hit, pb.hit) {
            (false, false) => None,
            (true, false) => Some((a, b)),
            (false, true) => Some((b, a)),
            (true, true) => {
                let crease = pa.face_normal.dot(pb.face_normal) < self.cos_crease;
                let d = pb.position - pa.position;
                let dist = d.length();
                let off_plane = pa.face_normal.dot(d).abs().max(pb.face_normal.dot(d).abs());
                let jump = dist > 0.0 && off_plane > style.depth_jump * dist;
                (crease || jump).then_some(if pa.depth <= pb.depth { (a, b) } else { (b, a) })
            }
        };
        if let Some((near, far)) = near_far {
            let silhouette = pa.hit != pb.hit;
            self.line[near] = true;
            self.outer[near] |= silhouette;
            if style.width >= 2 {
                self.line[far] = true;
                self.outer[far] |= silhouette;
            }
        }
    }
}

/// Grows a set of pixels by a disc of radius `r` pixels.
fn dilate(set: &[bool], w: usize, h: usize, r: usize) -> Vec<bool> {
    let mut out = set.to_vec();
    let ri = r as isize;
    for j in 0..h as isize {
        for i in 0..w as isize {
            if !set[(j * w as isize + i) as usize] {
                continue;
            }
            for dj in -ri..=ri {
                for di in -ri..=ri {
                    let (x, y) = (i + di, j + dj);
                    if di * di + dj * dj <= ri * ri && x >= 0 && y >= 0 && x < w as isize && y < h as isize {
                        out[(y * w as isize + x) as usize] = true;
                    }
                }
            }
        }
    }
    out
}

/// Assembles G-buffer pixels from the six pass images (see shaders/gbuffer.frag).
pub(crate) fn assemble(width: usize, height: usize, passes: &[Vec<[f32; 4]>; 6]) -> GBuffer {
    let v3 = |p: [f32; 4]| Vec3::new(p[0], p[1], p[2]);
    let pixels = (0..width * height)
        .map(|k| {
            let [p0, p1, p2, p3, p4, p5] = [0, 1, 2, 3, 4, 5].map(|s| passes[s][k]);
            let px = GPixel {
                hit: p0[3] > 0.5,
                position: v3(p0),
                l: v3(p1),
                falloff: p1[3],
                v: v3(p2),
                depth: p2[3],
                normal: v3(p3),
                tangent: Vec4::from_array(p4),
                face_normal: v3(p5),
                uv: Vec2::new(p3[3], p5[3]),
            };
            let finite = [p0, p1, p2, p3, p4, p5].iter().all(|p| p.iter().all(|x| x.is_finite()));
            if px.hit && finite {
                px
            } else {
                GPixel::default()
            }
        })
        .collect();
    GBuffer { width, height, pixels }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square of pixels facing the camera in the middle of an empty image.
    fn square(w: usize, h: usize, lo: usize, hi: usize) -> GBuffer {
        let pixels = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                let hit = (lo..hi).contains(&i) && (lo..hi).contains(&j);
                GPixel {
                    hit,
                    position: Vec3::new(i as f32, -(j as f32), 0.0),
                    face_normal: Vec3::Z,
                    depth: 1.0,
                    ..Default::default()
                }
            })
            .collect();
        GBuffer { width: w, height: h, pixels }
    }

    #[test]
    fn a_flat_square_gets_only_its_border() {
        let g = square(10, 10, 2, 8);
        let one = g.lines(&OutlineStyle { width: 1, ..Default::default() });
        for j in 0..10 {
            for i in 0..10 {
                let border = g.at(i, j).hit && (i == 2 || i == 7 || j == 2 || j == 7);
                assert_eq!(one[j * 10 + i], border, "width 1 at ({i}, {j})");
            }
        }
        // Width 2 adds the background ring (4-neighbours of the square only).
        let two = g.lines(&OutlineStyle::default());
        assert!(two[2 * 10 + 1] && two[10 + 2] && !two[10 + 1] && !two[5 * 10 + 5]);
        assert_eq!(g.coverage(), 36);
        assert_eq!(g.mask().pixels.iter().filter(|p| p[0] == 1.0).count(), 36);
    }

    #[test]
    fn a_depth_jump_and_a_crease_draw_lines() {
        let mut g = square(10, 10, 0, 10);
        // Right half pushed back: an occlusion contour between columns 4 and 5.
        for j in 0..10 {
            for i in 5..10 {
                let p = &mut g.pixels[j * 10 + i];
                p.position.z -= 5.0;
                p.depth = 6.0;
            }
        }
        let l = g.lines(&OutlineStyle { width: 1, ..Default::default() });
        assert!((1..9).all(|j| l[j * 10 + 4] && !l[j * 10 + 5] && !l[j * 10 + 3]), "line on the near side");
        // A crease: the lower half folded back by 90 degrees about row 4.5, positions
        // continuous.
        let mut g = square(10, 10, 0, 10);
        for j in 5..10 {
            for i in 0..10 {
                let p = &mut g.pixels[j * 10 + i];
                p.face_normal = Vec3::Y;
                p.position = Vec3::new(i as f32, -4.5, 4.5 - j as f32);
                p.depth = 1.0 + (j as f32 - 4.5);
            }
        }
        let l = g.lines(&OutlineStyle { width: 1, ..Default::default() });
        assert!((1..9).all(|i| l[4 * 10 + i] || l[5 * 10 + i]));
        assert!((1..9).all(|i| !l[2 * 10 + i] && !l[7 * 10 + i]));
    }

    #[test]
    fn short_interior_dashes_are_dropped_and_long_lines_kept() {
        // 400 x 400, all object (dashes under 10 pixels go): a crease across the whole image
        // and a three-pixel depth jump in a corner, whose line is an 8-pixel ring (a dash).
        let n = 400;
        let mut g = square(n, n, 0, n);
        for j in n / 2..n {
            for i in 0..n {
                let p = &mut g.pixels[j * n + i];
                p.face_normal = Vec3::Y;
                p.position = Vec3::new(i as f32, -(n as f32 / 2.0 - 0.5), (n as f32 / 2.0 - 0.5) - j as f32);
                p.depth = 1.0 + (j as f32 - (n as f32 / 2.0 - 0.5));
            }
        }
        for j in 10..13 {
            let p = &mut g.pixels[j * n + 10];
            p.position.z -= 5.0;
            p.depth = 6.0;
        }
        let l = g.lines(&OutlineStyle { width: 1, ..Default::default() });
        assert!((2..n - 2).all(|i| l[(n / 2 - 1) * n + i] || l[n / 2 * n + i]), "the crease stays");
        assert!((8..16).all(|j| (8..13).all(|i| !l[j * n + i])), "the dash is gone");
        // Without the dash filter's reach (a 100-pixel image keeps lines of 3 pixels and
        // more) the same dash is drawn: it is the filter that removed it.
        let mut small = square(100, 100, 0, 100);
        for j in 10..13 {
            let p = &mut small.pixels[j * 100 + 10];
            p.position.z -= 5.0;
            p.depth = 6.0;
        }
        let l = small.lines(&OutlineStyle { width: 1, ..Default::default() });
        assert!(l[11 * 100 + 9] && l[11 * 100 + 11]);
        // The silhouette stays whatever its length: a 3 x 3 object is all outline.
        let g = square(n, n, 48, 51);
        let l = g.lines(&OutlineStyle { width: 1, ..Default::default() });
        assert_eq!(l.iter().filter(|&&x| x).count(), 8);
    }

    /// The lines traced from bands of any height (1 row, 7 rows, uneven last band) are the
    /// lines of the whole image; the image has a silhouette, a crease and a depth jump that
    /// cross band boundaries, and a line width that grows.
    #[test]
    fn lines_from_bands_are_the_lines_of_the_whole_image() {
        let mut g = square(40, 30, 5, 28);
        for j in 12..30 {
            for i in 0..40 {
                let p = &mut g.pixels[j * 40 + i];
                p.face_normal = Vec3::Y;
                p.position.z -= if i > 20 { 9.0 } else { 0.0 };
                p.depth += if i > 20 { 9.0 } else { 0.0 };
            }
        }
        for width in [1, 2, 5] {
            let style = OutlineStyle { width, ..Default::default() };
            let whole = g.lines(&style);
            assert!(whole.iter().filter(|&&l| l).count() > 60, "the test image has lines");
            for rows in [1, 7, 29] {
                let mut t = LineTracer::new(40, 30, style);
                for band in g.pixels.chunks(40 * rows) {
                    t.push(band);
                }
                assert_eq!(t.finish(), whole, "width {width}, bands of {rows} rows");
            }
        }
    }

    #[test]
    fn dilation_grows_by_a_disc() {
        let mut set = vec![false; 49];
        set[3 * 7 + 3] = true;
        let d = dilate(&set, 7, 7, 2);
        assert_eq!(d.iter().filter(|&&x| x).count(), 13);
    }
}
