//! Reading scenes and models from glTF 2.0 (.gltf with its buffers, or .glb).
//!
//! Only geometry, the first camera and the first light are read. Images are not decoded (a
//! scene's textures play no part in sampling or rendering here), but a texture file the scene
//! names must exist, so that a broken scene is caught when it is loaded.
//!
//! Nothing in a file can make the loader panic: what the gltf crate would panic on is checked
//! before it sees the file (and any panic left inside it is caught at this boundary), every
//! accessor is checked against its buffer before it is read, the node hierarchy is checked to
//! be a forest, and every failure is an [`Error`] naming the file.
//!
//! Files a scene names are read under the file-access policy ([`crate::fsio`], README "File
//! access"): regular files inside the scene's directory only, with a size cap.

use std::path::Path;

use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::accessor::{check_accessor, read_floats};
use super::sources::{check_before_validation, check_extension, check_images, read_buffers};
use super::{Camera, CpuMesh, Light, Projection, Scene};
use crate::error::{Error, Result};
use crate::note::Note;

impl Scene {
    /// Loads a glTF 2.0 scene (.gltf or .glb): every triangle primitive of the default scene
    /// (node transforms applied), the first camera node and the first KHR_lights_punctual light
    /// node in depth-first order of the scene's nodes.
    ///
    /// - Missing normals are generated ([`CpuMesh::generate_normals`]). Missing tangents are
    ///   made with MikkTSpace ([`CpuMesh::ensure_tangents`]) when the primitive has
    ///   TEXCOORD_0; without texture coordinates `uvs` and `tangents` are `None`.
    /// - Skinned meshes are posed by their skin in the rest pose of the joint nodes:
    ///   $p' = \sum_k w_k\, J_{j_k} B_{j_k}\, p$ with $J$ the joint's world matrix and $B$ its
    ///   inverse bind matrix; the mesh node's own transform is ignored, as glTF prescribes.
    ///   Animations and morph targets are ignored.
    /// - Point and line primitives are skipped; strips and fans become triangle lists.
    /// - The camera's world matrix has any node scale removed (a camera has no scale).
    /// - A spot light is read as a point light at its position (the cone is ignored).
    ///
    /// Errors name the file and the reason: unreadable, corrupt or truncated files, an
    /// unsupported required extension or accessor type, a missing buffer or texture file, and
    /// a scene without a mesh, a camera or a light.
    ///
    /// A scene with more than one camera or light says which one it uses in a note
    /// told ([`crate::note::tell`]; [`Scene::load_with_notes`] returns them instead).
    pub fn load(path: impl AsRef<Path>) -> Result<Scene> {
        let (scene, notes) = Scene::load_with_notes(path)?;
        notes.into_iter().for_each(crate::note::tell);
        Ok(scene)
    }

    /// [`Scene::load`], with its notes returned rather than sent.
    pub fn load_with_notes(path: impl AsRef<Path>) -> Result<(Scene, Vec<Note>)> {
        let path = path.as_ref();
        let loaded = Loaded::read(path)?;
        let notes = loaded.notes(path);
        let camera = loaded.camera.ok_or_else(|| {
            Error::format(path, "the scene has no camera (add a camera node, or frame the model in one of the preset views instead)")
        })?;
        let light = loaded.light.ok_or_else(|| {
            Error::format(
                path,
                "the scene has no light (add a KHR_lights_punctual directional or point light node, or frame the model in one of the preset views instead)",
            )
        })?;
        Ok((Scene { meshes: loaded.meshes, camera, light }, notes))
    }

    /// Loads only the meshes of a model file (glTF 2.0 .gltf or .glb), in world space, as
    /// [`Scene::load`] reads them. Cameras and lights in the file are ignored.
    pub fn load_model(path: impl AsRef<Path>) -> Result<Vec<CpuMesh>> {
        Ok(Loaded::read(path.as_ref())?.meshes)
    }
}

/// The meshes of a self-contained glTF file held in memory (a .glb or a .gltf with data:
/// URIs), read as [`Scene::load_model`] reads files; `name` names it in errors.
pub(crate) fn load_model_bytes(name: &str, bytes: &[u8]) -> Result<Vec<CpuMesh>> {
    Ok(Loaded::parse(Path::new(name), bytes, None)?.meshes)
}

