//! An analytic view of a unit sphere: the painted sphere of the thesis's standard scenes,
//! without a mesh or a renderer. Tests, benchmarks and the conditioning study use it to turn a
//! reflectance function into a sample pattern, and to judge a fit on views that were not
//! painted.
//!
//! The camera is orthographic and distant, the light directional. The sphere's pole axis is
//! world $+y$; the tangent runs along increasing azimuth about that axis and $u$ with it
//! (an equirectangular uv layout), so 2D factors and uv factors get a well-defined frame.

use std::f64::consts::PI;

use glam::{DVec2, DVec3};

use crate::factor::{Pattern, Query};

/// One view of the unit sphere: a square `res`×`res` image, a camera direction and a
/// directional light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereView {
    /// Unit direction toward the light (world).
    pub light: DVec3,
    /// Unit direction toward the camera (world); the image's up is world $+y$ projected.
    pub camera: DVec3,
    /// Image width and height in pixels.
    pub res: usize,
}

/// A pixel of a view that sees the sphere, with the sample it makes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpherePixel {
    /// Column and row (row 0 at the top).
    pub pixel: [usize; 2],
    /// World-space normal (= position on the unit sphere).
    pub normal: DVec3,
    pub query: Query,
}

impl SphereView {
    /// A view from $+z$ with a light from `light` (any non-zero vector; normalized).
    pub fn new(light: DVec3, res: usize) -> SphereView {
        SphereView { light: light.normalize(), camera: DVec3::Z, res }
    }

    /// The same view seen from another direction.
    pub fn from_camera(self, camera: DVec3) -> SphereView {
        SphereView { camera: camera.normalize(), ..self }
    }

    /// Camera basis: right, up, toward-camera.
    fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let back = self.camera;
        let helper = if back.y.abs() > 0.999 { DVec3::Z } else { DVec3::Y };
        let right = helper.cross(back).normalize();
        let up = back.cross(right);
        (right, up, back)
    }

    /// The local shading frame at a sphere point: tangent along azimuth about $+y$,
    /// bitangent, normal. Near the poles, where azimuth is undefined, the tangent is $+x$
    /// projected.
    pub fn frame(n: DVec3) -> (DVec3, DVec3, DVec3) {
        let t = DVec3::Y.cross(n);
        let t = if t.length_squared() > 1e-12 { t.normalize() } else { (DVec3::X - n * n.x).normalize() };
        (t, n.cross(t), n)
    }

    /// Equirectangular texture coordinates of a sphere point: $u$ along azimuth, $v$ from the
    /// north pole.
    pub fn uv(n: DVec3) -> DVec2 {
        DVec2::new(n.x.atan2(n.z) / (2.0 * PI) + 0.5, n.y.clamp(-1.0, 1.0).acos() / PI)
    }

    /// The sample a world-space light and view direction make at a sphere point.
    pub fn query(n: DVec3, light: DVec3, view: DVec3) -> Query {
        let (t, b, n) = SphereView::frame(n);
        let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
        Query { l: local(light), v: local(view), uv: SphereView::uv(n) }
    }

    /// Every pixel whose centre sees the sphere, one pixel in from the silhouette (the
    /// default 1 px erosion of DESIGN.md), with its sample.
    pub fn pixels(&self) -> Vec<SpherePixel> {
        let (right, up, back) = self.basis();
        let r = self.res as f64;
        // Pixels whose whole footprint lies inside the disc, roughly: erode by one pixel.
        let inner = 1.0 - 2.0 / r;
        let mut out = Vec::new();
        for j in 0..self.res {
            for i in 0..self.res {
                let x = 2.0 * (i as f64 + 0.5) / r - 1.0;
                let y = 1.0 - 2.0 * (j as f64 + 0.5) / r;
                let rr = x * x + y * y;
                if rr >= inner * inner {
                    continue;
                }
                let normal = right * x + up * y + back * (1.0 - rr).sqrt();
                let query = SphereView::query(normal, self.light, self.camera);
                out.push(SpherePixel { pixel: [i, j], normal, query });
            }
        }
        out
    }

    /// The sample pattern of this view (with uv).
    pub fn pattern(&self) -> Pattern {
        Pattern::new(self.pixels().into_iter().map(|p| p.query).collect(), true)
    }
}

/// Standard painted views for studies and tests: the first is the thesis's usual
/// upper-left light seen from the front; the others add different lights and cameras
/// (multi-view fitting, thesis 4.4). At most three.
pub fn painted_views(count: usize, res: usize) -> Vec<SphereView> {
    let all = [
        SphereView::new(DVec3::new(-0.5, 0.5, 1.0), res),
        SphereView::new(DVec3::new(0.8, 0.3, 0.5), res).from_camera(DVec3::new(0.3, 0.0, 0.95)),
        SphereView::new(DVec3::new(0.1, -0.4, 0.9), res).from_camera(DVec3::new(-0.4, 0.4, 0.82)),
    ];
    all[..count.min(all.len())].to_vec()
}

/// Standard held-out views for judging fits: lights and cameras that no test paints from.
pub fn held_out_views(res: usize) -> Vec<SphereView> {
    let lights = [DVec3::new(0.7, 0.2, 0.7), DVec3::new(-0.2, -0.6, 0.8), DVec3::new(0.0, 0.9, 0.45)];
    let cameras = [DVec3::new(0.35, 0.1, 0.93), DVec3::new(-0.5, 0.3, 0.8), DVec3::Z];
    lights
        .iter()
        .zip(&cameras)
        .map(|(&l, &c)| SphereView::new(l, res).from_camera(c))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_sees_the_pole_facing_the_camera() {
        let view = SphereView::new(DVec3::new(1.0, 0.0, 1.0), 33);
        let px = view.pixels();
        let centre = px.iter().find(|p| p.pixel == [16, 16]).expect("centre pixel");
        assert!((centre.normal - DVec3::Z).length() < 1e-12);
        // At the facing point v = n, and the light is 45 degrees off.
        assert!((centre.query.v - DVec3::Z).length() < 1e-12);
        assert!((centre.query.l.z - 0.5f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn frame_is_orthonormal_and_right_handed() {
        for n in [DVec3::new(0.3, 0.4, 0.866), DVec3::new(0.0, 1.0, 0.0), DVec3::new(-0.6, -0.8, 0.0)] {
            let n = n.normalize();
            let (t, b, n2) = SphereView::frame(n);
            assert!((t.length() - 1.0).abs() < 1e-12 && (b.length() - 1.0).abs() < 1e-12);
            assert!(t.dot(n).abs() < 1e-12 && b.dot(n).abs() < 1e-12 && t.dot(b).abs() < 1e-12);
            assert!((t.cross(b) - n2).length() < 1e-12);
        }
    }

    #[test]
    fn pixel_count_matches_the_eroded_disc_area() {
        let view = SphereView::new(DVec3::Z, 200);
        let n = view.pixels().len() as f64;
        let want = PI * (100.0 - 1.0f64).powi(2);
        assert!((n - want).abs() / want < 0.01, "{n} vs {want}");
    }

    #[test]
    fn rotated_camera_sees_its_own_direction_at_the_centre() {
        let cam = DVec3::new(0.5, 0.3, 0.8).normalize();
        let view = SphereView::new(DVec3::X, 33).from_camera(cam);
        let centre = view.pixels().into_iter().find(|p| p.pixel == [16, 16]).unwrap();
        assert!((centre.normal - cam).length() < 1e-12);
    }
}
