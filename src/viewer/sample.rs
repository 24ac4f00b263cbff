//! Painting → samples for the viewer, and material → shading for the renderer.
//!
//! Kept apart on purpose: the library is growing its own painting sampler
//! (`scene`/`render`) and `render::Shading::from_material`; when they land, these small
//! functions are the only place the viewer has to change.

use glam::Vec3;

use crate::factor::Query;
use crate::material::Material;
use crate::render::{CoefTexture, FactorTexture, GBuffer, Shading, Term};

/// A pixel that can be a sample: where it is in the picture, where it is on the shading
/// function, and what divides its painted colour into a sample value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    /// Pixel index $j \cdot W + i$.
    pub pixel: u32,
    pub query: Query,
    /// $1 / (\text{colour} \times \text{intensity} \times \text{falloff})$ per channel: a sample value
    /// is the painted colour times this (DESIGN.md, Shading function).
    pub scale: [f64; 3],
}

/// The pixels of a G-buffer that may be samples, in pixel order: the pixel centre sees the
/// object, the viewer is above the shading normal's horizon ($v_z > 0$), the light reaches it
/// (non-zero colour and falloff), and so do all 8 neighbours (silhouette pixels mix object and
/// background paint, so a 1 px band is eroded; DESIGN.md, Silhouette pixels).
pub fn slots(g: &GBuffer, light_rgb: Vec3) -> Vec<Slot> {
    let (w, h) = (g.width, g.height);
    let hit = |i: isize, j: isize| i >= 0 && j >= 0 && i < w as isize && j < h as isize && g.pixels[j as usize * w + i as usize].hit;
    let mut out = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let p = &g.pixels[j * w + i];
            if !p.hit || p.v.z <= 0.0 {
                continue;
            }
            let (ii, jj) = (i as isize, j as isize);
            let inner = (-1..=1).all(|dj| (-1..=1).all(|di| hit(ii + di, jj + dj)));
            if !inner {
                continue;
            }
            let Some(query) = p.query() else { continue };
            let e = light_rgb * p.falloff;
            // NaN fails the test too (a light of non-finite colour is no light).
            if !e.is_finite() || e.min_element() <= 0.0 {
                continue;
            }
            let scale = [1.0 / e.x as f64, 1.0 / e.y as f64, 1.0 / e.z as f64];
            out.push(Slot { pixel: (j * w + i) as u32, query, scale });
        }
    }
    out
}

/// The renderer's form of a material: the same terms, factors, mappings and coefficients.
pub fn shading(material: &Material) -> Shading {
    let terms = material
        .terms
        .iter()
        .map(|t| Term {
            factors: t
                .factors
                .iter()
                .map(|f| FactorTexture { spec: f.spec.clone(), texels: f.texels.clone() })
                .collect(),
            map: t.map,
            coefficients: t.coefficients.as_ref().map(|c| CoefTexture::scalar(c.res, c.res, &c.texels)),
        })
        .collect();
    Shading { terms }
}
