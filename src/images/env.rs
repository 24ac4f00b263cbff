//! HDR environments: equirectangular (latitude-longitude) radiance maps, read from OpenEXR
//! or Radiance `.hdr` files and checked before anything is drawn with them.
//!
//! # Convention
//! World space is the scene's (glTF 2.0): $+y$ is up. Row 0 of the image is the zenith
//! ($+y$), the last row the nadir. The image's centre column ($u = 0.5$) looks along $-z$,
//! and $u$ grows toward $+x$ (the panorama read left to right from inside, standing upright
//! and facing $-z$, as glTF's default camera does). With $\phi = 2\pi(u - \tfrac12)$ and
//! $\theta = \pi v$ (from the zenith),
//!
//! $$ d(u, v) = (\sin\phi \sin\theta,\ \cos\theta,\ -\cos\phi \sin\theta). $$
//!
//! Pixel $(i, j)$ is the radiance at its centre, $u = (i + 0.5)/W$, $v = (j + 0.5)/H$.
//! This is the layout of the bundled Poly Haven maps (`assets/hdri/README.md`).
//!
//! Rotating an environment by $\alpha$ turns it about $+y$, counter-clockwise seen from
//! above (right-handed): the radiance arriving from $d$ is then the file's radiance from
//! $R_y(-\alpha)\,d$, which is the file's column at $u + \alpha / 2\pi$.

use std::f64::consts::PI;
use std::path::Path;

use glam::DVec3;

use super::env_read::Boxes;
pub use super::env_read::{MAX_ENV_WIDTH, MAX_HDR_HEADER};
use crate::error::{Error, Result};

/// Largest environment file read: 1 GiB, above an 8192×4096 RGBA float OpenEXR stored
/// uncompressed (537 MB). Files are read as a stream, so this bounds time, not memory.
pub const MAX_ENV_BYTES: u64 = 1 << 30;

/// An equirectangular HDR environment: linear RGB radiance, row 0 at the zenith,
/// exactly twice as wide as high.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 3]>,
}

/// Largest radiance accepted: half-float's largest finite value. A pixel above it is an
/// overflow in the file's history, not light (the sun of a real capture stays far below).
pub const MAX_RADIANCE: f32 = 65504.0;

impl Environment {
    /// Reads an OpenEXR or Radiance `.hdr` file (recognized by its content, not its name)
    /// under the file-access policy, and checks it as [`Environment::new`] does. A map larger
    /// than the renderer's 4096×4096 pixels (up to [`MAX_ENV_WIDTH`]×4096) is averaged down
    /// as it is read. Errors name the file: not an HDR image, corrupt or truncated, a
    /// Radiance header over [`MAX_HDR_HEADER`] bytes, zero-size, not 2:1, too large, a NaN,
    /// infinite or overflowing pixel, mostly negative.
    pub fn load(path: &Path) -> Result<Environment> {
        let (file, _) = crate::fsio::open_regular(path, MAX_ENV_BYTES)?;
        super::env_read::read(path, std::io::BufReader::new(file))
    }

    /// Decodes the bytes of an OpenEXR or Radiance `.hdr` file, as [`Environment::load`];
    /// errors name `path`.
    pub fn decode(path: &Path, bytes: &[u8]) -> Result<Environment> {
        super::env_read::read(path, std::io::Cursor::new(bytes))
    }

    /// An environment of these pixels. Errors ([`Error::Input`]): a zero size, an aspect other
    /// than 2:1, a pixel count that does not match, a non-finite value or one above
    /// [`MAX_RADIANCE`] (the message names the first bad pixel), a map mostly negative.
    ///
    /// Negative values are read as 0. Radiance is never negative, but lossy EXR codecs
    /// (DWAA/DWAB, B44) ring around bright sources: the bundled Poly Haven maps, stored
    /// DWAB-compressed upstream, hold values down to $-83$ beside a sun of a few thousand.
    /// Refusing them would refuse most real maps; a map whose pixels are mostly negative is
    /// no such map, and is refused.
    pub fn new(width: usize, height: usize, pixels: Vec<[f32; 3]>) -> Result<Environment> {
        Boxes::check_size(width, height).map_err(Error::input)?;
        if pixels.len() != width * height {
            return Err(Error::input(format!("{} pixels for a {width}x{height} environment", pixels.len())));
        }
        let mut boxes = Boxes::new(width, height).map_err(Error::input)?;
        for (k, p) in pixels.into_iter().enumerate() {
            boxes.add(k % width, k / width, p);
        }
        boxes.finish().map_err(Error::input)
    }

    /// The same radiance from every direction (the furnace test's environment).
    pub fn uniform(rgb: [f32; 3]) -> Environment {
        Environment { width: 8, height: 4, pixels: vec![rgb; 32] }
    }