/// What a glTF file holds, before checking that the scene is complete.
struct Loaded {
    meshes: Vec<CpuMesh>,
    camera: Option<Camera>,
    light: Option<Light>,
    /// The camera and light nodes, in the order walked: the first of each is used.
    cameras: Vec<String>,
    lights: Vec<String>,
}

/// Extensions a file may require and still be read correctly: they change only materials,
/// textures or lights, never the geometry, or change it as read here (KHR_mesh_quantization's
/// integer attributes: [`super::accessor::read_floats`]).
fn extension_is_read(name: &str) -> bool {
    name == "KHR_lights_punctual"
        || name == "KHR_mesh_quantization"
        || name.starts_with("KHR_materials_")
        || name.starts_with("KHR_texture_")
        || name == "EXT_texture_webp"
        || name == "EXT_texture_avif"
}

impl Loaded {
    /// A note for each of camera and light when the scene has several: which one is used.
    fn notes(&self, path: &Path) -> Vec<Note> {
        [("cameras", &self.cameras), ("lights", &self.lights)]
            .into_iter()
            .filter(|(_, nodes)| nodes.len() > 1)
            .map(|(what, nodes)| Note::FirstOfMany { scene: path.display().to_string(), what, count: nodes.len(), used: nodes[0].to_string() })
            .collect()
    }

    fn read(path: &Path) -> Result<Loaded> {
        check_extension(path)?;
        let bytes = crate::fsio::read_regular(path, crate::fsio::MAX_SCENE_BYTES)?;
        let base = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Loaded::parse(path, &bytes, Some(base))
    }

    /// Parses the bytes of a glTF file. `path` names it in errors; external buffers and images
    /// are looked up in `base` under the file-access policy ([`crate::fsio`]), and are an
    /// error when `base` is `None`.
    ///
    /// The gltf crate panics on a few malformed files (an out-of-range POSITION accessor in
    /// its validation, an image without a source). Those are checked for first; any other
    /// panic inside it is caught here and reported as a malformed file, never a crash.
    fn parse(path: &Path, bytes: &[u8], base: Option<&Path>) -> Result<Loaded> {
        match crate::error::catch_panic(|| Loaded::parse_unguarded(path, bytes, base)) {
            Ok(loaded) => loaded,
            Err(panic) => Err(Error::format(path, format!("malformed glTF (the glTF reader failed: {panic})"))),
        }
    }

    fn parse_unguarded(path: &Path, bytes: &[u8], base: Option<&Path>) -> Result<Loaded> {
        if bytes.is_empty() {
            return Err(Error::format(path, "empty file"));
        }
        let corrupt = |e: gltf::Error| Error::format(path, format!("corrupt, truncated or not glTF 2.0: {e}"));
        let (mut json, blob) = super::json::parse(bytes).map_err(corrupt)?;
        // Required extensions are checked here: gltf's validation knows only those compiled
        // into it, and would only say "Unsupported extension".
        if let Some(ext) = json.extensions_required.iter().find(|e| !extension_is_read(e)) {
            return Err(Error::format(
                path,
                format!("requires the unsupported glTF extension {ext} (re-export the file without it, e.g. with Blender)"),
            ));
        }
        json.extensions_required.clear();
        check_before_validation(&json).map_err(|reason| Error::format(path, reason))?;
        let document = gltf::Document::from_json(json)
            .map_err(|e| Error::format(path, format!("not a valid glTF 2.0 file: {e}")))?;
        check_images(path, base, &document)?;
        let buffers = read_buffers(path, base, &document, blob)?;

        let graph = NodeGraph::new(path, &document)?;
        let nodes = graph.depth_first(&document);
        super::budget::check_instanced(path, &nodes, &buffers)?;
        let mut walker = Walker {
            path,
            buffers: &buffers,
            worlds: &graph.worlds,
            meshes: Vec::new(),
            camera: None,
            light: None,
            cameras: Vec::new(),
            lights: Vec::new(),
            skipped: Vec::new(),
        };
        for node in &nodes {
            walker.visit(node)?;
        }
        if walker.meshes.is_empty() {
            let skipped = if walker.skipped.is_empty() {
                String::new()
            } else {
                format!(" (skipped {}: only triangles are supported)", walker.skipped.join(", "))
            };
            return Err(Error::format(path, format!("the scene has no triangle mesh{skipped}")));
        }
        Ok(Loaded { meshes: walker.meshes, camera: walker.camera, light: walker.light, cameras: walker.cameras, lights: walker.lights })
    }
}

