//! Operations on [`CpuMesh`]: world transforms, generated smooth normals, MikkTSpace tangents,
//! bounds.

use std::collections::HashMap;

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::CpuMesh;
use crate::error::{Error, Result};

/// A sphere containing a set of points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    pub center: Vec3,
    pub radius: f32,
}

impl BoundingSphere {
    /// The sphere centred on the axis-aligned bounding box of all vertices of `meshes`, with the
    /// radius reaching the farthest vertex. Not the minimal sphere, but deterministic and at most
    /// $\sqrt 3$ times too large only in degenerate cases. `None` when there are no vertices.
    pub fn of(meshes: &[CpuMesh]) -> Option<BoundingSphere> {
        let mut points = meshes.iter().flat_map(|m| m.positions.iter().copied()).peekable();
        points.peek()?;
        let (lo, hi) = points.fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        });
        let center = 0.5 * (lo + hi);
        let radius = meshes
            .iter()
            .flat_map(|m| m.positions.iter())
            .map(|p| p.distance(center))
            .fold(0.0f32, f32::max);
        Some(BoundingSphere { center, radius })
    }
}

impl CpuMesh {
    /// Axis-aligned bounds `(min, max)` of the positions; `None` for an empty mesh.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        if self.positions.is_empty() {
            return None;
        }
        Some(self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        ))
    }

    /// Applies `world_from_local` to the mesh: positions by the matrix, normals by the inverse
    /// transpose of its 3×3 part (renormalized), tangents by the 3×3 part (renormalized; `w`
    /// flips with a mirroring matrix so that the bitangent $n \times t \cdot w$ stays the
    /// transformed bitangent). A mirroring matrix (negative determinant) also reverses the
    /// triangle winding, as glTF prescribes, so front faces stay counter-clockwise.
    pub fn transform(&mut self, world_from_local: Mat4) {
        if world_from_local == Mat4::IDENTITY {
            return;
        }
        let linear = Mat3::from_mat4(world_from_local);
        let det = linear.determinant();
        // A singular matrix (zero scale) has no inverse transpose; keep the normals' directions.
        let normal_matrix = if det.abs() > f32::MIN_POSITIVE { linear.inverse().transpose() } else { Mat3::IDENTITY };
        for p in &mut self.positions {
            *p = world_from_local.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = (normal_matrix * *n).normalize_or(*n);
        }
        if let Some(tangents) = &mut self.tangents {
            let sign = if det < 0.0 { -1.0 } else { 1.0 };
            for t in tangents.iter_mut() {
                let xyz = (linear * t.truncate()).normalize_or(t.truncate());
                *t = xyz.extend(t.w * sign);
            }
        }
        if det < 0.0 {
            for tri in self.indices.chunks_exact_mut(3) {
                tri.swap(1, 2);
            }
        }
    }

    /// Replaces the normals with smooth, angle-weighted vertex normals (Thürmer and Wüthrich
    /// 1998): each face adds its unit normal times its angle at the vertex,
    /// $n_v = \mathrm{normalize}\left(\sum_{f \ni v} \alpha_{f,v}\, \hat n_f\right)$, which
    /// does not depend on how the surface is triangulated. Vertices at the same position (the
    /// split vertices of uv or normal seams) are welded first, so they all get the same
    /// normal. Front faces are counter-clockwise, so the normals of a closed mesh point
    /// outward.
    pub fn generate_normals(&mut self) {
        // Weld by exact position; -0.0 and 0.0 are the same point.
        let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
        let mut group_of_key: HashMap<[u32; 3], usize> = HashMap::new();
        let groups: Vec<usize> = self
            .positions
            .iter()
            .map(|&p| {
                let next = group_of_key.len();
                *group_of_key.entry(key(p)).or_insert(next)
            })
            .collect();
        let mut sums = vec![Vec3::ZERO; group_of_key.len()];
        for tri in self.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| i as usize);
            let p = [self.positions[a], self.positions[b], self.positions[c]];
            // A degenerate face has no normal; it adds nothing.
            let Some(face_normal) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else { continue };
            for (k, v) in [a, b, c].into_iter().enumerate() {
                let (e1, e2) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
                let angle = e1.angle_between(e2);
                if angle.is_finite() {
                    sums[groups[v]] += angle * face_normal;
                }
            }
        }
        // A vertex used by no face, or only by degenerate ones, has no normal; +Z keeps the
        // contract (unit normals) without inventing anything the renderer could notice.
        self.normals = groups.iter().map(|&g| sums[g].normalize_or(Vec3::Z)).collect();
    }

    /// Applies one matrix per vertex (a skin's blended joint matrices), as [`CpuMesh::transform`]
    /// does for one: positions by the matrix, normals by the inverse transpose of its 3×3
    /// part, tangents by the 3×3 part. The winding is reversed when most vertices' matrices
    /// mirror.
    pub fn transform_per_vertex(&mut self, world_from_local: &[Mat4]) {
        assert_eq!(world_from_local.len(), self.positions.len(), "one matrix per vertex");
        let mut mirrored = 0usize;
        for (v, m) in world_from_local.iter().enumerate() {
            let linear = Mat3::from_mat4(*m);
            let det = linear.determinant();
            mirrored += usize::from(det < 0.0);
            self.positions[v] = m.transform_point3(self.positions[v]);
            if let Some(n) = self.normals.get_mut(v) {
                let normal_matrix =
                    if det.abs() > f32::MIN_POSITIVE { linear.inverse().transpose() } else { Mat3::IDENTITY };
                *n = (normal_matrix * *n).normalize_or(*n);
            }
            if let Some(t) = self.tangents.as_mut().and_then(|t| t.get_mut(v)) {
                let xyz = (linear * t.truncate()).normalize_or(t.truncate());
                *t = xyz.extend(if det < 0.0 { -t.w } else { t.w });
            }
        }
        if 2 * mirrored > world_from_local.len() {
            for tri in self.indices.chunks_exact_mut(3) {
                tri.swap(1, 2);
            }
        }
    }

    /// Makes MikkTSpace tangents (bevy_mikktspace, the reference algorithm) when the mesh has
    /// none. Needs texture coordinates: a mesh without them is an [`Error::Input`].
    ///
    /// The tangent follows increasing $u$. glTF's $v$ runs down the texture image, and glTF's
    /// bitangent $b = (n \times t)\,w$ points up the image (towards decreasing $v$: the +Y of
    /// a glTF normal map), so MikkTSpace is fed $(u, 1 - v)$. An unmirrored layout then gets
    /// $w = +1$, and on the built-in sphere the frame $(t, n \times t, n)$ is exactly
    /// [`crate::brdf::SphereView::frame`].
    pub fn ensure_tangents(&mut self) -> Result<()> {
        if self.tangents.is_some() {
            return Ok(());
        }
        let Some(uvs) = &self.uvs else {
            return Err(Error::input(
                "the mesh has no texture coordinates (TEXCOORD_0), which tangents need",
            ));
        };
        let mut geometry = MikkGeometry {
            mesh: self,
            uvs,
            tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); self.positions.len()],
        };
        bevy_mikktspace::generate_tangents(&mut geometry)
            .map_err(|e| Error::input(format!("MikkTSpace tangent generation failed: {e:?}")))?;
        let tangents = geometry.tangents;
        self.tangents = Some(tangents);
        Ok(())
    }

    /// Replaces the tangents with the azimuthal field about +Y, $t = \mathrm{normalize}(\hat y
    /// \times n)$, $w = +1$ (near the poles, where that vanishes, +X projected onto the
    /// tangent plane): the frame of [`crate::brdf::SphereView::frame`]. A tangent frame for
    /// 2D factors on meshes without texture coordinates, where MikkTSpace has nothing to
    /// follow.
    pub fn azimuthal_tangents(&mut self) {
        self.tangents = Some(
            self.normals
                .iter()
                .map(|&n| {
                    let t = Vec3::Y.cross(n);
                    let t = if t.length_squared() > 1e-12 { t.normalize() } else { (Vec3::X - n * n.x).normalize_or(Vec3::X) };
                    t.extend(1.0)
                })
                .collect(),
        );
    }

    /// Checks the mesh invariants the renderer relies on: matching attribute lengths, a whole
    /// number of triangles, indices in range, finite positions.
    pub(crate) fn check(&self) -> std::result::Result<(), String> {
        let n = self.positions.len();
        if self.normals.len() != n {
            return Err(format!("{} normals for {n} positions", self.normals.len()));
        }
        if let Some(uvs) = &self.uvs {
            if uvs.len() != n {
                return Err(format!("{} texture coordinates for {n} positions", uvs.len()));
            }
        }
        if let Some(t) = &self.tangents {
            if t.len() != n {
                return Err(format!("{} tangents for {n} positions", t.len()));
            }
        }
        if self.indices.len() % 3 != 0 {
            return Err(format!("{} indices is not a whole number of triangles", self.indices.len()));
        }
        if let Some(&bad) = self.indices.iter().find(|&&i| i as usize >= n) {
            return Err(format!("index {bad} out of range for {n} vertices"));
        }
        if self.positions.iter().any(|p| !p.is_finite()) {
            return Err("non-finite vertex position".into());
        }
        Ok(())
    }
}

