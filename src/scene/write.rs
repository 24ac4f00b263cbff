//! Writing a scene as a self-contained glTF 2.0 file (JSON with the geometry in one embedded
//! base64 `data:` buffer, no .bin beside it), which [`Scene::load`] and Blender read back.

use std::path::Path;

use glam::{Quat, Vec3};
use serde_json::{json, Value};

use super::{Camera, CpuMesh, Light, Projection, Scene};
use crate::error::{Error, Result};

impl Scene {
    /// Writes the scene to `path` as one self-contained .gltf file (the geometry in an
    /// embedded base64 `data:` buffer, so the file can be moved alone): one node per mesh
    /// (identity transform: meshes are already in world space) with POSITION, NORMAL,
    /// TEXCOORD_0 and TANGENT when present, and u32 indices; a camera node (rotation and
    /// translation); a KHR_lights_punctual light node. No materials. Vertex data is stored
    /// bit for bit and JSON numbers exactly (each f32 is written as its f64 value), so
    /// [`Scene::load`] returns the same scene, up to the rounding of the camera's and light's
    /// node rotations (~1e-7). The file is written atomically ([`crate::commit::write_atomic`]).
    ///
    /// A scene with inconsistent meshes or a non-finite camera or light is an
    /// [`Error::Input`], and nothing is written.
    pub fn write_gltf(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        self.check_writable().map_err(|e| Error::input(format!("cannot write {}: {e}", path.display())))?;
        let text = serde_json::to_string(&self.to_gltf_json())
            .map_err(|e| Error::format(path, format!("cannot serialize the scene: {e}")))?;
        crate::commit::write_atomic(path, text.as_bytes())
    }

    /// What glTF cannot hold or [`Scene::load`] would refuse.
    fn check_writable(&self) -> std::result::Result<(), String> {
        if self.meshes.is_empty() {
            return Err("the scene has no mesh".into());
        }
        for (k, mesh) in self.meshes.iter().enumerate() {
            mesh.check().map_err(|e| format!("mesh {k}: {e}"))?;
            if mesh.indices.is_empty() {
                return Err(format!("mesh {k} has no triangles"));
            }
            let finite = mesh.normals.iter().all(|v| v.is_finite())
                && mesh.uvs.iter().flatten().all(|v| v.is_finite())
                && mesh.tangents.iter().flatten().all(|v| v.is_finite());
            if !finite {
                return Err(format!("mesh {k} has non-finite vertex attributes"));
            }
        }
        if !self.camera.world_from_camera.is_finite() {
            return Err("the camera transform is not finite".into());
        }
        let projection_ok = match self.camera.projection {
            Projection::Perspective { yfov, aspect, znear, zfar } => {
                yfov > 0.0 && yfov < std::f32::consts::PI && znear > 0.0 && znear.is_finite()
                    && aspect.is_none_or(|a| a > 0.0 && a.is_finite())
                    && zfar.is_none_or(|f| f > znear && f.is_finite())
            }
            Projection::Orthographic { xmag, ymag, znear, zfar } => {
                xmag != 0.0 && ymag != 0.0 && xmag.is_finite() && ymag.is_finite() && znear >= 0.0 && zfar > znear && zfar.is_finite()
            }
        };
        if !projection_ok {
            return Err(format!("invalid camera projection {:?}", self.camera.projection));
        }
        let (v, color, intensity) = match self.light {
            Light::Directional { direction, color, intensity } => (direction, color, intensity),
            Light::Point { position, color, intensity } => (position, color, intensity),
        };
        let direction_ok = !matches!(self.light, Light::Directional { direction, .. } if direction.length() < 1e-6);
        if !(v.is_finite() && direction_ok && color.is_finite() && color.min_element() >= 0.0 && intensity.is_finite() && intensity >= 0.0) {
            return Err(format!("invalid light {:?}", self.light));
        }
        Ok(())
    }

    /// The glTF JSON document of [`Scene::write_gltf`].
    fn to_gltf_json(&self) -> Value {
        let mut buffer = Buffer::default();
        let meshes: Vec<Value> = self.meshes.iter().enumerate().map(|(k, mesh)| buffer.mesh(k, mesh)).collect();
        let mut nodes: Vec<Value> = (0..meshes.len()).map(|k| json!({ "name": format!("mesh{k}"), "mesh": k })).collect();
        nodes.push(camera_node(&self.camera));
        let (light, light_node) = light_json(&self.light);
        nodes.push(light_node);

        let buffer_uri = format!("data:application/octet-stream;base64,{}", base64(&buffer.bin));
        json!({
            "asset": { "version": "2.0", "generator": concat!("brdfpaint ", env!("CARGO_PKG_VERSION")) },
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": { "KHR_lights_punctual": { "lights": [light] } },
            "scene": 0,
            "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
            "nodes": nodes,
            "meshes": meshes,
            "cameras": [camera_json(&self.camera.projection)],
            "accessors": buffer.accessors,
            "bufferViews": buffer.views,
            "buffers": [{ "byteLength": buffer.bin.len(), "uri": buffer_uri }],
        })
    }
}