/// The node hierarchy, checked to be a forest, with every node's world matrix.
struct NodeGraph {
    /// World-from-node matrix of every node of the document (also of nodes outside the scene,
    /// which skins may name as joints).
    worlds: Vec<Mat4>,
    /// The roots to walk: the default scene's nodes (the first scene's when there is no
    /// default), or every parentless node when the file has no scene at all.
    roots: Vec<usize>,
}

impl NodeGraph {
    fn new(path: &Path, document: &gltf::Document) -> Result<NodeGraph> {
        let n = document.nodes().len();
        let mut parent: Vec<Option<usize>> = vec![None; n];
        for node in document.nodes() {
            for child in node.children() {
                if let Some(other) = parent[child.index()].replace(node.index()) {
                    return Err(Error::format(
                        path,
                        format!("node {} is a child of both node {other} and node {}: the node hierarchy is not a tree", child.index(), node.index()),
                    ));
                }
            }
        }
        let locals: Vec<Mat4> =
            document.nodes().map(|node| Mat4::from_cols_array_2d(&node.transform().matrix())).collect();
        if let Some(bad) = locals.iter().position(|m| !m.is_finite()) {
            return Err(Error::format(path, format!("node {bad} has a non-finite transform")));
        }
        // World matrices, each node after its parent. Following parents from any node reaches
        // a root within n steps, unless the parents form a cycle.
        let mut worlds: Vec<Option<Mat4>> = vec![None; n];
        for start in 0..n {
            let mut chain = Vec::new();
            let mut at = Some(start);
            while let Some(i) = at {
                if worlds[i].is_some() {
                    break;
                }
                if chain.len() > n {
                    return Err(Error::format(path, format!("the node hierarchy has a cycle through node {i}")));
                }
                chain.push(i);
                at = parent[i];
            }
            let mut world = at.and_then(|i| worlds[i]).unwrap_or(Mat4::IDENTITY);
            for &i in chain.iter().rev() {
                world *= locals[i];
                if !world.is_finite() {
                    return Err(Error::format(path, format!("node {i} has a non-finite world transform")));
                }
                worlds[i] = Some(world);
            }
        }
        let worlds: Vec<Mat4> = worlds.into_iter().map(|w| w.unwrap_or(Mat4::IDENTITY)).collect();

        let scene = document.default_scene().or_else(|| document.scenes().next());
        let roots: Vec<usize> = match &scene {
            Some(scene) => scene.nodes().map(|n| n.index()).collect(),
            None => (0..n).filter(|&i| parent[i].is_none()).collect(),
        };
        if let Some(&r) = roots.iter().find(|&&r| parent[r].is_some()) {
            return Err(Error::format(path, format!("scene root node {r} is also a child of node {}", parent[r].unwrap_or(r))));
        }
        Ok(NodeGraph { worlds, roots })
    }

    /// The scene's nodes in depth-first order, each once.
    fn depth_first<'a>(&self, document: &'a gltf::Document) -> Vec<gltf::Node<'a>> {
        let nodes: Vec<gltf::Node<'a>> = document.nodes().collect();
        let mut seen = vec![false; nodes.len()];
        let mut order = Vec::new();
        let mut stack: Vec<usize> = self.roots.iter().rev().copied().collect();
        while let Some(i) = stack.pop() {
            // A root listed twice is walked once.
            if std::mem::replace(&mut seen[i], true) {
                continue;
            }
            order.push(nodes[i].clone());
            let children: Vec<usize> = nodes[i].children().map(|c| c.index()).collect();
            stack.extend(children.into_iter().rev());
        }
        order
    }
}

/// Reads the nodes' meshes, camera and light.
struct Walker<'a> {
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    worlds: &'a [Mat4],
    meshes: Vec<CpuMesh>,
    camera: Option<Camera>,
    light: Option<Light>,
    /// Each camera and light node met, named for a note ([`Loaded::notes`]).
    cameras: Vec<String>,
    lights: Vec<String>,
    skipped: Vec<String>,
}

