//! Writing a model with its material as one glTF 2.0 binary (.glb): the meshes, a
//! metallic-roughness material ([`super::pbr`]) that every viewer draws, optional PNG
//! textures for a material map, and the exact factored material packed under our extension
//! ([`crate::material::packed`]), which `brdfpaint render` and `view` read back.

use std::path::Path;

use glam::Vec3;
use serde_json::{json, Map, Value};

use super::pbr::Pbr;
use crate::error::{Error, Result};
use crate::material::packed::{File, EXTENSION, EXTENSION_VERSION};
use crate::scene::CpuMesh;

const F32: u32 = 5126;
const U32: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// PNG textures of a material map's PBR parameters over uv.
#[derive(Clone, Debug)]
pub struct Textures {
    /// `baseColorTexture` (sRGB PNG, as glTF requires).
    pub base_color: Vec<u8>,
    /// `metallicRoughnessTexture` (linear PNG: roughness in green, metallic in blue).
    pub metallic_roughness: Vec<u8>,
    /// `KHR_materials_specular`'s `specularColorTexture` (sRGB PNG, grey), when some texel's
    /// dielectric reflects more than core glTF's.
    pub specular_color: Option<Vec<u8>>,
}

/// What one .glb holds.
pub struct Glb<'a> {
    pub meshes: &'a [CpuMesh],
    pub pbr: Pbr,
    pub textures: Option<Textures>,
    /// The material directory's files ([`crate::material::packed::pack`]).
    pub factored: Vec<File>,
}

/// The binary chunk and the JSON arrays that point into it.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// Appends bytes as a buffer view (4-byte aligned); its index.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let mut v = json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes.len() });
        if let Some(t) = target {
            v["target"] = t.into();
        }
        self.views.push(v);
        self.views.len() - 1
    }

    /// Appends an accessor over a new view; its index.
    fn accessor(&mut self, bytes: &[u8], count: usize, kind: &str, component: u32, target: u32, extra: Value) -> usize {
        let view = self.view(bytes, Some(target));
        let mut a = json!({ "bufferView": view, "componentType": component, "count": count, "type": kind });
        if let (Value::Object(a), Value::Object(e)) = (&mut a, extra) {
            a.extend(e);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }
}

fn f32_bytes(values: impl Iterator<Item = f32>) -> Vec<u8> {
    values.flat_map(f32::to_le_bytes).collect()
}

/// One mesh's primitive attributes and indices.
fn primitive(b: &mut Builder, mesh: &CpuMesh) -> Value {
    let n = mesh.positions.len();
    let (lo, hi) = mesh.bounds().unwrap_or((Vec3::ZERO, Vec3::ZERO));
    let mut attributes = Map::new();
    let pos = b.accessor(&f32_bytes(mesh.positions.iter().flat_map(|p| p.to_array())), n, "VEC3", F32, ARRAY_BUFFER, json!({ "min": lo.to_array(), "max": hi.to_array() }));
    attributes.insert("POSITION".into(), pos.into());
    // glTF requires unit normals; a degenerate one is given +Z rather than refused.
    let normals = mesh.normals.iter().map(|v| v.try_normalize().unwrap_or(Vec3::Z));
    let normal = b.accessor(&f32_bytes(normals.flat_map(|v| v.to_array())), n, "VEC3", F32, ARRAY_BUFFER, json!({}));
    attributes.insert("NORMAL".into(), normal.into());
    if let Some(uv) = &mesh.uvs {
        let uv = b.accessor(&f32_bytes(uv.iter().flat_map(|v| v.to_array())), n, "VEC2", F32, ARRAY_BUFFER, json!({}));
        attributes.insert("TEXCOORD_0".into(), uv.into());
    }
    let index_bytes: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
    let indices = b.accessor(&index_bytes, mesh.indices.len(), "SCALAR", U32, ELEMENT_ARRAY_BUFFER, json!({}));
    json!({ "attributes": attributes, "indices": indices, "material": 0, "mode": 4 })
}

