//! Photographs with known normals: a second geometry source, without a mesh.
//!
//! A photograph (or a painting over a normal map) comes with
//! - a **normal map**: per pixel the unit surface normal in one frame, the *map frame*;
//!   [`NormalMap::read`] reads EXR (x, y, z as stored) or PNG (`n = 2c - 1` of the raw codes,
//!   no sRGB curve: a normal map is data). Pixels with alpha 0, with all channels 0, or
//!   with a zero-length normal are not surface. An optional mask removes more;
//! - the **camera** ([`PhotoCamera`]): orthographic (every view direction is the camera's
//!   $+z$) or perspective with a vertical field of view (the view direction of pixel
//!   $(i, j)$ runs through its centre), and the rotation from camera space (x right, y up,
//!   z toward the camera, the glTF camera convention) into the map frame. The identity
//!   means a **view-space** normal map; a **world-space** map gives the camera's
//!   world-from-camera rotation;
//! - **directional lights**, one image per light: the direction toward the light in the
//!   map frame and its colour × intensity, which is divided out of the image.
//!
//! **Local frame.** $z = n$; the tangent is $x = \mathrm{normalize}(\hat y \times n)$ with
//! $\hat y$ the map frame's $+y$ (for a view-space map, the image's up), and where $n$ is
//! within $10^{-6}$ of $\pm\hat y$ the map frame's $+x$ projected; $y = z \times x$. This is
//! [`crate::brdf::SphereView::frame`], so a front view of a sphere has exactly the frame of
//! the built-in sphere mesh. **uv** is the pixel centre over the image size,
//! $((i + \frac12)/W, (j + \frac12)/H)$, row 0 at the top.
//!
//! **Photographs** ([`read_photograph`]): EXR is linear; a PNG or JPEG is sRGB-encoded
//! (DESIGN.md) or linear ([`Encoding`]: photometric-stereo sets store sensor values), as
//! the file declares it (an `sRGB` or a `gAMA` 1.0 chunk) or the caller says. A pixel is
//! left out of a fit ([`Photo::photograph`]) where the light does not reach the surface
//! ($n \cdot l \le 0$), where any channel is at the file's largest code (clipped), or where
//! it is near black (a cast shadow, or too dark to read).

use std::path::Path;

use glam::{DMat3, DVec2, DVec3};
use image::ImageFormat;

use super::{Erosion, Geometry, PaintedView, PixelGeometry};
use crate::brdf::SphereView;
use crate::error::{Error, Result};
use crate::factor::Query;
use crate::note::Note;
use crate::fsio::{read_regular, MAX_IMAGE_BYTES};
use crate::images::{check_size, decode_limited, srgb_to_linear_f64, Painting};

/// How a photograph was taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhotoCamera {
    /// Parallel projection: every view direction is the camera's $+z$.
    Orthographic,
    /// Pinhole camera with this vertical field of view in radians; the horizontal one
    /// follows from the image's W/H.
    Perspective { yfov: f64 },
}

/// Unit normals per pixel in the map frame; `None` where there is no surface.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    /// How messages name the map: its path, or "normal map".
    pub name: String,
    pub width: usize,
    pub height: usize,
    pub normals: Vec<Option<DVec3>>,
}

/// A stored normal must have a length within this factor of 1: 8-bit codes round a unit
/// normal's length by under 1%, while a zero or grey pixel inside the surface is no normal.
const UNIT_TOLERANCE: f64 = 0.5;

impl NormalMap {
    /// A normal map from a function of the pixel (column, row); normals are normalized,
    /// zero-length or non-finite ones become `None`.
    pub fn from_fn(width: usize, height: usize, f: impl Fn(usize, usize) -> Option<DVec3>) -> Result<NormalMap> {
        check_size(width, height)?;
        let normals = (0..width * height).map(|k| f(k % width, k / width).and_then(unit)).collect();
        Ok(NormalMap { name: "normal map".into(), width, height, normals })
    }

