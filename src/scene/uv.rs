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

/// Where texture coordinates come from (`--uv` of `render` and `view`, and the demo): the one
/// rule for models with and without them, so a spatially varying material renders on any
/// model the same way everywhere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UvRule {
    /// The mesh's own texture coordinates; a spherical projection for meshes without them.
    #[default]
    Auto,
    /// Only the mesh's own (a material that needs them is refused on a mesh without).
    Mesh,
    /// A spherical projection about the model's centre, for every mesh ([`spherical_uvs`]).
    Spherical,
    /// A box projection: each vertex projected along its normal's dominant axis onto the
    /// model's bounding box ([`box_uvs`]).
    Box,
}

impl UvRule {
    /// Every rule, in the order the command line lists them.
    pub const ALL: [UvRule; 4] = [UvRule::Auto, UvRule::Mesh, UvRule::Spherical, UvRule::Box];

    /// The rule's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            UvRule::Auto => "auto",
            UvRule::Mesh => "mesh",
            UvRule::Spherical => "spherical",
            UvRule::Box => "box",
        }
    }

    /// Applies the rule to `meshes`; with it, a note for the user when a projection replaced
    /// or stood in for the mesh's own coordinates.
    pub fn apply(self, meshes: Vec<CpuMesh>) -> (Vec<CpuMesh>, Option<String>) {
        let missing = meshes.iter().filter(|m| m.uvs.is_none()).count();
        match self {
            UvRule::Mesh => (meshes, None),
            UvRule::Auto if missing == 0 => (meshes, None),
            UvRule::Auto => (
                spherical_uvs(meshes),
                Some(format!("{missing} mesh(es) without texture coordinates get a spherical projection")),
            ),
            UvRule::Spherical => {
                let cleared = meshes.into_iter().map(|m| CpuMesh { uvs: None, ..m }).collect();
                (spherical_uvs(cleared), Some("texture coordinates from a spherical projection".into()))
            }
            UvRule::Box => (box_uvs(meshes), Some("texture coordinates from a box projection".into())),
        }
    }
}

impl std::str::FromStr for UvRule {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        UvRule::ALL.into_iter().find(|r| r.name() == s).ok_or_else(|| {
            let names: Vec<&str> = UvRule::ALL.iter().map(|r| r.name()).collect();
            format!("'{s}' is not a uv rule ({})", names.join(", "))
        })
    }
}

/// Every mesh's texture coordinates from a box projection: a vertex whose normal points
/// mostly along axis k gets the other two coordinates of its position, scaled to [0, 1] by
/// the bounding box of all meshes (u along the first remaining axis, v down the second).
pub fn box_uvs(mut meshes: Vec<CpuMesh>) -> Vec<CpuMesh> {
    let (lo, hi) = meshes
        .iter()
        .flat_map(|m| m.positions.iter())
        .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let size = (hi - lo).max(Vec3::splat(1e-12));
    for m in &mut meshes {
        let uvs = m
            .positions
            .iter()
            .zip(&m.normals)
            .map(|(&p, &n)| {
                let t = (p - lo) / size;
                let a = n.abs();
                if a.x >= a.y && a.x >= a.z {
                    Vec2::new(t.z, 1.0 - t.y)
                } else if a.y >= a.z {
                    Vec2::new(t.x, 1.0 - t.z)
                } else {
                    Vec2::new(t.x, 1.0 - t.y)
                }
            })
            .collect();
        m.uvs = Some(uvs);
    }
    meshes
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin_model;

    #[test]
    fn auto_keeps_mesh_uvs_and_projects_where_there_are_none() {
        let sphere = builtin_model("sphere").unwrap();
        let (same, note) = UvRule::Auto.apply(sphere.clone());
        assert_eq!(same[0].uvs, sphere[0].uvs);
        assert!(note.is_none());
        let bare = vec![CpuMesh { uvs: None, ..sphere[0].clone() }];
        let (projected, note) = UvRule::Auto.apply(bare.clone());
        assert!(note.unwrap().contains("spherical"));
        // The projection of the sphere is the sphere's own layout (away from the seam).
        for (a, b) in projected[0].uvs.as_ref().unwrap().iter().zip(sphere[0].uvs.as_ref().unwrap()) {
            // Away from the seam and the poles, where u is arbitrary.
            if a.x > 0.01 && a.x < 0.99 && a.y > 0.01 && a.y < 0.99 {
                assert!((*a - *b).length() < 1e-4, "{a} vs {b}");
            }
        }
        assert!(UvRule::Mesh.apply(bare).0[0].uvs.is_none());
    }

    #[test]
    fn box_projects_each_vertex_along_its_dominant_normal_axis() {
        let m = CpuMesh {
            positions: vec![Vec3::new(1.0, 0.5, 0.25), Vec3::new(-1.0, -1.0, -1.0), Vec3::new(0.0, 1.0, 1.0)],
            normals: vec![Vec3::X, -Vec3::Y, Vec3::Z],
            indices: vec![0, 1, 2],
            ..Default::default()
        };
        let uv = box_uvs(vec![m])[0].uvs.clone().unwrap();
        // Bounding box [-1, 1]^3: t = (p + 1) / 2.
        assert!((uv[0] - Vec2::new(0.625, 0.25)).length() < 1e-6, "{}", uv[0]);
        assert!((uv[1] - Vec2::new(0.0, 1.0)).length() < 1e-6, "{}", uv[1]);
        assert!((uv[2] - Vec2::new(0.5, 0.0)).length() < 1e-6, "{}", uv[2]);
        assert_eq!("box".parse::<UvRule>(), Ok(UvRule::Box));
        assert!("cube".parse::<UvRule>().unwrap_err().contains("auto, mesh, spherical, box"));
    }
}
