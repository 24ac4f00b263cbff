//! Standard scenes (thesis 4.1): built-in models, standard views and lights, and automatic
//! framing. A standard scene never changes, so its prepared system can be cached: the artist
//! paints, and only the cheap solve runs.
//!
//! ```
//! use brdfpaint::scene::Scene;
//!
//! let scene = Scene::from_preset("sphere", "front-left").unwrap();
//! // The camera looks at the sphere at the origin.
//! let forward = scene.camera.world_from_camera.transform_vector3(-glam::Vec3::Z);
//! let to_centre = -scene.camera.world_from_camera.w_axis.truncate().normalize();
//! assert!(forward.dot(to_centre) > 0.9999);
//! // Any glTF model works the same way, and unknown names list the valid ones.
//! let err = Scene::from_preset("sphere", "sunset").unwrap_err().to_string();
//! assert!(err.contains("front-left") && err.contains("rim"));
//! ```

use std::f32::consts::{PI, TAU};
use std::path::Path;

use glam::{Mat4, Vec2, Vec3};

use super::{BoundingSphere, Camera, CpuMesh, Light, Projection, Scene};
use crate::error::{Error, Result};

/// A standard view and light. The view is a direction from the object's centre towards the
/// camera; the light is a direction in view space, so it keeps its place in the picture
/// whatever the view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Preset {
    /// The name used on the command line (`--preset NAME`).
    pub name: &'static str,
    /// One line for `--help` and error messages.
    pub description: &'static str,
    /// Camera direction seen from the object's centre: azimuth about +Y, from +Z towards +X,
    /// in degrees.
    pub view_azimuth_deg: f32,
    /// Camera elevation above the horizontal plane, in degrees (positive: looking down).
    pub view_elevation_deg: f32,
    /// Direction towards the light in view space (x right, y up, z towards the camera); not
    /// necessarily unit length.
    pub light_in_view: [f32; 3],
}

/// Elevation of the standard views: slightly above, so the top of the object shows.
const ELEVATION: f32 = 10.0;
/// The classic key light: from the upper left, in front.
const KEY: [f32; 3] = [-1.0, 1.0, 1.0];

static PRESETS: [Preset; 7] = [
    Preset {
        name: "front-left",
        description: "front view, light from the upper left front (the default)",
        view_azimuth_deg: 0.0,
        view_elevation_deg: ELEVATION,
        light_in_view: KEY,
    },
    Preset {
        name: "front-right",
        description: "front view, light from the upper right front",
        view_azimuth_deg: 0.0,
        view_elevation_deg: ELEVATION,
        light_in_view: [1.0, 1.0, 1.0],
    },
    Preset {
        name: "front",
        description: "front view, light at the camera (headlight)",
        view_azimuth_deg: 0.0,
        view_elevation_deg: ELEVATION,
        light_in_view: [0.0, 0.0, 1.0],
    },
    Preset {
        name: "top",
        description: "view from above (60° elevation), light from the upper left front",
        view_azimuth_deg: 0.0,
        view_elevation_deg: 60.0,
        light_in_view: KEY,
    },
    Preset {
        name: "side",
        description: "view from the right side (+X), light from the upper left front",
        view_azimuth_deg: 90.0,
        view_elevation_deg: ELEVATION,
        light_in_view: KEY,
    },
    Preset {
        name: "back",
        description: "view from behind (-Z), light from the upper left front",
        view_azimuth_deg: 180.0,
        view_elevation_deg: ELEVATION,
        light_in_view: KEY,
    },
    Preset {
        name: "rim",
        description: "front view, light from behind the object, above and to the right",
        view_azimuth_deg: 0.0,
        view_elevation_deg: ELEVATION,
        light_in_view: [0.3, 0.5, -1.0],
    },
];

/// All standard presets; the first is the default.
pub fn presets() -> &'static [Preset] {
    &PRESETS
}

/// The names of [`presets`], in order.
pub fn preset_names() -> Vec<&'static str> {
    PRESETS.iter().map(|p| p.name).collect()
}