    /// Read a normal map: EXR values are the normal's components; PNG codes $c \in [0, 1]$
    /// give $n = 2c - 1$. Alpha 0 or all channels 0 is background. Errors name the file.
    pub fn read(path: &Path) -> Result<NormalMap> {
        NormalMap::read_masked(path, None, None)
    }

    /// [`NormalMap::read`], with `mask` (and its name) removing pixels before the normals are
    /// checked: inside the surface every normal must be a unit vector (to within
    /// [`UNIT_TOLERANCE`]), so a zero, grey or garbled pixel there is an error naming it.
    /// A `.txt` map is the photometric-stereo sets' text form ([`NormalMap::read_text`]) of
    /// the photographs' `size`.
    pub fn read_masked(path: &Path, size: Option<(usize, usize)>, mask: Option<(&Painting, &str)>) -> Result<NormalMap> {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("txt")) {
            let Some((w, h)) = size.or(mask.map(|(m, _)| (m.width, m.height))) else {
                return Err(Error::format(path, "a text normal map needs the photographs' size to be read"));
            };
            return NormalMap::read_text(path, w, h)?.checked_with(mask);
        }
        let bytes = read_regular(path, MAX_IMAGE_BYTES)?;
        let format = image::guess_format(&bytes).ok().filter(|f| matches!(f, ImageFormat::Png | ImageFormat::OpenExr));
        let Some(format) = format else {
            return Err(Error::format(path, "cannot decode the normal map (corrupt, truncated or not PNG/EXR)"));
        };
        let img = decode_limited(path, &bytes, format)?;
        let float = matches!(img.color(), image::ColorType::Rgb32F | image::ColorType::Rgba32F);
        let (width, height) = (img.width() as usize, img.height() as usize);
        check_size(width, height).map_err(|e| Error::format(path, e.to_string()))?;
        let mut normals = Vec::with_capacity(width * height);
        for (k, p) in img.to_rgba32f().pixels().enumerate() {
            let [r, g, b, a] = p.0;
            if [r, g, b, a].iter().any(|x| !x.is_finite()) {
                return Err(Error::format(path, format!("pixel ({}, {}) is not finite", k % width, k / width)));
            }
            let c = DVec3::new(r as f64, g as f64, b as f64);
            normals.push(match (a <= 0.0 || c == DVec3::ZERO, float) {
                (true, _) => None,
                (false, true) => Some(c),
                (false, false) => Some(c * 2.0 - 1.0),
            });
        }
        NormalMap { name: path.display().to_string(), width, height, normals }.checked_with(mask)
    }

    /// The text form of photometric-stereo sets (DiLiGenT's `normal.txt`): one `x y z` line
    /// per pixel, row by row from the top, $(0, 0, 0)$ for background; `width` × `height`
    /// come from the images. Unchecked lengths ([`NormalMap::read_masked`] checks them).
    pub fn read_text(path: &Path, width: usize, height: usize) -> Result<NormalMap> {
        let rows = super::photoset::read_triples(path, "x y z")?;
        if rows.len() != width * height {
            return Err(Error::format(
                path,
                format!("{} normals for {width}x{height} images ({} pixels): one x y z line per pixel, row by row", rows.len(), width * height),
            ));
        }
        let normals = rows.iter().map(|r| Some(DVec3::from_array(r.values)).filter(|n| *n != DVec3::ZERO)).collect();
        Ok(NormalMap { name: path.display().to_string(), width, height, normals })
    }

    /// Applies `mask`, then normalizes every normal, refusing one whose length is not near 1.
    fn checked_with(self, mask: Option<(&Painting, &str)>) -> Result<NormalMap> {
        let mut map = match mask {
            Some((m, name)) => self.masked(m, name)?,
            None => self,
        };
        let name = map.name.clone();
        for (k, n) in map.normals.iter_mut().enumerate() {
            let Some(v) = *n else { continue };
            let len = v.length();
            if (len - 1.0).abs() > UNIT_TOLERANCE {
                let (i, j) = (k % map.width, k / map.width);
                return Err(Error::format(
                    &name,
                    format!("pixel ({i}, {j}) holds a normal of length {len:.3}, not a unit vector (zero or grey inside the surface; a background there needs a mask)"),
                ));
            }
            *n = Some(v / len);
        }
        Ok(map)
    }

    /// Remove every pixel where `mask` is not white: alpha 0 or a mean below one half.
    pub fn masked(mut self, mask: &Painting, name: &str) -> Result<NormalMap> {
        if (mask.width, mask.height) != (self.width, self.height) {
            return Err(Error::input(format!(
                "{name} is {}x{} but the normal map {} is {}x{}",
                mask.width, mask.height, self.name, self.width, self.height
            )));
        }
        for (k, n) in self.normals.iter_mut().enumerate() {
            let m = mask.pixels[k];
            // Linear mean; 0.5 linear is well inside white for any sensible mask.
            if !mask.painted(k) || (m[0] + m[1] + m[2]) / 3.0 < 0.5 {
                *n = None;
            }
        }
        Ok(self)
    }
}

