//! Meshes on the GPU, and small analytic meshes for tests and presets.

use std::f32::consts::PI;

use glam::{Vec2, Vec3, Vec4};

use crate::error::{Error, Result};
use crate::gl::{Buffer, Gl, VertexArray};
use crate::scene::CpuMesh;

/// Attribute locations (shaders/mesh.vert).
pub(crate) const ATTR_POSITION: u32 = 0;
pub(crate) const ATTR_NORMAL: u32 = 1;
pub(crate) const ATTR_TANGENT: u32 = 2;
pub(crate) const ATTR_UV: u32 = 3;

/// A [`CpuMesh`] uploaded to the GPU: one buffer per attribute and an index buffer, bound in
/// a vertex array.
pub struct Mesh {
    vao: VertexArray,
    _buffers: Vec<Buffer>,
    _indices: Buffer,
    index_count: usize,
}

impl Mesh {
    /// Uploads `cpu`. Meshes without tangents get $t = \mathrm{normalize}(\hat y \times n)$
    /// (the azimuthal tangent of src/brdf/sphere.rs; $x$ projected where $n \parallel y$),
    /// handedness +1; meshes without uvs get uv = 0.
    ///
    /// Errors ([`Error::Input`]): attribute arrays of different lengths, a triangle list whose
    /// length is not a multiple of 3, an index out of range, non-finite values.
    pub fn upload(gl: &Gl, cpu: &CpuMesh) -> Result<Mesh> {
        validate(cpu)?;
        let n = cpu.positions.len();
        let flat3 = |v: &[Vec3]| v.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
        let tangents: Vec<f32> = match &cpu.tangents {
            Some(t) => t.iter().flat_map(|t| t.to_array()).collect(),
            None => cpu.normals.iter().flat_map(|&n| fallback_tangent(n).to_array()).collect(),
        };
        let uvs: Vec<f32> = match &cpu.uvs {
            Some(uv) => uv.iter().flat_map(|t| t.to_array()).collect(),
            None => vec![0.0; 2 * n],
        };
        let vao = VertexArray::new(gl)?;
        let buffers = vec![
            Buffer::vertices(gl, &flat3(&cpu.positions))?,
            Buffer::vertices(gl, &flat3(&cpu.normals))?,
            Buffer::vertices(gl, &tangents)?,
            Buffer::vertices(gl, &uvs)?,
        ];
        vao.attribute(ATTR_POSITION, &buffers[0], 3);
        vao.attribute(ATTR_NORMAL, &buffers[1], 3);
        vao.attribute(ATTR_TANGENT, &buffers[2], 4);
        vao.attribute(ATTR_UV, &buffers[3], 2);
        // The element buffer binding is recorded in the bound vertex array.
        vao.bind();
        let indices = Buffer::indices(gl, &cpu.indices)?;
        // SAFETY: unbinding the vertex array keeps later buffer binds out of it.
        unsafe { glow::HasContext::bind_vertex_array(&**gl, None) };
        crate::gl_check!(gl, "mesh upload");
        Ok(Mesh { vao, _buffers: buffers, _indices: indices, index_count: cpu.indices.len() })
    }

    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.index_count / 3
    }

    /// Draws its triangles with the bound program (GL state: binds its vertex array, then
    /// unbinds it).
    pub(crate) fn draw(&self, gl: &Gl) {
        if self.index_count == 0 {
            return;
        }
        self.vao.bind();
        // SAFETY: the vertex array holds a u32 element buffer of index_count valid indices
        // (checked at upload).
        unsafe {
            glow::HasContext::draw_elements(&**gl, glow::TRIANGLES, self.index_count as i32, glow::UNSIGNED_INT, 0);
            glow::HasContext::bind_vertex_array(&**gl, None);
        }
    }
}

impl std::fmt::Debug for Mesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Mesh").field("triangles", &self.triangles()).finish()
    }
}