impl Walker<'_> {
    fn visit(&mut self, node: &gltf::Node) -> Result<()> {
        let world = self.worlds[node.index()];
        if let Some(mesh) = node.mesh() {
            let skin = match node.skin() {
                Some(skin) => Some(self.skin_matrices(&skin)?),
                None => None,
            };
            for primitive in mesh.primitives() {
                let what = format!("mesh {} primitive {}", mesh.index(), primitive.index());
                let Some(mut cpu) = self.primitive(&primitive, &what)? else { continue };
                match &skin {
                    Some(joints) => {
                        let per_vertex = self.vertex_skin(&primitive, joints, world, cpu.positions.len(), &what)?;
                        cpu.transform_per_vertex(&per_vertex);
                    }
                    None => cpu.transform(world),
                }
                if cpu.normals.is_empty() {
                    cpu.generate_normals();
                }
                if cpu.tangents.is_none() && cpu.uvs.is_some() {
                    cpu.ensure_tangents()?;
                }
                cpu.check().map_err(|e| Error::format(self.path, format!("{what}: {e}")))?;
                self.meshes.push(cpu);
            }
        }
        if let Some(camera) = node.camera() {
            if self.camera.is_none() {
                self.camera = Some(self.camera(&camera, world)?);
            }
            self.cameras.push(node_name("camera", camera.index(), node));
        }
        if let Some(light) = node.light() {
            if self.light.is_none() {
                self.light = Some(self.light(&light, world)?);
            }
            self.lights.push(node_name("light", light.index(), node));
        }
        Ok(())
    }

    fn camera(&self, camera: &gltf::Camera, world: Mat4) -> Result<Camera> {
        let bad = |reason: String| Error::format(self.path, format!("camera {}: {reason}", camera.index()));
        let projection = match camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                let (yfov, znear) = (p.yfov(), p.znear());
                if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(bad(format!("yfov {yfov} is not in (0, π)")));
                }
                if !(znear > 0.0 && znear.is_finite()) {
                    return Err(bad(format!("znear {znear} is not positive")));
                }
                if let Some(a) = p.aspect_ratio() {
                    if !(a > 0.0 && a.is_finite()) {
                        return Err(bad(format!("aspectRatio {a} is not positive")));
                    }
                }
                if let Some(f) = p.zfar() {
                    // NaN fails too.
                    if f.is_nan() || f <= znear {
                        return Err(bad(format!("zfar {f} is not beyond znear {znear}")));
                    }
                }
                Projection::Perspective { yfov, aspect: p.aspect_ratio(), znear, zfar: p.zfar() }
            }
            gltf::camera::Projection::Orthographic(o) => {
                let (xmag, ymag, znear, zfar) = (o.xmag(), o.ymag(), o.znear(), o.zfar());
                if !(xmag != 0.0 && ymag != 0.0 && xmag.is_finite() && ymag.is_finite()) {
                    return Err(bad(format!("xmag {xmag} / ymag {ymag} must be finite and non-zero")));
                }
                if !(znear >= 0.0 && zfar > znear && zfar.is_finite()) {
                    return Err(bad(format!("znear {znear} / zfar {zfar} must satisfy 0 <= znear < zfar")));
                }
                Projection::Orthographic { xmag, ymag, znear, zfar }
            }
        };
        // Remove scale (and shear) from the node's world matrix: keep the rotation and the
        // position, so view space has the units of world space.
        let (_, rotation, translation) = world.to_scale_rotation_translation();
        let world_from_camera = Mat4::from_rotation_translation(rotation.normalize(), translation);
        if !world_from_camera.is_finite() {
            return Err(bad("degenerate camera node transform".into()));
        }
        Ok(Camera { world_from_camera, projection })
    }

    fn light(&self, light: &gltf::khr_lights_punctual::Light, world: Mat4) -> Result<Light> {
        use gltf::khr_lights_punctual::Kind;
        let color = Vec3::from_array(light.color());
        let intensity = light.intensity();
        if !(color.is_finite() && color.min_element() >= 0.0 && intensity.is_finite() && intensity >= 0.0) {
            return Err(Error::format(
                self.path,
                format!("light {}: colour {color} and intensity {intensity} must be finite and non-negative", light.index()),
            ));
        }
        Ok(match light.kind() {
            Kind::Directional => {
                let direction = world.transform_vector3(-Vec3::Z).normalize_or_zero();
                if direction == Vec3::ZERO {
                    return Err(Error::format(self.path, format!("light {}: degenerate node transform", light.index())));
                }
                Light::Directional { direction, color, intensity }
            }
            // A spot light is read as a point light: its cone is ignored.
            Kind::Point | Kind::Spot { .. } => {
                Light::Point { position: world.transform_point3(Vec3::ZERO), color, intensity }
            }
        })
    }

    /// The joint matrices $J_j B_j$ of a skin, in joint order.
    fn skin_matrices(&self, skin: &gltf::Skin) -> Result<Vec<Mat4>> {
        let bad = |reason: String| Error::format(self.path, format!("skin {}: {reason}", skin.index()));
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        let inverse_binds: Vec<Mat4> = match skin.inverse_bind_matrices() {
            None => vec![Mat4::IDENTITY; joints.len()],
            Some(acc) => {
                check_accessor(&acc, self.buffers, "inverseBindMatrices", Dimensions::Mat4, &[DataType::F32])
                    .map_err(&bad)?;
                let buffers = self.buffers;
                let reader = skin.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let matrices: Vec<Mat4> = reader
                    .read_inverse_bind_matrices()
                    .ok_or_else(|| bad("inverseBindMatrices data lies outside its buffer".into()))?
                    .map(|m| Mat4::from_cols_array_2d(&m))
                    .collect();
                if matrices.len() < joints.len() {
                    return Err(bad(format!("{} inverse bind matrices for {} joints", matrices.len(), joints.len())));
                }
                matrices
            }
        };
        let matrices: Vec<Mat4> = joints.iter().zip(&inverse_binds).map(|(&j, &b)| self.worlds[j] * b).collect();
        if matrices.iter().any(|m| !m.is_finite()) {
            return Err(bad("non-finite joint matrix".into()));
        }
        Ok(matrices)
    }

    /// Each vertex's skinning matrix $\sum_k w_k J_{j_k} B_{j_k}$ from all its JOINTS_n /
    /// WEIGHTS_n sets, weights normalized to sum 1. A vertex without weight, or a primitive
    /// without JOINTS_0, keeps the node's world transform.
    fn vertex_skin(
        &self,
        primitive: &gltf::Primitive,
        joints: &[Mat4],
        node_world: Mat4,
        n: usize,
        what: &str,
    ) -> Result<Vec<Mat4>> {
        let bad = |reason: String| Error::format(self.path, format!("{what}: {reason}"));
        let buffers = self.buffers;
        let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
        let mut sums = vec![Mat4::ZERO; n];
        let mut weight_sums = vec![0.0f32; n];
        for set in 0.. {
            let (Some(ja), Some(wa)) =
                (primitive.get(&gltf::Semantic::Joints(set)), primitive.get(&gltf::Semantic::Weights(set)))
            else {
                break;
            };
            let (jname, wname) = (format!("JOINTS_{set}"), format!("WEIGHTS_{set}"));
            check_accessor(&ja, buffers, &jname, Dimensions::Vec4, &[DataType::U8, DataType::U16]).map_err(&bad)?;
            check_accessor(&wa, buffers, &wname, Dimensions::Vec4, &[DataType::F32, DataType::U8, DataType::U16])
                .map_err(&bad)?;
            let js: Vec<[u16; 4]> = reader
                .read_joints(set)
                .ok_or_else(|| bad(format!("{jname} data lies outside its buffer")))?
                .into_u16()
                .collect();
            let ws: Vec<[f32; 4]> = reader
                .read_weights(set)
                .ok_or_else(|| bad(format!("{wname} data lies outside its buffer")))?
                .into_f32()
                .collect();
            check_count(js.len(), n, &jname).map_err(&bad)?;
            check_count(ws.len(), n, &wname).map_err(&bad)?;
            for v in 0..n {
                for k in 0..4 {
                    let w = ws[v][k];
                    if w == 0.0 {
                        continue;
                    }
                    if !(w > 0.0 && w.is_finite()) {
                        return Err(bad(format!("{wname} of vertex {v} is {w}")));
                    }
                    let j = js[v][k] as usize;
                    let m = joints
                        .get(j)
                        .ok_or_else(|| bad(format!("{jname} of vertex {v} names joint {j} of {}", joints.len())))?;
                    sums[v] += *m * w;
                    weight_sums[v] += w;
                }
            }
        }
        Ok(sums
            .into_iter()
            .zip(weight_sums)
            .map(|(m, w)| if w > 0.0 { m * (1.0 / w) } else { node_world })
            .collect())
    }

    /// Reads one primitive in its local space, or `None` for a skipped point/line primitive.
    fn primitive(&mut self, primitive: &gltf::Primitive, what: &str) -> Result<Option<CpuMesh>> {
        let mode = primitive.mode();
        if matches!(mode, Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip) {
            let skipped = format!("{what} ({mode:?})");
            // A mesh used by several nodes is read once per node; name it once.
            if !self.skipped.contains(&skipped) {
                self.skipped.push(skipped);
            }
            return Ok(None);
        }
        let bad = |reason: String| Error::format(self.path, format!("{what}: {reason}"));
        let buffers = self.buffers;
        let (positions, n) = read_positions(primitive, buffers).map_err(&bad)?;
        let normals = read_normals(primitive, buffers, n).map_err(&bad)?;
        let tangents = read_tangents(primitive, buffers, n).map_err(&bad)?;
        // Tangents without normals are meaningless (their frame is the normal's): drop them
        // and let them be remade from the generated normals.
        let tangents = if normals.is_empty() { None } else { tangents };
        let uvs = read_uvs(primitive, buffers, n).map_err(&bad)?;
        let vertex_order = read_vertex_order(primitive, buffers, n).map_err(&bad)?;
        let indices = triangles(mode, &vertex_order);
        if let Some(&bad_index) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(bad(format!("index {bad_index} out of range for {n} vertices")));
        }
        if indices.is_empty() {
            return Err(bad("no triangles (fewer than 3 indices)".into()));
        }
        Ok(Some(CpuMesh { positions, normals, tangents, uvs, indices }))
    }
}