fn unit(d: DVec3) -> Option<DVec3> {
    let len = d.length();
    (len.is_finite() && len > 1e-6).then(|| d / len)
}

/// A directional light of a photograph.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotoLight {
    /// Direction toward the light, map frame (normalized here).
    pub direction: DVec3,
    /// Colour × intensity per channel: divided out of the image.
    pub rgb: [f64; 3],
}

/// A photograph's geometry: normals, camera, and the camera's orientation in the map frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Photo {
    pub normals: NormalMap,
    pub camera: PhotoCamera,
    /// Rotation from camera space into the map frame (identity: a view-space map).
    pub camera_to_frame: DMat3,
}

/// The frame a normal map (and its lights) is given in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapFrame {
    /// Camera space: x right, y up, z toward the camera (photometric-stereo sets, DiLiGenT).
    View,
    /// Any frame, with the direction toward the camera and the image's up in it.
    World { toward_camera: DVec3, up: DVec3 },
}

/// A normal facing away from the camera: camera-space $n_z$ below this. A view-space map
/// has them only in a thin rim band (a perspective camera sees a little past $n_z = 0$).
const AWAY_Z: f64 = -0.05;

impl Photo {
    /// A view-space normal map seen by `camera`.
    pub fn view_space(normals: NormalMap, camera: PhotoCamera) -> Photo {
        Photo { normals, camera, camera_to_frame: DMat3::IDENTITY }
    }

    /// A normal map in `frame`, seen by `camera`: the camera's rotation into the map frame
    /// from the direction toward it and the up vector (made orthogonal to it).
    pub fn new(normals: NormalMap, camera: PhotoCamera, frame: MapFrame) -> Result<Photo> {
        let camera_to_frame = match frame {
            MapFrame::View => DMat3::IDENTITY,
            MapFrame::World { toward_camera, up } => {
                let back = unit(toward_camera).ok_or_else(|| Error::input(format!("camera direction {toward_camera} is not a direction")))?;
                let right = unit(up.cross(back))
                    .ok_or_else(|| Error::input(format!("the up vector {up} is parallel to the camera direction {toward_camera}")))?;
                DMat3::from_cols(right, back.cross(right), back)
            }
        };
        Ok(Photo { normals, camera, camera_to_frame })
    }

    /// The share of surface normals that face away from the camera ([`AWAY_Z`]): near 0
    /// for a map in the frame the photo says, a good part for a world-space map taken as
    /// view space (a sixth when its camera is 50° off the map's $z$).
    pub fn facing_away(&self) -> f64 {
        let to_camera = self.camera_to_frame.transpose();
        let (away, all) = self.normals.normals.iter().flatten().fold((0usize, 0usize), |(a, n), &v| {
            (a + usize::from((to_camera * v).z < AWAY_Z), n + 1)
        });
        away as f64 / all.max(1) as f64
    }