/// The tangent a mesh without tangents gets: the azimuthal direction about world $+y$.
pub fn fallback_tangent(n: Vec3) -> Vec4 {
    let t = Vec3::Y.cross(n);
    let t = if t.length_squared() > 1e-12 { t.normalize() } else { (Vec3::X - n * n.x).normalize_or(Vec3::X) };
    t.extend(1.0)
}

fn validate(m: &CpuMesh) -> Result<()> {
    let n = m.positions.len();
    let bad_len = |what: &str, len: usize| {
        Error::input(format!("mesh has {n} positions but {len} {what}: every vertex needs one"))
    };
    if m.normals.len() != n {
        return Err(bad_len("normals", m.normals.len()));
    }
    if let Some(t) = &m.tangents {
        if t.len() != n {
            return Err(bad_len("tangents", t.len()));
        }
    }
    if let Some(uv) = &m.uvs {
        if uv.len() != n {
            return Err(bad_len("uvs", uv.len()));
        }
    }
    if m.indices.len() % 3 != 0 {
        return Err(Error::input(format!(
            "mesh has {} indices, not a multiple of 3 (a triangle list)",
            m.indices.len()
        )));
    }
    if let Some(&i) = m.indices.iter().find(|&&i| i as usize >= n) {
        return Err(Error::input(format!("mesh index {i} is out of range ({n} vertices)")));
    }
    if m.indices.len() > i32::MAX as usize {
        return Err(Error::input(format!("mesh has {} indices, too many to draw", m.indices.len())));
    }
    let finite = m.positions.iter().all(|p| p.is_finite())
        && m.normals.iter().all(|p| p.is_finite())
        && m.tangents.as_ref().is_none_or(|t| t.iter().all(|p| p.is_finite()))
        && m.uvs.as_ref().is_none_or(|t| t.iter().all(|p| p.is_finite()));
    if !finite {
        return Err(Error::input("mesh has a NaN or infinite vertex attribute"));
    }
    Ok(())
}

/// A unit sphere at `centre` with radius `radius`, `segments` around the pole axis world
/// $+y$ and `rings` from pole to pole. The conventions of src/brdf/sphere.rs:
/// $u = \mathrm{atan2}(x, z)/2\pi + 0.5$, $v = \arccos(y)/\pi$ (of the unit normal), tangent
/// $\mathrm{normalize}(\hat y \times n)$ with handedness +1, and at the poles the tangent of
/// the vertex's azimuth. The seam at $u = 0/1$ and the poles have duplicated vertices.
pub fn uv_sphere(centre: Vec3, radius: f32, segments: usize, rings: usize) -> CpuMesh {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let mut m = CpuMesh::default();
    let (mut tangents, mut uvs) = (Vec::new(), Vec::new());
    for r in 0..=rings {
        let v = r as f32 / rings as f32;
        let theta = v * PI;
        for s in 0..=segments {
            let u = s as f32 / segments as f32;
            // $\phi = \mathrm{atan2}(x, z)$, so $x = \sin\theta \sin\phi$, $z = \sin\theta\cos\phi$.
            let phi = (u - 0.5) * 2.0 * PI;
            let n = Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos());
            m.positions.push(centre + radius * n);
            m.normals.push(n);
            // $\hat y \times n \propto (\cos\phi, 0, -\sin\phi)$, also defined at the poles.
            tangents.push(Vec4::new(phi.cos(), 0.0, -phi.sin(), 1.0));
            uvs.push(Vec2::new(u, v));
        }
    }
    let row = segments as u32 + 1;
    for r in 0..rings as u32 {
        for s in 0..segments as u32 {
            let (a, b) = (r * row + s, r * row + s + 1);
            let (c, d) = (a + row, b + row);
            // Counter-clockwise seen from outside; degenerate pole triangles are skipped.
            if r != 0 {
                m.indices.extend([a, c, b]);
            }
            if r + 1 != rings as u32 {
                m.indices.extend([b, c, d]);
            }
        }
    }
    m.tangents = Some(tangents);
    m.uvs = Some(uvs);
    m
}