/// The view of a mesh that bevy_mikktspace reads, and the tangents it writes.
struct MikkGeometry<'a> {
    mesh: &'a CpuMesh,
    uvs: &'a [glam::Vec2],
    tangents: Vec<Vec4>,
}

impl MikkGeometry<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.mesh.indices[face * 3 + vert] as usize
    }
}

impl bevy_mikktspace::Geometry for MikkGeometry<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.vertex(face, vert)].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.vertex(face, vert)].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        // Flip v: see `CpuMesh::ensure_tangents`.
        let uv = self.uvs[self.vertex(face, vert)];
        [uv.x, 1.0 - uv.y]
    }
    fn set_tangent(&mut self, tangent_space: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
        // A vertex of an isolated degenerate face gets no tangent space; the default (+X, w = 1)
        // is as good as any there.
        let t = tangent_space.map_or([1.0, 0.0, 0.0, 1.0], |ts| ts.tangent_encoded());
        let v = self.vertex(face, vert);
        self.tangents[v] = Vec4::from_array(t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    /// The faces of [`split_cube`]: outward normal and the in-face axes u and v.
    const CUBE_FACES: [(Vec3, Vec3, Vec3); 6] = [
        (Vec3::X, Vec3::Y, Vec3::Z),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::Z, Vec3::X),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::Y, Vec3::X),
    ];

    /// A unit cube with 24 split vertices (4 per face), CCW outward, without normals.
    pub(crate) fn split_cube() -> CpuMesh {
        let mut m = CpuMesh::default();
        let mut uvs = Vec::new();
        for (n, u, v) in CUBE_FACES {
            let base = m.positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                m.positions.push(n + a * u + b * v);
                uvs.push(Vec2::new(0.5 + 0.5 * a, 0.5 + 0.5 * b));
            }
            // u × v = n for every face above, so (0,1,2) is CCW seen from outside.
            m.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        m.uvs = Some(uvs);
        m
    }

    #[test]
    fn cube_normals_are_welded_and_outward() {
        let mut cube = split_cube();
        cube.generate_normals();
        for (p, n) in cube.positions.iter().zip(&cube.normals) {
            assert!((n.length() - 1.0).abs() < 1e-6, "normal {n} not unit at {p}");
            // Welding makes every corner normal the corner's diagonal.
            assert!(n.dot(p.normalize()) > 1.0 - 1e-5, "corner {p} has normal {n}");
        }
    }

    #[test]
    fn sphere_normals_point_outward() {
        let mut s = crate::scene::sphere_mesh(24, 12);
        let given = s.normals.clone();
        s.generate_normals();
        for ((p, n), g) in s.positions.iter().zip(&s.normals).zip(&given) {
            assert!(n.dot(*p) > 0.99, "normal {n} at {p} does not point outward");
            assert!(n.dot(*g) > 0.99, "generated {n} far from analytic {g} at {p}");
        }
    }

    #[test]
    fn mirroring_transform_keeps_outward_normals_and_ccw() {
        let mut cube = split_cube();
        cube.generate_normals();
        let before = cube.clone();
        cube.transform(Mat4::from_scale(Vec3::new(-2.0, 1.0, 1.0)));
        for k in 0..cube.positions.len() {
            // p' = (-2x, y, z); the normal goes by the inverse transpose diag(-1/2, 1, 1).
            let (p0, n0) = (before.positions[k], before.normals[k]);
            assert_eq!(cube.positions[k], Vec3::new(-2.0 * p0.x, p0.y, p0.z));
            let expected = Vec3::new(-0.5 * n0.x, n0.y, n0.z).normalize();
            assert!((cube.normals[k] - expected).length() < 1e-6, "normal {} vs {expected}", cube.normals[k]);
            assert!(cube.normals[k].dot(cube.positions[k]) > 0.0, "inward normal at {}", cube.positions[k]);
        }
        // The winding was reversed, so faces are still counter-clockwise seen from outside.
        for tri in cube.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| cube.positions[tri[k] as usize]);
            assert!((b - a).cross(c - a).dot(a + b + c) > 0.0, "inward triangle {tri:?}");
        }
    }

    #[test]
    fn per_vertex_transform_matches_uniform_one() {
        let mut a = split_cube();
        a.generate_normals();
        a.ensure_tangents().unwrap();
        let mut b = a.clone();
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(1.0, 3.0, 0.5),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(1.0, 2.0, 3.0),
        );
        a.transform(m);
        b.transform_per_vertex(&vec![m; b.positions.len()]);
        assert_eq!(a.indices, b.indices);
        for k in 0..a.positions.len() {
            assert!((a.positions[k] - b.positions[k]).length() < 1e-5);
            assert!((a.normals[k] - b.normals[k]).length() < 1e-6);
            let (ta, tb) = (a.tangents.as_ref().unwrap()[k], b.tangents.as_ref().unwrap()[k]);
            assert!((ta - tb).length() < 1e-6);
        }
    }

    #[test]
    fn tangents_follow_u_and_need_uvs() {
        let mut cube = split_cube();
        cube.generate_normals();
        let mut no_uv = cube.clone();
        no_uv.uvs = None;
        let err = no_uv.ensure_tangents().unwrap_err().to_string();
        assert!(err.contains("texture coordinates"), "{err}");

        cube.ensure_tangents().unwrap();
        let t = cube.tangents.as_ref().unwrap();
        assert_eq!(t.len(), cube.positions.len());
        // Face k of `split_cube` has axes (n, u, v), 4 vertices each, position n + a u + b v and
        // uv (0.5 + 0.5 a, 0.5 + 0.5 b): texture u runs along the face's u axis.
        for (i, t) in t.iter().enumerate() {
            let n = cube.normals[i];
            let (_, u, v) = CUBE_FACES[i / 4];
            // The face's u axis projected onto the tangent plane of the (smooth, diagonal)
            // vertex normal: MikkTSpace's tangent.
            let expected = (u - u.dot(n) * n).normalize();
            assert!((t.truncate() - expected).length() < 1e-4, "tangent {t} at vertex {i}, expected {expected}");
            assert!(t.truncate().dot(n).abs() < 1e-5);
            // Seen from outside (n towards the viewer) u is right and texture v runs up the
            // screen along v, while glTF's v runs down the image: the layout is mirrored, so
            // w = -1 and the bitangent (n × t) w points along -v (towards decreasing v).
            assert_eq!(t.w, -1.0, "w at vertex {i}");
            let bitangent = n.cross(t.truncate()) * t.w;
            assert!(bitangent.dot(-v) > 0.7, "bitangent {bitangent} at vertex {i}");
        }
    }

    #[test]
    fn bounding_sphere_contains_all_points() {
        let cube = split_cube();
        let s = BoundingSphere::of(std::slice::from_ref(&cube)).unwrap();
        assert!(s.center.length() < 1e-6);
        assert!((s.radius - 3f32.sqrt()).abs() < 1e-6);
        assert!(BoundingSphere::of(&[]).is_none());
    }
}
