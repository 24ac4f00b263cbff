//! Scene geometry: a glTF scene rasterized by the renderer's G-buffer, so the sampled
//! pixels are exactly the pixels the outline and reference passes cover (same vertex
//! stage, same `surface()` code, no multisampling).

use std::path::Path;

use glam::{DVec2, DVec3};

use super::{Erosion, Geometry, PaintedView, PixelGeometry};
use crate::error::{Error, Result};
use crate::factor::Query;
use crate::gl::HeadlessContext;
use crate::images::Painting;
use crate::render::{GBuffer, GpuScene, Renderer};
use crate::scene::{Camera, Light, Projection, Scene};

/// Largest disagreement between the camera's aspect and the painting's W/H (DESIGN.md).
pub const ASPECT_TOLERANCE: f64 = 0.01;

/// A headless renderer for sampling scenes. Holds its own GL context; use it on one thread.
pub struct SceneSampler {
    // Declared before the context so it is dropped while the context still exists.
    renderer: Renderer,
    ctx: HeadlessContext,
}

impl SceneSampler {
    /// A headless EGL context (llvmpipe unless told otherwise) and a renderer.
    pub fn new() -> Result<SceneSampler> {
        let ctx = HeadlessContext::new()?;
        let renderer = Renderer::new(ctx.gl())?;
        Ok(SceneSampler { renderer, ctx })
    }