/// The glTF material: metallic-roughness, textures, and the packed factored material.
fn material(b: &mut Builder, glb: &Glb, images: &mut Vec<Value>, textures: &mut Vec<Value>) -> Value {
    let p = &glb.pbr;
    let mut pbr = json!({
        "baseColorFactor": [p.base_color[0], p.base_color[1], p.base_color[2], 1.0],
        "metallicFactor": p.metallic,
        "roughnessFactor": p.roughness,
    });
    let mut texture = |png: &[u8]| {
        let view = b.view(png, None);
        images.push(json!({ "bufferView": view, "mimeType": "image/png" }));
        textures.push(json!({ "sampler": 0, "source": images.len() - 1 }));
        json!({ "index": textures.len() - 1 })
    };
    let mut specular_texture = None;
    if let Some(t) = &glb.textures {
        pbr["baseColorTexture"] = texture(&t.base_color);
        pbr["metallicRoughnessTexture"] = texture(&t.metallic_roughness);
        specular_texture = t.specular_color.as_deref().map(&mut texture);
    }
    let files: Vec<Value> = glb
        .factored
        .iter()
        .map(|(name, bytes)| {
            let mime = if name.ends_with(".json") { "application/json" } else { "image/x-exr" };
            json!({ "name": name, "bufferView": b.view(bytes, None), "mimeType": mime })
        })
        .collect();
    let mut extensions = json!({ EXTENSION: { "version": EXTENSION_VERSION, "files": files } });
    if let Some(k) = p.specular_color() {
        extensions[SPECULAR] = json!({ "specularColorFactor": [k, k, k] });
        if let Some(t) = specular_texture {
            extensions[SPECULAR]["specularColorTexture"] = t;
        }
    }
    if let Some(c) = p.coat {
        extensions[CLEARCOAT] = json!({ "clearcoatFactor": c.factor, "clearcoatRoughnessFactor": c.roughness });
    }
    if let Some(sh) = p.sheen {
        extensions[SHEEN] = json!({ "sheenColorFactor": sh.color, "sheenRoughnessFactor": sh.roughness });
    }
    json!({ "name": "brdfpaint", "pbrMetallicRoughness": pbr, "extensions": extensions })
}

/// The extension that carries a dielectric $F_0$ above core glTF's 0.04.
const SPECULAR: &str = "KHR_materials_specular";
/// The extension that carries a clear coat.
const CLEARCOAT: &str = "KHR_materials_clearcoat";
/// The extension that carries a sheen.
const SHEEN: &str = "KHR_materials_sheen";

/// Our extension, and the Khronos ones the material needs.
fn extensions_used(p: &Pbr) -> Value {
    let mut used = vec![EXTENSION];
    if p.specular_color().is_some() {
        used.push(SPECULAR);
    }
    if p.coat.is_some() {
        used.push(CLEARCOAT);
    }
    if p.sheen.is_some() {
        used.push(SHEEN);
    }
    json!(used)
}

/// The document and its binary chunk.
fn document(glb: &Glb) -> (Value, Vec<u8>) {
    let mut b = Builder::default();
    let (mut images, mut textures) = (Vec::new(), Vec::new());
    let mut meshes = Vec::new();
    for mesh in glb.meshes {
        meshes.push(json!({ "primitives": [primitive(&mut b, mesh)] }));
    }
    let material = material(&mut b, glb, &mut images, &mut textures);
    let nodes: Vec<Value> = (0..meshes.len()).map(|k| json!({ "mesh": k })).collect();
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": crate::material::TOOL },
        "extensionsUsed": extensions_used(&glb.pbr),
        "scene": 0,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": [material],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{ "byteLength": b.bin.len() }],
    });
    if !images.is_empty() {
        doc["images"] = images.into();
        doc["textures"] = textures.into();
        // Linear filtering with mipmaps; clamped at the edges, as the factored material clamps uv.
        doc["samplers"] = json!([{ "magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071 }]);
    }
    (doc, b.bin)
}

/// The bytes of the .glb: header, JSON chunk (space-padded), BIN chunk (zero-padded).
pub fn to_bytes(glb: &Glb) -> Result<Vec<u8>> {
    if glb.meshes.is_empty() || glb.meshes.iter().any(|m| m.indices.is_empty()) {
        return Err(Error::input("the model has a mesh without triangles"));
    }
    let (doc, bin) = document(glb);
    let mut json = serde_json::to_vec(&doc).map_err(|e| Error::input(format!("cannot write the glTF JSON: {e}")))?;
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let total = u32::try_from(total).map_err(|_| Error::input("the model and material pass the 4 GiB a .glb holds"))?;
    let mut out = Vec::with_capacity(total as usize);
    for word in [0x4654_6C67u32, 2, total, json.len() as u32, 0x4E4F_534A] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(&json);
    for word in [bin.len() as u32, 0x004E_4942] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(&bin);
    Ok(out)
}

/// Writes the .glb atomically ([`crate::commit::write_atomic`]).
pub fn write(path: &Path, glb: &Glb) -> Result<()> {
    crate::commit::write_atomic(path, &to_bytes(glb)?)
}
