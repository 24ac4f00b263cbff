//! A spatially varying test object with a known answer: bands of two analytic BRDFs across
//! the sphere's $u$, like wood grain of a lacquered and a bare wood, for judging material
//! maps and four-factor fits (thesis Table 5.4) on views that were and were not painted.

use glam::DVec3;

use super::{Analytic, Reflectance, SphereView};
use crate::factor::{Pattern, Query};
use crate::factor::Grid;

/// Two BRDFs in alternating bands of equal width in $u$ (band 0, at $u = 0$, is `a`).
#[derive(Clone, Debug, PartialEq)]
pub struct Striped {
    pub a: Analytic,
    pub b: Analytic,
    pub bands: usize,
}

impl Striped {
    /// Glossy dark varnish and matte orange wood, four bands of each.
    pub fn wood() -> Striped {
        Striped {
            a: Analytic::BlinnPhong { diffuse: [0.10, 0.08, 0.05], specular: [0.5, 0.5, 0.5], exponent: 40.0 },
            b: Analytic::Lambert { albedo: [0.55, 0.35, 0.15] },
            bands: 8,
        }
    }

    /// The stripe $\lfloor u \cdot \text{bands} \rfloor \bmod \text{bands}$ that texture
    /// coordinate `u` lies in (0 without bands). Stripes wrap around: $u$ and $u + 1$ are the
    /// same point of a closed surface, so $u = 1$ is stripe 0.
    pub fn band(&self, u: f64) -> usize {
        if self.bands == 0 {
            return 0;
        }
        let x = (u * self.bands as f64).floor().rem_euclid(self.bands as f64);
        // A non-finite u (never from a G-buffer or a sphere view) falls in stripe 0.
        if x.is_finite() { (x as usize).min(self.bands - 1) } else { 0 }
    }

    /// Which BRDF (0: `a`, 1: `b`) is at texture coordinate `u`.
    pub fn region(&self, u: f64) -> usize {
        self.band(u) % 2
    }


    /// Four views that together see every side of the sphere: the first is the usual
    /// upper-left light from the front.
    pub fn painted_views(res: usize) -> Vec<SphereView> {
        vec![
            SphereView::new(DVec3::new(-0.4, 0.5, 1.0), res),
            SphereView::new(DVec3::new(0.6, 0.3, 0.2), res).from_camera(DVec3::new(1.0, 0.1, -0.3)),
            SphereView::new(DVec3::new(0.0, 0.6, -1.0), res).from_camera(DVec3::new(-0.2, 0.2, -1.0)),
            SphereView::new(DVec3::new(-1.0, 0.2, 0.1), res).from_camera(DVec3::new(-1.0, -0.1, 0.2)),
        ]
    }

    /// Held-out views: new lights from cameras on four sides.
    pub fn held_out_views(res: usize) -> Vec<SphereView> {
        vec![
            SphereView::new(DVec3::new(0.7, 0.2, 0.7), res).from_camera(DVec3::new(0.35, 0.1, 0.93)),
            SphereView::new(DVec3::new(-0.2, -0.6, 0.8), res).from_camera(DVec3::new(-0.5, 0.3, 0.8)),
            SphereView::new(DVec3::new(0.3, 0.8, -0.5), res).from_camera(DVec3::new(0.5, 0.3, -0.8)),
            SphereView::new(DVec3::new(-0.5, 0.7, -0.5), res).from_camera(DVec3::new(-0.9, 0.3, 0.1)),
        ]
    }

    /// The samples the views paint, with each view's pixel grid.
    pub fn paint(&self, views: &[SphereView]) -> (Pattern, Vec<[f64; 3]>, Vec<Grid>) {
        let mut queries = Vec::new();
        let mut grids = Vec::new();
        for v in views {
            let mut grid = Grid { width: v.res, height: v.res, sample: vec![None; v.res * v.res] };
            for p in v.pixels() {
                grid.sample[p.pixel[1] * v.res + p.pixel[0]] = Some(queries.len() as u32);
                queries.push(p.query);
            }
            grids.push(grid);
        }
        let values = queries.iter().map(|q| self.shading(q)).collect();
        (Pattern::new(queries, true), values, grids)
    }
}
impl Reflectance for Striped {
    /// The shading function at a query: its uv picks the band's model.
    fn shading(&self, q: &Query) -> [f64; 3] {
        if self.region(q.uv.x) == 0 { &self.a } else { &self.b }.shading(q)
    }
}