    /// Unit direction toward the viewer at pixel (i, j), map frame.
    pub fn view_direction(&self, i: usize, j: usize) -> DVec3 {
        let cam = match self.camera {
            PhotoCamera::Orthographic => DVec3::Z,
            PhotoCamera::Perspective { yfov } => {
                let (w, h) = (self.normals.width as f64, self.normals.height as f64);
                let t = (0.5 * yfov).tan();
                let x = (2.0 * (i as f64 + 0.5) / w - 1.0) * t * w / h;
                let y = (1.0 - 2.0 * (j as f64 + 0.5) / h) * t;
                // The ray runs along (x, y, -1); toward the viewer is its opposite.
                DVec3::new(-x, -y, 1.0).normalize()
            }
        };
        (self.camera_to_frame * cam).normalize()
    }

    /// The geometry of the photograph under one light: every surface pixel whose normal
    /// faces the camera, eroded at the edge of the surface.
    pub fn geometry(&self, light: &PhotoLight, erosion: Erosion) -> Result<Geometry> {
        if let PhotoCamera::Perspective { yfov } = self.camera {
            if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
                return Err(Error::input(format!("photograph field of view {yfov} rad is outside (0, pi)")));
            }
        }
        let l = unit(light.direction).ok_or_else(|| {
            Error::input(format!("light direction {} is not a direction", light.direction))
        })?;
        if light.rgb.iter().any(|&c| !(c > 0.0 && c.is_finite())) {
            return Err(Error::input(format!(
                "light colour x intensity {:?} has a zero, negative or non-finite channel, so it cannot be divided out",
                light.rgb
            )));
        }
        let (w, h) = (self.normals.width, self.normals.height);
        let pixels: Vec<Option<PixelGeometry>> = (0..w * h)
            .map(|k| {
                let n = self.normals.normals[k]?;
                let (i, j) = (k % w, k / w);
                let (t, b, n) = SphereView::frame(n);
                let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
                let v = local(self.view_direction(i, j));
                (v.z > 0.0).then(|| PixelGeometry {
                    query: Query {
                        l: local(l),
                        v,
                        uv: DVec2::new((i as f64 + 0.5) / w as f64, (j as f64 + 0.5) / h as f64),
                    },
                    position: None,
                    light: light.rgb,
                })
            })
            .collect();
        let surface: Vec<bool> = self.normals.normals.iter().map(Option::is_some).collect();
        let kept = erosion.apply(&surface, w, h);
        let usable = pixels.iter().zip(&kept).map(|(p, &k)| k && p.is_some()).collect();
        Ok(Geometry { width: w, height: h, pixels, usable, left_out: 0, has_uv: true })
    }

    /// One light's image as a view: the image must have the normal map's size.
    pub fn view(&self, light: &PhotoLight, image: Painting, name: &str, erosion: Erosion) -> Result<PaintedView> {
        if (image.width, image.height) != (self.normals.width, self.normals.height) {
            return Err(Error::input(format!(
                "{name} is {}x{} but the normal map {} is {}x{}",
                image.width, image.height, self.normals.name, self.normals.width, self.normals.height
            )));
        }
        let geometry = self.geometry(light, erosion).map_err(|e| Error::input(format!("{name}: {e}")))?;
        Ok(PaintedView { name: name.to_string(), source: self.normals.name.clone(), geometry, painting: image })
    }

    /// A photograph as a view ([`Photo::view`]) without the pixels a fit cannot read: where
    /// the light does not reach ($n \cdot l \le 0$), where a channel clipped
    /// ([`Painting::saturated`] as [`read_photograph`] marks it), and near black (largest
    /// channel at most [`NEAR_BLACK`] of `white`, the file's largest value). They become
    /// unpainted (alpha 0).
    pub fn photograph(&self, light: &PhotoLight, image: Painting, white: f32, name: &str, erosion: Erosion) -> Result<(PaintedView, LeftOut)> {
        let mut view = self.view(light, image, name, erosion)?;
        let (g, p) = (&view.geometry, &mut view.painting);
        let mut left = LeftOut::default();
        for (k, px) in g.pixels.iter().enumerate() {
            let Some(px) = px.filter(|_| g.usable[k] && p.alpha[k] > 0.0) else { continue };
            left.object += 1;
            let top = p.pixels[k].iter().copied().fold(0.0, f32::max);
            let count = if px.query.l.z <= 0.0 {
                &mut left.unlit
            } else if p.saturated[k] {
                &mut left.saturated
            } else if top <= NEAR_BLACK * white {
                &mut left.dark
            } else {
                continue;
            };
            *count += 1;
            p.alpha[k] = 0.0;
        }
        if left.object > 0 && left.kept() == 0 {
            return Err(Error::input(format!(
                "{name}: every pixel on the object is in shadow, clipped or near black ({}): nothing to fit",
                left.counts()
            )));
        }
        Ok((view, left))
    }
}