/// A primitive's POSITION attribute, and its vertex count.
fn read_positions(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data]) -> std::result::Result<(Vec<Vec3>, usize), String> {
    let accessor = primitive.get(&gltf::Semantic::Positions).ok_or("no POSITION attribute")?;
    check_accessor(&accessor, buffers, "POSITION", Dimensions::Vec3, QUANTIZED)?;
    let n = accessor.count();
    if n > u32::MAX as usize {
        return Err(format!("{n} vertices is more than 32-bit indices can address"));
    }
    let positions = all_elements(read_floats::<3>(&accessor, buffers), n, "POSITION")?;
    Ok((positions.into_iter().map(Vec3::from_array).collect(), n))
}

/// A primitive's unit normals for its `n` vertices; empty without a NORMAL attribute.
fn read_normals(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data], n: usize) -> std::result::Result<Vec<Vec3>, String> {
    let Some(accessor) = primitive.get(&gltf::Semantic::Normals) else { return Ok(Vec::new()) };
    check_accessor(&accessor, buffers, "NORMAL", Dimensions::Vec3, SIGNED_QUANTIZED)?;
    let normals = all_elements(read_floats::<3>(&accessor, buffers), n, "NORMAL")?;
    Ok(normals.into_iter().map(|v| unit_or(Vec3::from_array(v), Vec3::Z)).collect())
}

