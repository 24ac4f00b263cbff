//! Texture coordinates for meshes that have none, so that spatially varying materials (a uv
//! factor, coefficient textures) render on any model.

use glam::{Vec2, Vec3};

use super::{BoundingSphere, CpuMesh};

/// `meshes` with texture coordinates where they have none: the built-in sphere's $(u, v)$
/// (`sphere_mesh`: $u = \mathrm{atan2}(x, z)/2\pi + \tfrac12$, $v = \arccos y/\pi$) of the
/// direction from the model's centre, so that a material map painted on the sphere wraps
/// around another model as it wrapped around the sphere. Meshes without uvs would otherwise
/// read every coefficient texture at uv = 0 (`render::Mesh::upload`): one stripe everywhere.
/// Tangents are left as they are (none: the renderer's azimuthal fallback), so uniform
/// materials render exactly as before.
pub fn spherical_uvs(mut meshes: Vec<CpuMesh>) -> Vec<CpuMesh> {
    let centre = BoundingSphere::of(&meshes).map_or(Vec3::ZERO, |b| b.center);
    for m in meshes.iter_mut().filter(|m| m.uvs.is_none()) {
        let uvs = m
            .positions
            .iter()
            .map(|&p| {
                let d = (p - centre).normalize_or(Vec3::Y);
                let u = d.x.atan2(d.z) / std::f32::consts::TAU + 0.5;
                Vec2::new(u, d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI)
            })
            .collect();
        m.uvs = Some(uvs);
    }
    meshes
}