const F32: u32 = 5126;
const U32: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// The one binary buffer of the file, with its buffer views and accessors.
#[derive(Default)]
struct Buffer {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Buffer {
    /// Appends one tightly packed attribute and returns its accessor index.
    fn push(&mut self, floats_or_ints: &[u8], count: usize, kind: &str, component: u32, target: u32) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(floats_or_ints);
        // Keep every view 4-byte aligned, as glTF requires for f32 and u32 data.
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": floats_or_ints.len(), "target": target }));
        let accessor = json!({ "bufferView": self.views.len() - 1, "componentType": component, "count": count, "type": kind });
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Appends mesh `k`'s vertex attributes and indices, and returns its glTF mesh.
    fn mesh(&mut self, k: usize, mesh: &CpuMesh) -> Value {
        let n = mesh.positions.len();
        let (lo, hi) = mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ZERO));
        let mut attributes = serde_json::Map::new();
        let position = self.push(&f32_bytes(mesh.positions.iter().flat_map(|p| p.to_array())), n, "VEC3", F32, ARRAY_BUFFER);
        if let (Value::Object(a), Value::Object(e)) =
            (&mut self.accessors[position], json!({ "min": lo.to_array(), "max": hi.to_array() }))
        {
            a.extend(e);
        }
        attributes.insert("POSITION".into(), position.into());
        let normal = self.push(&f32_bytes(mesh.normals.iter().flat_map(|v| v.to_array())), n, "VEC3", F32, ARRAY_BUFFER);
        attributes.insert("NORMAL".into(), normal.into());
        if let Some(t) = &mesh.tangents {
            let tangent = self.push(&f32_bytes(t.iter().flat_map(|v| v.to_array())), n, "VEC4", F32, ARRAY_BUFFER);
            attributes.insert("TANGENT".into(), tangent.into());
        }
        if let Some(uv) = &mesh.uvs {
            let uv = self.push(&f32_bytes(uv.iter().flat_map(|v| v.to_array())), n, "VEC2", F32, ARRAY_BUFFER);
            attributes.insert("TEXCOORD_0".into(), uv.into());
        }
        let index_bytes: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let indices = self.push(&index_bytes, mesh.indices.len(), "SCALAR", U32, ELEMENT_ARRAY_BUFFER);
        json!({
            "name": format!("mesh{k}"),
            "primitives": [{ "attributes": attributes, "indices": indices, "mode": 4 }],
        })
    }
}

/// The glTF camera of `projection`.
fn camera_json(projection: &Projection) -> Value {
    match *projection {
        Projection::Perspective { yfov, aspect, znear, zfar } => {
            let mut p = json!({ "yfov": yfov, "znear": znear });
            if let Some(a) = aspect {
                p["aspectRatio"] = a.into();
            }
            if let Some(f) = zfar {
                p["zfar"] = f.into();
            }
            json!({ "type": "perspective", "perspective": p })
        }
        Projection::Orthographic { xmag, ymag, znear, zfar } => json!({
            "type": "orthographic",
            "orthographic": { "xmag": xmag, "ymag": ymag, "znear": znear, "zfar": zfar },
        }),
    }
}

/// The node that places camera 0.
fn camera_node(camera: &Camera) -> Value {
    // A camera has no scale: write its rotation and position.
    let (_, rotation, translation) = camera.world_from_camera.to_scale_rotation_translation();
    json!({
        "name": "camera",
        "camera": 0,
        "rotation": rotation.normalize().to_array(),
        "translation": translation.to_array(),
    })
}

/// The KHR_lights_punctual light of `light`, and the node that places it.
fn light_json(light: &Light) -> (Value, Value) {
    match *light {
        Light::Directional { direction, color, intensity } => {
            // The node's -Z is the direction the light travels.
            let rotation = Quat::from_rotation_arc(-Vec3::Z, direction.normalize());
            (
                json!({ "type": "directional", "color": color.to_array(), "intensity": intensity }),
                json!({ "name": "light", "rotation": rotation.to_array(), "extensions": { "KHR_lights_punctual": { "light": 0 } } }),
            )
        }
        Light::Point { position, color, intensity } => (
            json!({ "type": "point", "color": color.to_array(), "intensity": intensity }),
            json!({ "name": "light", "translation": position.to_array(), "extensions": { "KHR_lights_punctual": { "light": 0 } } }),
        ),
    }
}