/// The preset called `name`, or an [`Error::Input`] listing the valid names.
pub fn preset(name: &str) -> Result<Preset> {
    PRESETS.iter().find(|p| p.name == name).copied().ok_or_else(|| {
        Error::input(format!("unknown preset '{name}'; valid presets: {}", preset_names().join(", ")))
    })
}

impl Default for Preset {
    fn default() -> Self {
        PRESETS[0]
    }
}

impl Preset {
    /// Unit direction from the object's centre towards the camera, world space.
    pub fn view_direction(&self) -> Vec3 {
        let (az, el) = (self.view_azimuth_deg.to_radians(), self.view_elevation_deg.to_radians());
        Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos())
    }

    /// Unit direction towards the light, view space.
    pub fn light_in_view(&self) -> Vec3 {
        Vec3::from_array(self.light_in_view).normalize()
    }
}

impl Scene {
    /// A standard scene: `model` (a built-in name from [`builtin_models`], or the path of a
    /// .glb/.gltf file whose cameras and lights are ignored) framed by [`frame`] for the preset
    /// called `preset_name`, with a square picture (aspect 1).
    pub fn from_preset(model: impl AsRef<Path>, preset_name: &str) -> Result<Scene> {
        let preset = preset(preset_name)?;
        Ok(frame(model_meshes(model)?, &preset, 1.0))
    }
}

/// Vertical field of view of framed cameras.
pub const FRAME_YFOV: f32 = 30.0 * PI / 180.0;
/// The fraction of the frame's height (or width, if narrower) the object's bounding sphere fills.
pub const FRAME_FILL: f32 = 0.85;

/// Frames `meshes` for `preset` with a perspective camera of aspect `aspect` (width / height):
/// the camera (30° vertical field of view) looks at the centre of the meshes' bounding sphere
/// from the preset's view direction, +Y up, at the distance where the sphere fills 85% of the
/// frame's height, or of its width when that is the narrower side. The clip planes bracket the
/// sphere with margin. The light is directional, white, intensity 1, from the preset's
/// direction relative to the camera. Deterministic.
pub fn frame(meshes: Vec<CpuMesh>, preset: &Preset, aspect: f32) -> Scene {
    let bound = BoundingSphere::of(&meshes).unwrap_or(BoundingSphere { center: Vec3::ZERO, radius: 1.0 });
    // A point-sized (or empty) object still needs a finite camera distance.
    let radius = if bound.radius > 0.0 && bound.radius.is_finite() { bound.radius } else { 1.0 };
    let aspect = if aspect > 0.0 && aspect.is_finite() { aspect } else { 1.0 };

    // The sphere's silhouette subtends the half-angle $\alpha = \arcsin(r/d)$; it fills the
    // fraction $f$ of the narrower half-extent when $\tan\alpha = f \tan(\mathrm{yfov}/2) \min(1, \mathrm{aspect})$.
    let half_extent = FRAME_FILL * (FRAME_YFOV / 2.0).tan() * aspect.min(1.0);
    let distance = radius / half_extent.atan().sin();

    // Camera basis: `back` towards the camera (its +Z), `right` and `up` span the picture.
    let back = preset.view_direction();
    let eye = bound.center + distance * back;
    // Keep world +Y up unless the camera looks (nearly) straight down or up.
    let world_up = if back.cross(Vec3::Y).length() > 1e-3 { Vec3::Y } else { -Vec3::Z };
    let right = world_up.cross(back).normalize();
    let up = back.cross(right);
    let world_from_camera = Mat4::from_cols(right.extend(0.0), up.extend(0.0), back.extend(0.0), eye.extend(1.0));

    let znear = (distance - radius) * 0.5;
    let zfar = (distance + radius) * 2.0;
    let camera = Camera {
        world_from_camera,
        projection: Projection::Perspective { yfov: FRAME_YFOV, aspect: Some(aspect), znear, zfar: Some(zfar) },
    };
    let towards_light = world_from_camera.transform_vector3(preset.light_in_view()).normalize();
    let light = Light::Directional { direction: -towards_light, color: Vec3::ONE, intensity: 1.0 };
    Scene { meshes, camera, light }
}