/// Near black, as a fraction of the file's white: a 16-bit linear code of 131, an 8-bit sRGB
/// code of 7. Below it a photograph shows a cast shadow, or noise more than shading.
pub const NEAR_BLACK: f32 = 0.002;

/// The pixels of photographs on the object, and those left out of a fit ([`Photo::photograph`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LeftOut {
    /// Pixels that see the surface, off the eroded silhouette, not transparent.
    pub object: usize,
    /// Facing away from the light: $n \cdot l \le 0$.
    pub unlit: usize,
    /// A channel at the file's largest code.
    pub saturated: usize,
    /// Near black ([`NEAR_BLACK`]).
    pub dark: usize,
}

impl LeftOut {
    /// Pixels kept as samples.
    pub fn kept(&self) -> usize {
        self.object - self.unlit - self.saturated - self.dark
    }

    /// Sums the counts of several photographs.
    pub fn add(&mut self, other: &LeftOut) {
        self.object += other.object;
        self.unlit += other.unlit;
        self.saturated += other.saturated;
        self.dark += other.dark;
    }

    fn counts(&self) -> String {
        format!("{} unlit, {} saturated, {} near black", self.unlit, self.saturated, self.dark)
    }

    /// One line for `images` photographs.
    pub fn note(&self, images: usize) -> Note {
        Note::PhotoSamples { images, object: self.object, kept: self.kept(), saturated: self.saturated, unlit: self.unlit, dark: self.dark }
    }
}

/// How a PNG or JPEG photograph's codes become linear values (EXR is always linear).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// The sRGB transfer function: DESIGN.md's convention for PNG and JPEG.
    Srgb,
    /// The code over its largest value: how photometric-stereo sets store sensor values.
    Linear,
}

impl Encoding {
    pub fn name(self) -> &'static str {
        match self {
            Encoding::Srgb => "sRGB",
            Encoding::Linear => "linear",
        }
    }

    /// What a PNG's own chunks say: an `sRGB` or `iCCP` chunk, or a `gAMA` other than 1.0,
    /// is sRGB-like; a `gAMA` of 1.0 (100000) is linear; none of them says nothing.
    pub fn declared(png: &[u8]) -> Option<Encoding> {
        let mut at = 8;
        while at + 8 <= png.len() {
            let len = u32::from_be_bytes(png[at..at + 4].try_into().ok()?) as usize;
            let kind = &png[at + 4..at + 8];
            let data = png.get(at + 8..at + 8 + len)?;
            match kind {
                b"sRGB" | b"iCCP" => return Some(Encoding::Srgb),
                b"gAMA" if len == 4 => {
                    let gamma = u32::from_be_bytes(data.try_into().ok()?);
                    return Some(if gamma == 100_000 { Encoding::Linear } else { Encoding::Srgb });
                }
                b"IDAT" | b"IEND" => return None,
                _ => {}
            }
            at += 12 + len;
        }
        None
    }
}