/// An axis-aligned cube of half extent `half` at `centre`, flat-shaded (4 vertices per
/// face), with per-face uvs and tangents. Its edges are creases, for outline tests.
pub fn cube(centre: Vec3, half: f32) -> CpuMesh {
    let mut m = CpuMesh::default();
    let (mut tangents, mut uvs) = (Vec::new(), Vec::new());
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            // Tangent and bitangent spanning the face, with t × b = n.
            let t = {
                let mut t = Vec3::ZERO;
                t[(axis + 1) % 3] = 1.0;
                t
            };
            let b = n.cross(t);
            let base = m.positions.len() as u32;
            for (du, dv) in [(0.0f32, 0.0f32), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                let p = centre + half * (n + t * (2.0 * du - 1.0) + b * (2.0 * dv - 1.0));
                m.positions.push(p);
                m.normals.push(n);
                tangents.push(t.extend(1.0));
                uvs.push(Vec2::new(du, dv));
            }
            m.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    m.tangents = Some(tangents);
    m.uvs = Some(uvs);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_attributes_follow_the_analytic_sphere_conventions() {
        let m = uv_sphere(Vec3::ZERO, 1.0, 16, 8);
        let (t, uv) = (m.tangents.as_ref().unwrap(), m.uvs.as_ref().unwrap());
        for k in 0..m.positions.len() {
            let n = m.normals[k];
            assert!((m.positions[k] - n).length() < 1e-6);
            assert!((n.length() - 1.0).abs() < 1e-6);
            if n.y.abs() < 0.999 {
                // u = atan2(x, z)/2pi + 0.5, except on the seam where u = 0 and 1 coincide.
                let u = n.x.atan2(n.z) / (2.0 * PI) + 0.5;
                assert!((uv[k].x - u).abs() < 1e-5 || (uv[k].x - u).abs() > 0.99999, "{k}: {} vs {u}", uv[k].x);
                let want = Vec3::Y.cross(n).normalize();
                assert!((t[k].truncate() - want).length() < 1e-5);
            }
            assert!((uv[k].y - n.y.clamp(-1.0, 1.0).acos() / PI).abs() < 1e-5);
        }
        assert_eq!(m.indices.len(), 3 * (2 * 16 * 8 - 2 * 16));
    }

    #[test]
    fn sphere_triangles_face_outward() {
        let m = uv_sphere(Vec3::ZERO, 1.0, 12, 6);
        for tri in m.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions[tri[k] as usize]);
            let normal = (b - a).cross(c - a);
            assert!(normal.dot(a + b + c) > 0.0);
        }
    }

    #[test]
    fn cube_faces_are_right_handed() {
        let m = cube(Vec3::ZERO, 1.0);
        let t = m.tangents.as_ref().unwrap();
        for ((p, n), t) in m.positions.iter().zip(&m.normals).zip(t) {
            assert!(p.dot(*n) > 0.99);
            assert!(t.truncate().dot(*n).abs() < 1e-6);
        }
        for tri in m.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| m.positions[tri[k] as usize]);
            assert!((b - a).cross(c - a).dot(m.normals[tri[0] as usize]) > 0.0);
        }
    }

    #[test]
    fn invalid_meshes_are_rejected() {
        let mut m = uv_sphere(Vec3::ZERO, 1.0, 8, 4);
        m.indices.extend([0, 1, 10_000]);
        assert!(validate(&m).unwrap_err().to_string().contains("out of range"));
        let mut m = uv_sphere(Vec3::ZERO, 1.0, 8, 4);
        m.normals.pop();
        assert!(validate(&m).is_err());
        let mut m = uv_sphere(Vec3::ZERO, 1.0, 8, 4);
        m.positions[3].x = f32::NAN;
        assert!(validate(&m).is_err());
    }
}