/// A UV sphere of radius 1 at the origin, with the conventions of
/// [`crate::brdf::SphereView`]: pole axis +Y, `segments` around (at least 3), `rings` from
/// pole to pole (at least 2). Vertex $(i, j)$ has polar angle $\theta = \pi i / \mathrm{rings}$
/// from +Y and azimuth $\varphi = 2\pi j / \mathrm{segments} - \pi$ about +Y from +Z towards +X,
/// so $p = n = (\sin\theta\sin\varphi, \cos\theta, \sin\theta\cos\varphi)$ and
/// $uv = (\varphi / 2\pi + \tfrac12, \theta / \pi)$, i.e. $u = \mathrm{atan2}(x, z)/2\pi + \tfrac12$,
/// $v = \arccos(y)/\pi$ (v down, the glTF convention). The seam (at $-Z$) and the poles have
/// duplicate vertices with their own uvs.
///
/// Tangents are analytic: the azimuthal direction $t = \mathrm{normalize}(\hat y \times n) =
/// (\cos\varphi, 0, -\sin\varphi)$ along increasing $u$, $w = +1$ (bitangent $n \times t$,
/// towards decreasing $v$), as in [`crate::brdf::SphereView::frame`]; each pole duplicate gets
/// the tangent of its own meridian. MikkTSpace gives the same away from the seam, and on the
/// seam (where it only sees one side) the chord direction instead.
pub fn sphere_mesh(segments: u32, rings: u32) -> CpuMesh {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let mut mesh = CpuMesh::default();
    let (mut uvs, mut tangents) = (Vec::new(), Vec::new());
    for i in 0..=rings {
        let theta = PI * i as f32 / rings as f32;
        // Exact poles: sin/cos of π are not exactly 0 and -1 in f32.
        let (st, ct) = if i == 0 { (0.0, 1.0) } else if i == rings { (0.0, -1.0) } else { theta.sin_cos() };
        for j in 0..=segments {
            let phi = TAU * j as f32 / segments as f32 - PI;
            // Exact seam at -Z on both of its sides.
            let (sp, cp) = if j == 0 || j == segments { (0.0, -1.0) } else { phi.sin_cos() };
            let p = Vec3::new(st * sp, ct, st * cp);
            mesh.positions.push(p);
            mesh.normals.push(p);
            tangents.push(glam::Vec4::new(cp, 0.0, -sp, 1.0));
            uvs.push(Vec2::new(j as f32 / segments as f32, i as f32 / rings as f32));
        }
    }
    let vertex = |i: u32, j: u32| i * (segments + 1) + j;
    for i in 0..rings {
        for j in 0..segments {
            // Seen from outside: a top-left, b bottom-left, c bottom-right, d top-right (CCW).
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
            // The triangles touching a pole with two corners are degenerate: leave them out.
            if i + 1 != rings {
                mesh.indices.extend([a, b, c]);
            }
            if i != 0 {
                mesh.indices.extend([a, c, d]);
            }
        }
    }
    mesh.uvs = Some(uvs);
    mesh.tangents = Some(tangents);
    mesh
}

/// Names accepted by [`builtin_model`], in a stable order.
pub fn builtin_models() -> &'static [&'static str] {
    &["sphere", "bunny", "suzanne", "teapot", "apple", "fox"]
}