impl std::str::FromStr for Encoding {
    type Err = Error;
    fn from_str(s: &str) -> Result<Encoding> {
        match s.to_ascii_lowercase().as_str() {
            "srgb" => Ok(Encoding::Srgb),
            "linear" => Ok(Encoding::Linear),
            _ => Err(Error::input(format!("encoding '{s}': expected srgb or linear"))),
        }
    }
}

/// A photograph decoded to linear RGB, and the encoding read (`None` for EXR). A PNG's own
/// declaration ([`Encoding::declared`]) wins over `default`; `forced` wins over both. Unlike
/// a painting's, its `saturated` marks a pixel with *any* channel at the largest code: a
/// camera's channels clip one at a time.
pub fn read_photograph(path: &Path, forced: Option<Encoding>, default: Encoding) -> Result<(Painting, Option<Encoding>)> {
    let bytes = read_regular(path, MAX_IMAGE_BYTES)?;
    let format = image::guess_format(&bytes).ok();
    if !matches!(format, Some(ImageFormat::Png | ImageFormat::Jpeg)) {
        // EXR, and anything else for the painting decoder to name.
        return Ok((Painting::decode(path, &bytes)?, None));
    }
    let format = format.expect("matched above");
    let encoding = forced.or_else(|| (format == ImageFormat::Png).then(|| Encoding::declared(&bytes)).flatten()).unwrap_or(default);
    let img = decode_limited(path, &bytes, format)?;
    let (width, height) = (img.width() as usize, img.height() as usize);
    check_size(width, height).map_err(|e| Error::format(path, e.to_string()))?;
    let wide = matches!(img.color(), image::ColorType::L16 | image::ColorType::La16 | image::ColorType::Rgb16 | image::ColorType::Rgba16);
    let top = if wide { 65535.0 } else { 255.0 };
    let decode = |c: f64| match encoding {
        Encoding::Srgb => srgb_to_linear_f64(c / top) as f32,
        Encoding::Linear => (c / top) as f32,
    };
    let n = width * height;
    let mut p = Painting { width, height, pixels: Vec::with_capacity(n), alpha: Vec::with_capacity(n), saturated: Vec::with_capacity(n) };
    // 16-bit codes for both depths: an 8-bit code c is c * 257, its largest 65535.
    for px in img.to_rgba16().pixels() {
        let [r, g, b, a] = px.0.map(|c| if wide { c as f64 } else { (c / 257) as f64 });
        p.pixels.push([decode(r), decode(g), decode(b)]);
        p.alpha.push((a / top) as f32);
        p.saturated.push([r, g, b].contains(&top));
    }
    Ok((p, Some(encoding)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perspective_view_directions_point_back_through_pixel_centres() {
        let map = NormalMap::from_fn(4, 2, |_, _| Some(DVec3::Z)).unwrap();
        let photo = Photo::view_space(map, PhotoCamera::Perspective { yfov: 1.0 });
        // Pixel (3, 0): x = 0.75 t W/H, y = 0.5 t with t = tan(0.5).
        let t = 0.5f64.tan();
        let want = DVec3::new(-0.75 * t * 2.0, -0.5 * t, 1.0).normalize();
        assert!((photo.view_direction(3, 0) - want).length() < 1e-12);
        let ortho = Photo::view_space(photo.normals.clone(), PhotoCamera::Orthographic);
        assert_eq!(ortho.view_direction(3, 0), DVec3::Z);
    }

    #[test]
    fn a_world_frame_turns_the_camera_into_the_map() {
        let toward = DVec3::new(0.3, 0.4, 0.87).normalize();
        let map = NormalMap::from_fn(2, 2, |_, _| Some(DVec3::Z)).unwrap();
        let world = MapFrame::World { toward_camera: toward, up: DVec3::Y };
        let photo = Photo::new(map.clone(), PhotoCamera::Orthographic, world).unwrap();
        assert!((photo.view_direction(1, 1) - toward).length() < 1e-12);
        // The image's right is horizontal, its up leans toward +y.
        let r = photo.camera_to_frame;
        assert!(r.x_axis.y.abs() < 1e-12 && r.y_axis.y > 0.0 && (r.determinant() - 1.0).abs() < 1e-12);
        let parallel = MapFrame::World { toward_camera: DVec3::Y, up: DVec3::Y };
        assert!(Photo::new(map, PhotoCamera::Orthographic, parallel).is_err());
    }

    #[test]
    fn photographs_decode_linear_or_srgb_and_clip_by_channel() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.png");
        let raw: Vec<u16> = vec![65535, 0, 32768, 1000, 2000, 3000];
        image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(2, 1, raw).unwrap().save(&path).unwrap();
        let (p, e) = read_photograph(&path, None, Encoding::Linear).unwrap();
        assert_eq!(e, Some(Encoding::Linear));
        assert_eq!(p.saturated, vec![true, false], "one channel at 65535 clips the pixel");
        assert_eq!(p.pixels[0], [1.0, 0.0, (32768.0 / 65535.0) as f32]);
        let (q, _) = read_photograph(&path, Some(Encoding::Srgb), Encoding::Linear).unwrap();
        assert!((q.pixels[1][0] as f64 - srgb_to_linear_f64(1000.0 / 65535.0)).abs() < 1e-7);
        let path8 = dir.path().join("p8.png");
        image::RgbImage::from_raw(1, 1, vec![10, 255, 10]).unwrap().save(&path8).unwrap();
        let (p8, _) = read_photograph(&path8, None, Encoding::Linear).unwrap();
        assert!(p8.saturated[0] && p8.pixels[0][1] == 1.0 && (p8.pixels[0][0] - 10.0 / 255.0).abs() < 1e-7);
        // A PNG's own declaration: sRGB or gAMA 1.0 (chunks after the signature and IHDR).
        let chunk = |kind: &[u8], data: &[u8]| [&(data.len() as u32).to_be_bytes()[..], kind, data, &[0; 4]].concat();
        let png = |c: Vec<u8>| [&b"\x89PNG\r\n\x1a\n"[..], &chunk(b"IHDR", &[0; 13]), &c, &chunk(b"IDAT", &[])].concat();
        assert_eq!(Encoding::declared(&png(chunk(b"gAMA", &100_000u32.to_be_bytes()))), Some(Encoding::Linear));
        assert_eq!(Encoding::declared(&png(chunk(b"gAMA", &45_455u32.to_be_bytes()))), Some(Encoding::Srgb));
        assert_eq!(Encoding::declared(&png(chunk(b"sRGB", &[0]))), Some(Encoding::Srgb));
        assert_eq!(Encoding::declared(&png(chunk(b"tEXt", b"a"))), None);
    }

    #[test]
    fn the_local_frame_is_the_sphere_views() {
        let n = DVec3::new(0.3, 0.4, 0.5).normalize();
        let map = NormalMap::from_fn(3, 3, |i, j| (i, j).eq(&(1, 1)).then_some(n)).unwrap();
        let photo = Photo::view_space(map, PhotoCamera::Orthographic);
        let light = PhotoLight { direction: DVec3::new(-1.0, 1.0, 1.0), rgb: [2.0, 1.0, 0.5] };
        let g = photo.geometry(&light, Erosion::NONE).unwrap();
        let q = g.pixels[4].unwrap().query;
        let want = SphereView::query(n, light.direction.normalize(), DVec3::Z);
        assert!((q.l - want.l).length() < 1e-12 && (q.v - want.v).length() < 1e-12);
        assert_eq!(q.uv, DVec2::new(0.5, 0.5));
        assert_eq!(g.pixels[4].unwrap().light, [2.0, 1.0, 0.5]);
        assert_eq!(g.usable_count(), 1);
        // The default erosion removes a one-pixel surface entirely.
        assert_eq!(photo.geometry(&light, Erosion::default()).unwrap().usable_count(), 0);
        assert!(photo.geometry(&PhotoLight { rgb: [1.0, 0.0, 1.0], ..light }, Erosion::NONE).is_err());
    }
}