fn f32_bytes(values: impl Iterator<Item = f32>) -> Vec<u8> {
    values.flat_map(f32::to_le_bytes).collect()
}

/// Standard base64 (RFC 4648) with padding.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{frame, sphere_mesh, Preset};
    use glam::{Mat4, Vec2, Vec4};

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (input, expected) in
            [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foob", "Zm9vYg=="), ("fooba", "Zm9vYmE="), ("foobar", "Zm9vYmFy")]
        {
            assert_eq!(base64(input.as_bytes()), expected, "input {input:?}");
        }
    }

    fn close3(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() <= 1e-5
    }

    #[test]
    fn round_trip_framed_sphere() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("scene.gltf");
        let scene = frame(vec![sphere_mesh(24, 12)], &Preset::default(), 4.0 / 3.0);
        scene.write_gltf(&path).unwrap();
        let back = Scene::load(&path).unwrap();

        assert_eq!(back.meshes.len(), 1);
        let (a, b) = (&scene.meshes[0], &back.meshes[0]);
        assert_eq!(a.indices, b.indices);
        assert_eq!(a.positions.len(), b.positions.len());
        for k in 0..a.positions.len() {
            assert!(close3(a.positions[k], b.positions[k]), "position {k}: {} vs {}", a.positions[k], b.positions[k]);
            assert!(close3(a.normals[k], b.normals[k]), "normal {k}");
            let (ua, ub): (Vec2, Vec2) = (a.uvs.as_ref().unwrap()[k], b.uvs.as_ref().unwrap()[k]);
            assert!((ua - ub).abs().max_element() <= 1e-5, "uv {k}");
            let (ta, tb): (Vec4, Vec4) = (a.tangents.as_ref().unwrap()[k], b.tangents.as_ref().unwrap()[k]);
            assert!((ta - tb).abs().max_element() <= 1e-5, "tangent {k}: {ta} vs {tb}");
        }

        let (ca, cb) = (scene.camera, back.camera);
        let diff = (ca.world_from_camera - cb.world_from_camera).to_cols_array().map(f32::abs);
        assert!(diff.iter().all(|&d| d <= 1e-5), "camera\n{}\nvs\n{}", ca.world_from_camera, cb.world_from_camera);
        assert_eq!(ca.projection, cb.projection);

        let (Light::Directional { direction: da, color: ca_, intensity: ia }, Light::Directional { direction: db, color: cb_, intensity: ib }) =
            (scene.light, back.light)
        else {
            panic!("light kind changed: {:?}", back.light)
        };
        assert!(close3(da, db), "light {da} vs {db}");
        assert_eq!((ca_, ia), (cb_, ib));

        // No temporary file is left behind.
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names, vec![std::ffi::OsString::from("scene.gltf")]);
    }

    #[test]
    fn round_trip_point_light_and_orthographic_camera() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ortho.gltf");
        let mut mesh = sphere_mesh(8, 4);
        mesh.uvs = None;
        mesh.tangents = None;
        let scene = Scene {
            meshes: vec![mesh],
            camera: crate::scene::Camera {
                world_from_camera: Mat4::from_translation(Vec3::new(0.0, 0.0, 5.0)),
                projection: Projection::Orthographic { xmag: 2.0, ymag: 1.5, znear: 0.1, zfar: 10.0 },
            },
            light: Light::Point { position: Vec3::new(1.0, 2.0, 3.0), color: Vec3::new(1.0, 0.5, 0.25), intensity: 20.0 },
        };
        scene.write_gltf(&path).unwrap();
        let back = Scene::load(&path).unwrap();
        assert_eq!(back.camera, scene.camera);
        assert_eq!(back.light, scene.light);
        assert!(back.meshes[0].uvs.is_none() && back.meshes[0].tangents.is_none());
    }

    #[test]
    fn unwritable_path_is_an_error_naming_it() {
        let scene = frame(vec![sphere_mesh(8, 4)], &Preset::default(), 1.0);
        let err = scene.write_gltf("/nonexistent-dir/scene.gltf").unwrap_err().to_string();
        assert!(err.contains("/nonexistent-dir/scene.gltf"), "{err}");
    }
}