/// The bundled model files, compiled in so that an installed binary needs no asset folder.
fn builtin_bytes(name: &str) -> Option<(&'static str, &'static [u8])> {
    macro_rules! asset {
        ($file:literal) => {
            ($file, include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/models/", $file)).as_slice())
        };
    }
    Some(match name {
        "bunny" => asset!("bunny/bunny.glb"),
        "suzanne" => asset!("suzanne/suzanne.glb"),
        "teapot" => asset!("teapot/teapot.glb"),
        "apple" => asset!("apple/apple.glb"),
        "fox" => asset!("fox/fox.glb"),
        _ => return None,
    })
}

/// A model shipped with the product (origins and licences in `assets/models/*/README.md`):
/// - `sphere`: [`sphere_mesh`]`(64, 32)`, unit radius, with uvs and tangents;
/// - `bunny`: the Stanford bunny (CC0 conversion), normals, no uvs;
/// - `suzanne`: Blender's monkey (CC0), normals, no uvs;
/// - `teapot`: Newell's Utah teapot (public domain), generated normals, no uvs;
/// - `apple`: a photogrammetry apple from Poly Haven (CC0), normals, uvs, MikkTSpace tangents;
/// - `fox`: the Khronos glTF sample Fox in its rest pose (CC0 + CC-BY 4.0), uvs, generated
///   normals, MikkTSpace tangents.
pub fn builtin_model(name: &str) -> Result<Vec<CpuMesh>> {
    if name == "sphere" {
        return Ok(vec![sphere_mesh(64, 32)]);
    }
    let (file, bytes) = builtin_bytes(name).ok_or_else(|| {
        Error::input(format!("unknown built-in model '{name}'; valid models: {}", builtin_models().join(", ")))
    })?;
    super::load::load_model_bytes(&format!("{file} (built-in)"), bytes)
}

/// The meshes of `model`: a built-in model name ([`builtin_models`]) or the path of a
/// .glb/.gltf file ([`Scene::load_model`]). Anything else is an error that lists the built-in
/// names.
pub fn model_meshes(model: impl AsRef<Path>) -> Result<Vec<CpuMesh>> {
    let model = model.as_ref();
    if let Some(name) = model.to_str().filter(|n| builtin_models().contains(n)) {
        return builtin_model(name);
    }
    let is_gltf = model
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("glb") || e.eq_ignore_ascii_case("gltf"));
    if is_gltf || model.exists() {
        return Scene::load_model(model);
    }
    Err(Error::input(format!(
        "unknown model '{}': neither a built-in model ({}) nor a .glb/.gltf file",
        model.display(),
        builtin_models().join(", ")
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::SphereView;
    use glam::DVec3;

    #[test]
    fn sphere_matches_sphere_view_conventions() {
        let s = sphere_mesh(16, 8);
        s.check().unwrap();
        let uvs = s.uvs.as_ref().unwrap();
        let tangents = s.tangents.as_ref().unwrap();
        for (k, p) in s.positions.iter().enumerate() {
            assert!((p.length() - 1.0).abs() < 1e-6, "vertex {k} at {p}");
            assert!((s.normals[k] - *p).length() < 1e-6);
            // uv = SphereView::uv(n), except on the seam's u = 1 side and at the poles, where u
            // is the segment's own.
            let expected = SphereView::uv(p.as_dvec3()).as_vec2();
            assert!((uvs[k].y - expected.y).abs() < 1e-5, "vertex {k}: v {} vs {}", uvs[k].y, expected.y);
            let on_seam_or_pole = p.y.abs() > 1.0 - 1e-6 || uvs[k].x == 0.0 || uvs[k].x == 1.0;
            if !on_seam_or_pole {
                assert!((uvs[k].x - expected.x).abs() < 1e-5, "vertex {k} at {p}: u {} vs {}", uvs[k].x, expected.x);
            } else if p.y.abs() < 1.0 - 1e-6 {
                assert!(p.z < 0.0 && p.x.abs() < 1e-6, "seam vertex {k} at {p} not at -Z");
            }
            // The tangent frame is SphereView's: t = normalize(Y × n), bitangent n × t (w = +1).
            let tangent = tangents[k].truncate().as_dvec3();
            assert_eq!(tangents[k].w, 1.0, "w at {p}");
            assert!((tangent.length() - 1.0).abs() < 1e-6 && tangent.dot(p.as_dvec3()).abs() < 1e-6, "{tangent} at {p}");
            if p.y.abs() < 1.0 - 1e-6 {
                let (t, b, _) = SphereView::frame(p.as_dvec3());
                assert!((tangent - t).length() < 1e-6, "tangent {tangent} at {p}, expected {t}");
                let bitangent = s.normals[k].as_dvec3().cross(tangent) * tangents[k].w as f64;
                assert!((bitangent - b).length() < 1e-6, "bitangent {bitangent} at {p}, expected {b}");
            } else {
                // A pole duplicate follows its meridian: u increases along t.
                let phi = std::f64::consts::TAU * uvs[k].x as f64 - std::f64::consts::PI;
                assert!((tangent - DVec3::new(phi.cos(), 0.0, -phi.sin())).length() < 1e-6, "{tangent} at pole, u {}", uvs[k].x);
            }
        }
        // Every triangle is wound counter-clockwise seen from outside.
        for tri in s.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| s.positions[tri[k] as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.dot(a + b + c) > 0.0, "inward triangle {tri:?}");
        }
        assert_eq!(s.indices.len(), 3 * (2 * 16 * 8 - 2 * 16));
        assert_eq!(s.positions.len(), 17 * 9);
    }

    #[test]
    fn preset_lookup_and_error() {
        assert_eq!(preset("front-left").unwrap(), presets()[0]);
        assert_eq!(Preset::default().name, "front-left");
        for p in presets() {
            assert_eq!(preset(p.name).unwrap().name, p.name);
        }
        for name in ["front-left", "front-right", "top", "rim", "back", "side", "front"] {
            assert!(preset_names().contains(&name), "{name}");
        }
        let err = preset("backlit").unwrap_err().to_string();
        assert!(err.contains("backlit") && err.contains("front-left") && err.contains("rim"), "{err}");
        let err = builtin_model("cow").unwrap_err().to_string();
        assert!(err.contains("cow") && err.contains("teapot"), "{err}");
        let err = model_meshes("cow").unwrap_err().to_string();
        assert!(err.contains("cow") && err.contains("sphere"), "{err}");
        let err = Scene::from_preset("sphere", "noon").unwrap_err().to_string();
        assert!(err.contains("noon") && err.contains("back"), "{err}");
    }

    #[test]
    fn framing_fills_85_percent_and_lights_from_preset() {
        for aspect in [0.5f32, 1.0, 16.0 / 9.0] {
            for p in presets() {
                let scene = frame(vec![sphere_mesh(8, 4)], p, aspect);
                let cam = scene.camera;
                let Projection::Perspective { yfov, aspect: Some(a), znear, zfar: Some(zfar) } = cam.projection else {
                    panic!("framed camera is not perspective with an aspect")
                };
                assert_eq!(a, aspect);
                // The camera matrix is a rotation (orthonormal, right-handed) and a position.
                let m3 = glam::Mat3::from_mat4(cam.world_from_camera);
                assert!((m3.transpose() * m3).abs_diff_eq(glam::Mat3::IDENTITY, 1e-5), "{}", p.name);
                assert!((m3.determinant() - 1.0).abs() < 1e-5);
                let eye = cam.world_from_camera.w_axis.truncate();
                let d = eye.length();
                assert!(znear > 0.0 && znear < d - 1.0 && zfar > d + 1.0);
                // Looks at the centre, from the preset's direction, +Y up in the image.
                let forward = cam.world_from_camera.transform_vector3(-Vec3::Z);
                assert!(forward.dot(-eye / d) > 1.0 - 1e-6, "{}: forward {forward}", p.name);
                assert!((eye / d).dot(p.view_direction()) > 1.0 - 1e-6);
                let up = cam.world_from_camera.transform_vector3(Vec3::Y);
                assert!(up.y > 0.4 && up.dot(forward).abs() < 1e-5, "{}: up {up}", p.name);
                // The sphere's silhouette, tan(asin(1/d)), is 85% of the narrower half extent.
                let silhouette = (1.0 / d).asin().tan();
                let half = (yfov / 2.0).tan() * aspect.min(1.0);
                assert!((silhouette / half - 0.85).abs() < 1e-4, "aspect {aspect}: fill {}", silhouette / half);
                // The light, brought back to view space, is the preset's.
                let Light::Directional { direction, color, intensity } = scene.light else { panic!() };
                let towards_view = cam.world_from_camera.inverse().transform_vector3(-direction);
                assert!(towards_view.dot(p.light_in_view()) > 1.0 - 1e-5, "{}: {towards_view}", p.name);
                assert_eq!((color, intensity), (Vec3::ONE, 1.0));
            }
        }
        // front-left, worked by hand: the camera is at +Z (10° up), so light from the viewer's
        // upper left front travels towards +x, -y, -z in the world.
        let scene = frame(vec![sphere_mesh(8, 4)], &Preset::default(), 1.0);
        let Light::Directional { direction, .. } = scene.light else { panic!() };
        assert!(direction.x > 0.0 && direction.y < 0.0 && direction.z < 0.0, "{direction}");
        // back: the camera is behind the object, at -Z.
        let scene = frame(vec![sphere_mesh(8, 4)], &preset("back").unwrap(), 1.0);
        assert!(scene.camera.world_from_camera.w_axis.z < 0.0);
        // side: the camera is at +X.
        let scene = frame(vec![sphere_mesh(8, 4)], &preset("side").unwrap(), 1.0);
        assert!(scene.camera.world_from_camera.w_axis.x > 0.0);
    }

    #[test]
    fn framing_is_deterministic_and_centres_offset_objects() {
        let mut mesh = sphere_mesh(8, 4);
        mesh.transform(Mat4::from_scale_rotation_translation(Vec3::splat(3.0), glam::Quat::IDENTITY, Vec3::new(5.0, -2.0, 1.0)));
        let a = frame(vec![mesh.clone()], &Preset::default(), 1.5);
        let b = frame(vec![mesh], &Preset::default(), 1.5);
        assert_eq!(a.camera, b.camera);
        assert_eq!(a.light, b.light);
        let eye = a.camera.world_from_camera.w_axis.truncate();
        let forward = a.camera.world_from_camera.transform_vector3(-Vec3::Z);
        let to_centre = (Vec3::new(5.0, -2.0, 1.0) - eye).normalize();
        assert!(forward.dot(to_centre) > 1.0 - 1e-6);
        // Distance scales with the radius: 3 / sin(atan(0.85 tan 15°)).
        let expected = 3.0 / (FRAME_FILL * (FRAME_YFOV / 2.0).tan()).atan().sin();
        assert!(((Vec3::new(5.0, -2.0, 1.0) - eye).length() - expected).abs() < 1e-4);
    }

    #[test]
    fn builtin_models_load() {
        // (name, vertices of the file, has uvs)
        let expected = [
            ("sphere", 65 * 33, true),
            ("bunny", 2826, false),
            ("suzanne", 7503, false),
            ("teapot", 792, false),
            ("apple", 4019, true),
            ("fox", 1728, true),
        ];
        assert_eq!(builtin_models(), expected.map(|e| e.0).as_slice());
        for (name, vertices, has_uvs) in expected {
            let meshes = builtin_model(name).unwrap_or_else(|e| panic!("{name}: {e}"));
            let n: usize = meshes.iter().map(|m| m.positions.len()).sum();
            assert_eq!(n, vertices, "{name}");
            for m in &meshes {
                m.check().unwrap();
                assert!(!m.indices.is_empty(), "{name}");
                assert_eq!(m.uvs.is_some(), has_uvs, "{name}");
                // Tangents exactly where there are uvs.
                assert_eq!(m.tangents.is_some(), has_uvs, "{name}");
                assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4), "{name}");
            }
        }
    }
}