/// A primitive's tangents (unit, w ±1) for its `n` vertices, if it has a TANGENT attribute.
fn read_tangents(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data], n: usize) -> std::result::Result<Option<Vec<Vec4>>, String> {
    let Some(accessor) = primitive.get(&gltf::Semantic::Tangents) else { return Ok(None) };
    check_accessor(&accessor, buffers, "TANGENT", Dimensions::Vec4, SIGNED_QUANTIZED)?;
    let tangents = all_elements(read_floats::<4>(&accessor, buffers), n, "TANGENT")?;
    let tangents = tangents.into_iter().map(|t| {
        // w is ±1 by the spec; snap anything else to its sign.
        let w = if t[3] < 0.0 { -1.0 } else { 1.0 };
        unit_or(Vec3::new(t[0], t[1], t[2]), Vec3::X).extend(w)
    });
    Ok(Some(tangents.collect()))
}

/// A primitive's texture coordinates (TEXCOORD_0, finite) for its `n` vertices, if it has them.
fn read_uvs(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data], n: usize) -> std::result::Result<Option<Vec<Vec2>>, String> {
    let Some(accessor) = primitive.get(&gltf::Semantic::TexCoords(0)) else { return Ok(None) };
    check_accessor(&accessor, buffers, "TEXCOORD_0", Dimensions::Vec2, QUANTIZED)?;
    let uvs: Vec<Vec2> =
        all_elements(read_floats::<2>(&accessor, buffers), n, "TEXCOORD_0")?.into_iter().map(Vec2::from_array).collect();
    if uvs.iter().any(|uv| !uv.is_finite()) {
        return Err("non-finite texture coordinate".into());
    }
    Ok(Some(uvs))
}