    /// The renderer, for other passes on the same context.
    pub fn renderer(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// The context.
    pub fn context(&self) -> &HeadlessContext {
        &self.ctx
    }

    /// The G-buffer of `scene` at `width` × `height`.
    pub fn gbuffer(&mut self, scene: &Scene, width: usize, height: usize) -> Result<GBuffer> {
        self.ctx.make_current()?;
        let gpu = GpuScene::upload(self.ctx.gl(), scene)?;
        self.renderer.gbuffer(&gpu, width, height)
    }

    /// The geometry of `scene` at `width` × `height` (see [`geometry_from_gbuffer`]).
    pub fn geometry(&mut self, scene: &Scene, width: usize, height: usize, erosion: Erosion) -> Result<Geometry> {
        self.gbuffer_and_geometry(scene, width, height, erosion).map(|(_, geometry)| geometry)
    }

    /// The G-buffer and the geometry drawn from it.
    fn gbuffer_and_geometry(&mut self, scene: &Scene, width: usize, height: usize, erosion: Erosion) -> Result<(GBuffer, Geometry)> {
        crate::images::check_size(width, height)?;
        let g = self.gbuffer(scene, width, height)?;
        let has_uv = scene.meshes.iter().all(|m| m.uvs.is_some());
        let geometry = geometry_from_gbuffer(&g, &scene.light, has_uv, erosion)?;
        Ok((g, geometry))
    }

    /// Load a scene and its painting and sample them: the painting's size sets the pixel
    /// grid, and a camera aspect that disagrees with it by more than 1% is an error. Errors
    /// name the file.
    pub fn load_view(&mut self, scene_path: &Path, painting_path: &Path, erosion: Erosion) -> Result<(Scene, PaintedView)> {
        self.load_with_gbuffer(scene_path, painting_path, erosion).map(|(scene, view, _)| (scene, view))
    }

    /// [`SceneSampler::load_view`] for a painting that may have been made on the sheet's
    /// page: what the page put there is left out ([`super::page::remove_page`], with the
    /// lines drawn from the same G-buffer the geometry comes from), and said. The G-buffer
    /// comes back too: it holds each pixel's frame, for turning the light
    /// ([`super::register`]).
    pub fn load_painted_view(
        &mut self,
        scene_path: &Path,
        painting_path: &Path,
        erosion: Erosion,
    ) -> Result<(Scene, PaintedView, GBuffer, Option<super::page::PageLeftovers>)> {
        let (scene, mut view, g) = self.load_with_gbuffer(scene_path, painting_path, erosion)?;
        let hit: Vec<bool> = g.pixels.iter().map(|p| p.hit).collect();
        let lines = g.lines(&crate::render::OutlineStyle::default());
        let left = super::page::remove_page(&mut view.painting, &lines, &hit);
        Ok((scene, view, g, left))
    }

    fn load_with_gbuffer(&mut self, scene_path: &Path, painting_path: &Path, erosion: Erosion) -> Result<(Scene, PaintedView, GBuffer)> {
        let scene = Scene::load(scene_path)?;
        let name = painting_path.display().to_string();
        // The aspect is checked from the header first, so a mismatched painting is refused
        // without being decoded (a file that has no readable header gets its error below).
        if let Ok((width, height)) = crate::images::header_size(painting_path) {
            check_aspect(&scene.camera, width, height, &name)?;
        }
        let painting = Painting::read(painting_path)?;
        check_aspect(&scene.camera, painting.width, painting.height, &name)?;
        let (g, geometry) =
            self.gbuffer_and_geometry(&scene, painting.width, painting.height, erosion).map_err(|e| match e {
                Error::Input(m) => Error::input(format!("{}: {m}", scene_path.display())),
                other => other,
            })?;
        let view = PaintedView { name, source: scene_path.display().to_string(), geometry, painting };
        Ok((scene, view, g))
    }
}

/// The light's colour × intensity per channel. Every channel must be positive and finite,
/// or it could not be divided out.
pub fn light_rgb(light: &Light) -> Result<[f64; 3]> {
    let (color, intensity) = match *light {
        Light::Directional { color, intensity, .. } | Light::Point { color, intensity, .. } => (color, intensity),
    };
    let rgb = (color * intensity).as_dvec3().to_array();
    if rgb.iter().any(|&x| !(x > 0.0 && x.is_finite())) {
        return Err(Error::input(format!(
            "the light's colour {color} x intensity {intensity} has a zero, negative or non-finite channel, so it cannot be divided out of the painting"
        )));
    }
    Ok(rgb)
}

/// The geometry of a G-buffer: pixels that see the object and face the camera
/// ($v_z > 0$; the G-buffer marks back-facing pixels as hits too), with the light's
/// colour × intensity × falloff. `erosion` removes the silhouette band, measured from the
/// G-buffer's coverage (a back-facing pixel is object, not background).
pub fn geometry_from_gbuffer(g: &GBuffer, light: &Light, has_uv: bool, erosion: Erosion) -> Result<Geometry> {
    let rgb = light_rgb(light)?;
    let pixels: Vec<Option<PixelGeometry>> = g
        .pixels
        .iter()
        .map(|p| {
            let q = p.query()?;
            // Back-facing (an interpolated normal turned away from the eye at the rim) and
            // grazing pixels are not samples: $v_z \le 0$ has no place in the view factor.
            // (Written so that NaN is rejected too.)
            if q.v.z.is_nan() || q.v.z <= 0.0 || p.falloff.is_nan() || p.falloff <= 0.0 {
                return None;
            }
            let f = p.falloff as f64;
            Some(PixelGeometry {
                query: Query { uv: if has_uv { q.uv } else { DVec2::ZERO }, ..q },
                position: Some(p.position.as_dvec3()),
                light: rgb.map(|c| c * f),
            })
        })
        .collect();
    let coverage: Vec<bool> = g.pixels.iter().map(|p| p.hit).collect();
    let kept = erosion.apply(&coverage, g.width, g.height);
    let usable = pixels.iter().zip(&kept).map(|(p, &k)| k && p.is_some()).collect();
    Ok(Geometry { width: g.width, height: g.height, pixels, usable, left_out: 0, has_uv })
}

/// The aspect (width / height) a camera was made for, if it says: a perspective camera's
/// aspectRatio, an orthographic camera's xmag / ymag.
pub fn camera_aspect(camera: &Camera) -> Option<f64> {
    match camera.projection {
        Projection::Perspective { aspect, .. } => aspect.map(|a| a as f64),
        Projection::Orthographic { xmag, ymag, .. } => (ymag != 0.0).then(|| (xmag / ymag).abs() as f64),
    }
}

/// A painting of `width` × `height` must match the camera's aspect within 1% (DESIGN.md):
/// `error: painting.png is 640x480 but the scene camera's aspect is 1.0`.
pub fn check_aspect(camera: &Camera, width: usize, height: usize, painting: &str) -> Result<()> {
    let Some(aspect) = camera_aspect(camera) else { return Ok(()) };
    let ours = width as f64 / height as f64;
    // The epsilon keeps exactly 1% (e.g. 101x100 against 1.0) on the allowed side.
    if (ours - aspect).abs() > ASPECT_TOLERANCE * aspect + 1e-9 {
        return Err(Error::input(format!(
            "{painting} is {width}x{height} but the scene camera's aspect is {:?}",
            aspect as f32
        )));
    }
    Ok(())
}

/// Vertex count and bounding box of a scene's meshes.
fn model_summary(scene: &Scene) -> (usize, DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let mut n = 0;
    for m in &scene.meshes {
        n += m.positions.len();
        for p in &m.positions {
            lo = lo.min(p.as_dvec3());
            hi = hi.max(p.as_dvec3());
        }
    }
    (n, lo, hi)
}

/// Two views of one material must show the same model (thesis 4.4): the same number of
/// vertices and the same bounding box (within 1e-4 of its diagonal). Cameras and lights
/// may differ.
pub fn check_same_model(first: &Scene, first_name: &str, other: &Scene, other_name: &str) -> Result<()> {
    let (n1, lo1, hi1) = model_summary(first);
    let (n2, lo2, hi2) = model_summary(other);
    if n1 != n2 {
        return Err(Error::input(format!(
            "{other_name} shows another model than {first_name} ({n2} vertices, not {n1}): every view must show the same model"
        )));
    }
    let tol = 1e-4 * (hi1 - lo1).length().max(f64::MIN_POSITIVE);
    if (lo1 - lo2).abs().max_element() > tol || (hi1 - hi2).abs().max_element() > tol {
        return Err(Error::input(format!(
            "{other_name} shows another model than {first_name} (bounds {lo2:.4}..{hi2:.4}, not {lo1:.4}..{hi1:.4}): every view must show the same model"
        )));
    }
    Ok(())
}
