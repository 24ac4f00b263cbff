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

use std::path::Path;

use glam::{DMat3, DVec2, DVec3};

use super::{Erosion, Geometry, PaintedView, PixelGeometry};
use crate::brdf::SphereView;
use crate::error::{Error, Result};
use crate::factor::Query;
use crate::images::{check_size, Painting};

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
    pub width: usize,
    pub height: usize,
    pub normals: Vec<Option<DVec3>>,
}

impl NormalMap {
    /// A normal map from a function of the pixel (column, row); normals are normalized,
    /// zero-length or non-finite ones become `None`.
    pub fn from_fn(width: usize, height: usize, f: impl Fn(usize, usize) -> Option<DVec3>) -> Result<NormalMap> {
        check_size(width, height)?;
        let normals = (0..width * height).map(|k| f(k % width, k / width).and_then(unit)).collect();
        Ok(NormalMap { width, height, normals })
    }

    /// Read a normal map: EXR values are the normal's components; PNG codes $c \in [0, 1]$
    /// give $n = 2c - 1$. Errors name the file.
    pub fn read(path: &Path) -> Result<NormalMap> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        let img = image::load_from_memory(&bytes)
            .map_err(|e| Error::format(path, format!("cannot decode the normal map (corrupt, truncated or not PNG/EXR): {e}")))?;
        let float = matches!(img.color(), image::ColorType::Rgb32F | image::ColorType::Rgba32F);
        let (width, height) = (img.width() as usize, img.height() as usize);
        check_size(width, height).map_err(|e| Error::format(path, e.to_string()))?;
        let mut normals = Vec::with_capacity(width * height);
        for (k, p) in img.to_rgba32f().pixels().enumerate() {
            let [r, g, b, a] = p.0;
            if [r, g, b, a].iter().any(|x| !x.is_finite()) {
                return Err(Error::format(path, format!("pixel ({}, {}) is not finite", k % width, k / width)));
            }
            let n = if a <= 0.0 || (r == 0.0 && g == 0.0 && b == 0.0) {
                None
            } else if float {
                unit(DVec3::new(r as f64, g as f64, b as f64))
            } else {
                unit(DVec3::new(r as f64, g as f64, b as f64) * 2.0 - 1.0)
            };
            normals.push(n);
        }
        Ok(NormalMap { width, height, normals })
    }

    /// Remove every pixel where `mask` is not white: alpha 0 or a mean below one half.
    pub fn masked(mut self, mask: &Painting, name: &str) -> Result<NormalMap> {
        if (mask.width, mask.height) != (self.width, self.height) {
            return Err(Error::input(format!(
                "{name} is {}x{} but the normal map is {}x{}",
                mask.width, mask.height, self.width, self.height
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

impl Photo {
    /// A view-space normal map seen by `camera`.
    pub fn view_space(normals: NormalMap, camera: PhotoCamera) -> Photo {
        Photo { normals, camera, camera_to_frame: DMat3::IDENTITY }
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
                "{name} is {}x{} but the normal map is {}x{}",
                image.width, image.height, self.normals.width, self.normals.height
            )));
        }
        let geometry = self.geometry(light, erosion).map_err(|e| Error::input(format!("{name}: {e}")))?;
        Ok(PaintedView { name: name.to_string(), source: "normal map".into(), geometry, painting: image })
    }
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
