//! The pixels of a painted view that are samples, through the library's sampler
//! ([`crate::sample`]): the same pixels, queries and light as `brdfpaint fit --scene
//! --image`, so the live fit of a painting is the fit the command line makes of it.

use crate::error::Result;
use crate::factor::Query;
use crate::render::GBuffer;
use crate::sample::{scene::geometry_from_gbuffer, Erosion};
use crate::scene::Scene;

/// A pixel that can be a sample: where it is in the picture, where it is on the shading
/// function, and what divides its painted colour into a sample value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    /// Pixel index $j \cdot W + i$.
    pub pixel: u32,
    pub query: Query,
    /// Colour × intensity × falloff of the light at the pixel: a sample value is the
    /// painted colour divided by it (DESIGN.md, Shading function).
    pub light: [f64; 3],
}

/// The usable pixels of `scene`'s G-buffer `g`, in pixel order (front-facing, off the
/// eroded silhouette band; see [`geometry_from_gbuffer`]), and whether the queries carry
/// texture coordinates.
pub fn slots(g: &GBuffer, scene: &Scene) -> Result<(Vec<Slot>, bool)> {
    let has_uv = scene.meshes.iter().all(|m| m.uvs.is_some());
    let geometry = geometry_from_gbuffer(g, &scene.light, has_uv, Erosion::default())?;
    let slots = geometry
        .pixels
        .iter()
        .zip(&geometry.usable)
        .enumerate()
        .filter_map(|(k, (p, &usable))| {
            let p = p.as_ref().filter(|_| usable)?;
            Some(Slot { pixel: k as u32, query: p.query, light: p.light })
        })
        .collect();
    Ok((slots, has_uv))
}