/// A primitive's vertex indices in the order its mode reads them: its index accessor's, or
/// the `n` vertices in turn when it has none.
fn read_vertex_order(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data], n: usize) -> std::result::Result<Vec<u32>, String> {
    let Some(accessor) = primitive.indices() else { return Ok((0..n as u32).collect()) };
    check_accessor(&accessor, buffers, "indices", Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32])?;
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let indices: Vec<u32> = reader.read_indices().ok_or("index data lies outside its buffer")?.into_u32().collect();
    check_count(indices.len(), accessor.count(), "indices")?;
    Ok(indices)
}

/// The triangle list of a triangle, strip or fan primitive whose vertices come in
/// `vertex_order`.
fn triangles(mode: Mode, vertex_order: &[u32]) -> Vec<u32> {
    match mode {
        Mode::Triangles => {
            // A trailing partial triangle is malformed; drop it rather than fail.
            let whole = vertex_order.len() / 3 * 3;
            vertex_order[..whole].to_vec()
        }
        Mode::TriangleStrip => (2..vertex_order.len())
            .flat_map(|i| {
                let (a, b, c) = (vertex_order[i - 2], vertex_order[i - 1], vertex_order[i]);
                // Every other strip triangle is wound the other way round.
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => {
            (2..vertex_order.len()).flat_map(|i| [vertex_order[0], vertex_order[i - 1], vertex_order[i]]).collect()
        }
        // Point and line primitives are skipped before they are read.
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => Vec::new(),
    }
}

/// An attribute's elements as read ([`read_floats`]: `None` when its data lies outside its
/// buffer), checked to be all `n` of them.
fn all_elements<T>(read: Option<Vec<T>>, n: usize, name: &str) -> std::result::Result<Vec<T>, String> {
    let elements = read.ok_or_else(|| format!("{name} data lies outside its buffer"))?;
    check_count(elements.len(), n, name)?;
    Ok(elements)
}

/// "camera 0 at node 3 ('Main')": an object and the node that places it, for a note.
fn node_name(what: &str, index: usize, node: &gltf::Node) -> String {
    let name = node.name().map(|n| format!(" ('{n}')")).unwrap_or_default();
    format!("{what} {index} at node {}{name}", node.index())
}

/// Component types of positions and texture coordinates: float, or 8- and 16-bit integers
/// (KHR_mesh_quantization; glTF 2.0 itself allows normalized unsigned texture coordinates).
const QUANTIZED: &[DataType] = &[DataType::F32, DataType::I8, DataType::U8, DataType::I16, DataType::U16];

/// Component types of normals and tangents: float, or normalized signed 8- and 16-bit
/// integers (KHR_mesh_quantization).
const SIGNED_QUANTIZED: &[DataType] = &[DataType::F32, DataType::I8, DataType::I16];

/// `v` normalized, or `fallback` when it has no direction. Vectors already unit to float
/// rounding are kept bit for bit, so a written scene loads back unchanged.
fn unit_or(v: Vec3, fallback: Vec3) -> Vec3 {
    if (v.length_squared() - 1.0).abs() <= 1e-6 {
        v
    } else {
        v.normalize_or(fallback)
    }
}

fn check_count(got: usize, expected: usize, name: &str) -> std::result::Result<(), String> {
    if got != expected {
        return Err(format!("{name} has {got} elements readable of {expected} (truncated buffer?)"));
    }
    Ok(())
}