    /// Radiance arriving from world direction `d` with the environment rotated by
    /// `rotate_deg` about $+y$: bilinear between pixel centres, wrapping around in $u$ and
    /// clamped at the poles in $v$ (as the GPU samples it at mip level 0).
    pub fn radiance(&self, d: DVec3, rotate_deg: f64) -> [f64; 3] {
        let (u, v) = direction_to_uv(d);
        let u = u + rotate_deg / 360.0;
        let (w, h) = (self.width as f64, self.height as f64);
        let x = u * w - 0.5;
        let y = (v * h - 0.5).clamp(0.0, h - 1.0);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let col = |i: f64| (i.rem_euclid(w)) as usize;
        let row = |j: f64| (j.min(h - 1.0)) as usize;
        let at = |i: f64, j: f64| self.pixels[row(j) * self.width + col(i)].map(f64::from);
        let (a, b, c, e) = (at(x0, y0), at(x0 + 1.0, y0), at(x0, y0 + 1.0), at(x0 + 1.0, y0 + 1.0));
        [0, 1, 2].map(|k| (1.0 - fy) * ((1.0 - fx) * a[k] + fx * b[k]) + fy * ((1.0 - fx) * c[k] + fx * e[k]))
    }
}

/// The environments bundled with the tool (`assets/hdri/`, CC0, README there): name and
/// file bytes. The demo renders its materials under them.
pub const BUNDLED: [(&str, &[u8]); 2] = [
    ("city", include_bytes!("../../assets/hdri/city.exr")),
    ("sunset", include_bytes!("../../assets/hdri/sunset.exr")),
];

/// A bundled environment by name ([`BUNDLED`]).
pub fn bundled(name: &str) -> Result<Environment> {
    let (name, bytes) = BUNDLED
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| Error::input(format!("no bundled environment '{name}' (city, sunset)")))?;
    Environment::decode(Path::new(&format!("assets/hdri/{name}.exr")), bytes)
}

/// Unit direction to equirectangular coordinates $(u, v) \in [0, 1)\times[0, 1]$
/// (module docs): $u = \mathrm{atan2}(d_x, -d_z)/2\pi + \tfrac12$, $v = \arccos(d_y)/\pi$.
pub fn direction_to_uv(d: DVec3) -> (f64, f64) {
    let d = d.normalize_or(DVec3::Y);
    let u = d.x.atan2(-d.z) / (2.0 * PI) + 0.5;
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    (u.rem_euclid(1.0), v)
}

/// Equirectangular coordinates to a unit direction, the inverse of [`direction_to_uv`].
pub fn uv_to_direction(u: f64, v: f64) -> DVec3 {
    let (phi, theta) = (2.0 * PI * (u - 0.5), PI * v);
    DVec3::new(phi.sin() * theta.sin(), theta.cos(), -phi.cos() * theta.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_and_direction_round_trip_and_match_the_convention() {
        // The centre column looks along -z, row 0 is up, u = 0.75 is +x.
        assert!((uv_to_direction(0.5, 0.5) - DVec3::NEG_Z).length() < 1e-12);
        assert!((uv_to_direction(0.75, 0.5) - DVec3::X).length() < 1e-12);
        assert!((uv_to_direction(0.3, 0.0) - DVec3::Y).length() < 1e-12);
        for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.7), (0.01, 0.99)] {
            let (u2, v2) = direction_to_uv(uv_to_direction(u, v));
            assert!((u - u2).abs() < 1e-12 && (v - v2).abs() < 1e-12, "{u} {v}: {u2} {v2}");
        }
    }

    #[test]
    fn radiance_wraps_in_u_and_rotation_shifts_columns() {
        let (w, h) = (8, 4);
        let pixels = (0..w * h).map(|k| [(k % w) as f32, (k / w) as f32, 1.0]).collect();
        let env = Environment::new(w, h, pixels).unwrap();
        // The centre of pixel (3, 1).
        let d = uv_to_direction(3.5 / 8.0, 1.5 / 4.0);
        let r = env.radiance(d, 0.0);
        assert!((r[0] - 3.0).abs() < 1e-9 && (r[1] - 1.0).abs() < 1e-9, "{r:?}");
        // On the seam (u = 0): halfway between the last and the first column.
        let r = env.radiance(uv_to_direction(0.0, 1.5 / 4.0), 0.0);
        assert!((r[0] - 3.5).abs() < 1e-9, "{r:?}");
        // Rotating by 90 degrees reads two columns further on.
        let r = env.radiance(d, 90.0);
        assert!((r[0] - 5.0).abs() < 1e-9, "{r:?}");
    }

    #[test]
    fn bundled_environments_decode() {
        for (name, _) in BUNDLED {
            let env = bundled(name).unwrap();
            assert_eq!((env.width, env.height), (512, 256), "{name}");
            assert!(env.pixels.iter().flatten().all(|x| x.is_finite() && *x >= 0.0), "{name}");
        }
        assert!(bundled("moon").is_err());
    }

    #[test]
    fn bad_environments_are_one_line_errors() {
        let e = |w, h, px: Vec<[f32; 3]>| Environment::new(w, h, px).unwrap_err().to_string();
        assert!(e(0, 0, vec![]).contains("no pixels"));
        assert!(e(4, 4, vec![[1.0; 3]; 16]).contains("twice as wide"));
        let mut px = vec![[1.0; 3]; 8];
        px[5][1] = f32::NAN;
        assert!(e(4, 2, px.clone()).contains("pixel (1, 1)"), "{}", e(4, 2, px));
        px[5][1] = f32::INFINITY;
        assert!(e(4, 2, px.clone()).contains("radiance inf"));
        px[5][1] = 1e6;
        assert!(e(4, 2, px.clone()).contains("up to 65504"));
        // Codec ringing below zero reads as 0.
        px[5][1] = -80.0;
        assert_eq!(Environment::new(4, 2, px).unwrap().pixels[5][1], 0.0);
    }
}
