//! The renderer: factored shading, reference shading, G-buffer, mask, outline, and an analytic
//! GGX shader for speed comparisons.
//!
//! Every pass draws the same meshes with the same vertex stage (`shaders/mesh.vert`) into an
//! RGBA32F target without multisampling, so every pass covers exactly the same pixels: the
//! pixels of the outline and reference images are the pixels the G-buffer (and so the
//! sampler) sees. Pixel $(i, j)$ has its centre at $(i + 0.5, j + 0.5)$, row 0 at the top.
//!
//! ```no_run
//! use brdfpaint::gl::HeadlessContext;
//! use brdfpaint::render::{mesh::uv_sphere, GpuScene, Renderer, ReferenceStyle};
//! use brdfpaint::scene::{Camera, Light, Projection, Scene};
//! use glam::{Mat4, Vec3};
//!
//! let ctx = HeadlessContext::new()?;
//! let scene = Scene {
//!     meshes: vec![uv_sphere(Vec3::ZERO, 1.0, 64, 32)],
//!     camera: Camera {
//!         world_from_camera: Mat4::from_translation(Vec3::new(0.0, 0.0, 4.0)),
//!         projection: Projection::Perspective { yfov: 0.8, aspect: None, znear: 0.1, zfar: None },
//!     },
//!     light: Light::Directional { direction: Vec3::new(1.0, -1.0, -1.0), color: Vec3::ONE, intensity: 1.0 },
//! };
//! let mut renderer = Renderer::new(ctx.gl())?;
//! let gpu = GpuScene::upload(ctx.gl(), &scene)?;
//! let reference = renderer.reference(&gpu, &ReferenceStyle::default(), 256, 256)?;
//! let g = renderer.gbuffer(&gpu, 256, 256)?; // l, v, uv per pixel for the sampler
//! assert_eq!(g.pixels.len(), reference.pixels.len());
//! # Ok::<(), brdfpaint::Error>(())
//! ```

mod camera;
pub mod env;
mod gbuffer;
pub mod mesh;
pub mod orbit;
mod shading;
pub mod sheet;

use std::collections::HashMap;

use glam::Vec3;
use glow::HasContext;

pub use camera::{LightUniforms, View};
pub use env::{Background, GpuEnvironment, Lighting};
pub use gbuffer::{GBuffer, GPixel, LineTracer, OutlineStyle};
pub use mesh::Mesh;
pub use orbit::Orbit;
pub use shading::{check, GpuShading, MAX_FACTORS, MAX_TERMS};
pub use sheet::{reference_exposure, Sheet, SHEET_FILES};

use crate::error::{Error, Result};
use crate::material::Material;
use crate::gl::{header, Framebuffer, Gl, Program};
use crate::scene::{Camera, Light, Scene};

/// The GLSL sources, compiled into the binary so `shaders/` documents exactly what runs.
pub mod sources {
    pub const MESH_VERT: &str = include_str!("../../shaders/mesh.vert");
    pub const SURFACE: &str = include_str!("../../shaders/surface.glsl");
    pub const PARAM: &str = include_str!("../../shaders/param.glsl");
    pub const TERM: &str = include_str!("../../shaders/term.glsl");
    pub const FACTORED_FRAG: &str = include_str!("../../shaders/factored.frag");
    pub const ENV: &str = include_str!("../../shaders/env.glsl");
    pub const ENV_FRAG: &str = include_str!("../../shaders/env.frag");
    pub const BACKGROUND_VERT: &str = include_str!("../../shaders/background.vert");
    pub const BACKGROUND_FRAG: &str = include_str!("../../shaders/background.frag");
    pub const REFERENCE_FRAG: &str = include_str!("../../shaders/reference.frag");
    pub const GBUFFER_FRAG: &str = include_str!("../../shaders/gbuffer.frag");
    pub const GGX_FRAG: &str = include_str!("../../shaders/ggx.frag");
}

/// A linear float RGBA image, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<[f32; 4]>,
}

impl Image {
    /// The pixel at column `i`, row `j`.
    pub fn at(&self, i: usize, j: usize) -> [f32; 4] {
        self.pixels[j * self.width + i]
    }

    /// The RGB channels (alpha dropped), as [`Rgb`](crate::images::Rgb) for writing PNG or EXR.
    pub fn to_rgb(&self) -> crate::images::Rgb {
        let pixels = self.pixels.iter().map(|p| [p[0], p[1], p[2]]).collect();
        crate::images::Rgb { width: self.width, height: self.height, pixels }
    }
}

/// A scene's meshes on the GPU, with its camera and light.
#[derive(Debug)]
pub struct GpuScene {
    pub meshes: Vec<Mesh>,
    pub camera: Camera,
    pub light: Light,
}

impl GpuScene {
    /// Uploads every mesh of `scene`.
    pub fn upload(gl: &Gl, scene: &Scene) -> Result<GpuScene> {
        let meshes = scene.meshes.iter().map(|m| Mesh::upload(gl, m)).collect::<Result<Vec<_>>>()?;
        Ok(GpuScene { meshes, camera: scene.camera, light: scene.light })
    }

    /// Total triangles.
    pub fn triangles(&self) -> usize {
        self.meshes.iter().map(Mesh::triangles).sum()
    }
}

/// The standard material of the reference image: Lambert plus Phong,
/// $c = k_a + E\,[k_d \max(\cos\theta_l, 0) + k_s \max(r \cdot v, 0)^n]$ with $E$ the
/// light's colour × intensity × falloff × `exposure`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceStyle {
    pub ambient: Vec3,
    pub diffuse: Vec3,
    pub specular: Vec3,
    pub shininess: f32,
    /// Scales the light (glTF intensities are physical; the reference only has to show
    /// where the light comes from).
    pub exposure: f32,
}

impl Default for ReferenceStyle {
    fn default() -> Self {
        ReferenceStyle {
            ambient: Vec3::splat(0.04),
            diffuse: Vec3::splat(0.6),
            specular: Vec3::splat(0.35),
            shininess: 32.0,
            exposure: 1.0,
        }
    }
}

/// Analytic Cook-Torrance with GGX, the model of [`crate::brdf::Analytic::Ggx`]
/// ($\alpha$ = `roughness`²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    pub diffuse: Vec3,
    pub f0: Vec3,
    pub roughness: f32,
}

impl Default for Ggx {
    fn default() -> Self {
        Ggx { diffuse: Vec3::new(0.45, 0.25, 0.12), f0: Vec3::splat(0.04), roughness: 0.4 }
    }
}

/// Draws [`GpuScene`]s with the passes of this module. Holds its programs (factored ones
/// are compiled per term layout on first use) and an offscreen target reused while the
/// size stays the same. Use it on the thread of its context.
pub struct Renderer {
    gl: Gl,
    reference: Program,
    gbuffer: Program,
    ggx: Program,
    factored: HashMap<String, Program>,
    background: Option<env::BackgroundPass>,
    target: Option<Framebuffer>,
}

impl Renderer {
    /// Compiles the fixed programs. Errors: shader compile or link failures (with the log).
    pub fn new(gl: &Gl) -> Result<Renderer> {
        Ok(Renderer {
            gl: gl.clone(),
            reference: mesh_program(gl, "reference", &[], sources::REFERENCE_FRAG)?,
            gbuffer: mesh_program(gl, "gbuffer", &[], sources::GBUFFER_FRAG)?,
            ggx: mesh_program(gl, "ggx", &[], sources::GGX_FRAG)?,
            factored: HashMap::new(),
            background: None,
            target: None,
        })
    }

    /// The GL function table.
    pub fn gl(&self) -> &Gl {
        &self.gl
    }

    /// Uploads a shading function for [`Renderer::factored`].
    pub fn upload(&self, material: &Material) -> Result<GpuShading> {
        GpuShading::upload(&self.gl, material)
    }

    /// The factored shading function under the scene's light:
    /// $S(l, v, uv) \times$ colour × intensity (× $1/d^2$ for point lights). Background is
    /// (0, 0, 0, 0); alpha is 1 on the object.
    pub fn factored(&mut self, scene: &GpuScene, shading: &GpuShading, width: usize, height: usize) -> Result<Image> {
        self.begin(width, height)?;
        self.draw_factored(scene, shading, width, height)?;
        self.read()
    }

    /// Draws the factored shading into the bound framebuffer (a window's, for the viewer),
    /// which the caller has cleared and whose viewport covers `width` × `height`. Terms after
    /// the first are added with blending.
    pub fn draw_factored(&mut self, scene: &GpuScene, shading: &GpuShading, width: usize, height: usize) -> Result<()> {
        let view = View::new(&scene.camera, width, height)?;
        let light = LightUniforms::new(&scene.light)?;
        for term in &shading.terms {
            if !self.factored.contains_key(&term.key) {
                let defines: Vec<(&str, String)> = term.defines.iter().map(|(n, v)| (*n, v.clone())).collect();
                let fragment = format!("{}\n{}", sources::TERM, sources::FACTORED_FRAG);
                let program = mesh_program(&self.gl, "factored", &defines, &fragment)?;
                self.factored.insert(term.key.clone(), program);
            }
        }
        let gl = &self.gl;
        for (k, term) in shading.terms.iter().enumerate() {
            let program = &self.factored[&term.key];
            program.bind();
            view.apply(program);
            light.apply(program);
            shading.apply(k, program);
            // SAFETY: state changes on the current context.
            unsafe { term_pass_state(gl, k) };
            for mesh in &scene.meshes {
                mesh.draw(gl);
            }
        }
        // SAFETY: restore the defaults the other passes assume.
        unsafe { default_pass_state(gl) };
        crate::gl::check_error(gl, "factored shading")
    }

    /// The reference image: Lambert + Phong under the scene's light (thesis 4.1).
    /// Background (0, 0, 0, 0).
    pub fn reference(
        &mut self,
        scene: &GpuScene,
        style: &ReferenceStyle,
        width: usize,
        height: usize,
    ) -> Result<Image> {
        let view = View::new(&scene.camera, width, height)?;
        let mut light = LightUniforms::new(&scene.light)?;
        light.rgb *= style.exposure;
        self.begin(width, height)?;
        let p = &self.reference;
        p.bind();
        view.apply(p);
        light.apply(p);
        p.set_vec3("u_ambient", style.ambient);
        p.set_vec3("u_diffuse", style.diffuse);
        p.set_vec3("u_specular", style.specular);
        p.set_f32("u_shininess", style.shininess);
        self.draw_all(p, scene);
        self.read()
    }

    /// The analytic GGX model under the scene's light, like [`Renderer::factored`].
    pub fn ggx(&mut self, scene: &GpuScene, model: &Ggx, width: usize, height: usize) -> Result<Image> {
        self.begin(width, height)?;
        self.draw_ggx(scene, model, width, height)?;
        self.read()
    }

    /// Draws the GGX model into the bound framebuffer.
    pub fn draw_ggx(&mut self, scene: &GpuScene, model: &Ggx, width: usize, height: usize) -> Result<()> {
        let view = View::new(&scene.camera, width, height)?;
        let light = LightUniforms::new(&scene.light)?;
        let p = &self.ggx;
        p.bind();
        view.apply(p);
        light.apply(p);
        p.set_vec3("u_diffuse", model.diffuse);
        p.set_vec3("u_f0", model.f0);
        p.set_f32("u_roughness", model.roughness);
        self.draw_all(p, scene);
        crate::gl::check_error(&self.gl, "GGX shading")
    }

    /// The G-buffer: six passes of the same geometry, one quantity each. Drawn and read in
    /// bands ([`Renderer::gbuffer_bands`]), so besides the result only one band's passes
    /// are held.
    pub fn gbuffer(&mut self, scene: &GpuScene, width: usize, height: usize) -> Result<GBuffer> {
        // The size is checked against the target's limits before anything is allocated.
        Framebuffer::sized(&mut self.target, &self.gl, width, height)?;
        let mut pixels = Vec::new();
        pixels.try_reserve_exact(width * height).map_err(|_| too_large("G-buffer", width, height))?;
        self.gbuffer_bands(scene, width, height, band_rows(width), |_, band| {
            pixels.extend_from_slice(&band.pixels);
            Ok(())
        })?;
        Ok(GBuffer { width, height, pixels })
    }

    /// The G-buffer of [`Renderer::gbuffer`] in horizontal bands of at most `rows` rows, top
    /// to bottom: `each(first_row, band)` gets a `width` × (band height) G-buffer. Each band
    /// is drawn with the six passes scissored to its rows on the full-size target, so its
    /// pixels are exactly the full G-buffer's (same viewport and rasterization); a 4096²
    /// image is then worked through with the memory of one band.
    pub fn gbuffer_bands(
        &mut self,
        scene: &GpuScene,
        width: usize,
        height: usize,
        rows: usize,
        mut each: impl FnMut(usize, GBuffer) -> Result<()>,
    ) -> Result<()> {
        Framebuffer::sized(&mut self.target, &self.gl, width, height)?;
        let view = View::new(&scene.camera, width, height)?;
        let light = LightUniforms::new(&scene.light)?;
        self.in_bands(height, rows, |r, band| {
            let mut passes: [Vec<[f32; 4]>; 6] = Default::default();
            for (k, pass) in passes.iter_mut().enumerate() {
                r.begin_band(width, height, band.clone())?;
                let p = &r.gbuffer;
                p.bind();
                view.apply(p);
                light.apply(p);
                p.set_i32("u_output", k as i32);
                r.draw_all(p, scene);
                *pass = r.read_rows(band.clone())?;
            }
            each(band.start, gbuffer::assemble(width, band.len(), &passes))
        })
    }

    /// The reference image of [`Renderer::reference`] in horizontal bands of at most `rows`
    /// rows, top to bottom, as [`Renderer::gbuffer_bands`] draws the G-buffer.
    pub fn reference_bands(
        &mut self,
        scene: &GpuScene,
        style: &ReferenceStyle,
        width: usize,
        height: usize,
        rows: usize,
        mut each: impl FnMut(usize, Image) -> Result<()>,
    ) -> Result<()> {
        Framebuffer::sized(&mut self.target, &self.gl, width, height)?;
        let view = View::new(&scene.camera, width, height)?;
        let mut light = LightUniforms::new(&scene.light)?;
        light.rgb *= style.exposure;
        self.in_bands(height, rows, |r, band| {
            r.begin_band(width, height, band.clone())?;
            let p = &r.reference;
            p.bind();
            view.apply(p);
            light.apply(p);
            p.set_vec3("u_ambient", style.ambient);
            p.set_vec3("u_diffuse", style.diffuse);
            p.set_vec3("u_specular", style.specular);
            p.set_f32("u_shininess", style.shininess);
            r.draw_all(p, scene);
            let pixels = r.read_rows(band.clone())?;
            each(band.start, Image { width, height: band.len(), pixels })
        })
    }

    /// Calls `band(self, rows)` for the bands of `rows` rows of an image `height` high, top
    /// to bottom, and then turns the scissor test off, whatever happened: code that draws
    /// after (the viewer, the stroke timing) clears and draws the whole target.
    fn in_bands(
        &mut self,
        height: usize,
        rows: usize,
        mut band: impl FnMut(&mut Renderer, std::ops::Range<usize>) -> Result<()>,
    ) -> Result<()> {
        let rows = rows.max(1);
        let result = (0..height).step_by(rows).try_for_each(|start| band(self, start..(start + rows).min(height)));
        // SAFETY: a state change on the current context.
        unsafe { self.gl.disable(glow::SCISSOR_TEST) };
        result
    }

    /// The coverage mask: 1 where the pixel centre sees the object, else 0 (one pass).
    pub fn mask(&mut self, scene: &GpuScene, width: usize, height: usize) -> Result<Image> {
        let view = View::new(&scene.camera, width, height)?;
        let light = LightUniforms::new(&scene.light)?;
        self.begin(width, height)?;
        let p = &self.gbuffer;
        p.bind();
        view.apply(p);
        light.apply(p);
        p.set_i32("u_output", 0);
        self.draw_all(p, scene);
        let mut image = self.read()?;
        for px in &mut image.pixels {
            *px = if px[3] > 0.5 { [1.0; 4] } else { [0.0, 0.0, 0.0, 1.0] };
        }
        Ok(image)
    }

    /// The coloring-book page: black silhouette, crease and occlusion lines on white.
    pub fn outline(&mut self, scene: &GpuScene, style: &OutlineStyle, width: usize, height: usize) -> Result<Image> {
        Ok(self.gbuffer(scene, width, height)?.outline(style))
    }

    /// Binds the offscreen target of this size (made or remade as needed), clears colour to
    /// (0, 0, 0, 0) and depth to 1, enables the depth test (`LESS`), no blending, no culling
    /// (meshes are drawn two-sided).
    pub fn begin(&mut self, width: usize, height: usize) -> Result<()> {
        Framebuffer::sized(&mut self.target, &self.gl, width, height)?.begin_pass();
        crate::gl_check!(self.gl, "target setup");
        Ok(())
    }

    /// [`Renderer::begin`], drawing only rows `rows` (from the top) of the target (the
    /// scissor stays on until [`Renderer::in_bands`] ends).
    fn begin_band(&mut self, width: usize, height: usize, rows: std::ops::Range<usize>) -> Result<()> {
        Framebuffer::sized(&mut self.target, &self.gl, width, height)?.begin_band(rows);
        crate::gl_check!(self.gl, "target setup");
        Ok(())
    }

    fn read_rows(&self, rows: std::ops::Range<usize>) -> Result<Vec<[f32; 4]>> {
        let target = self.target.as_ref().ok_or_else(|| Error::Gl("nothing was rendered".into()))?;
        target.read_rows(rows)
    }

    fn draw_all(&self, program: &Program, scene: &GpuScene) {
        program.bind();
        for mesh in &scene.meshes {
            mesh.draw(&self.gl);
        }
    }

    fn read(&self) -> Result<Image> {
        let target = self.target.as_ref().ok_or_else(|| Error::Gl("nothing was rendered".into()))?;
        Ok(Image { width: target.width(), height: target.height(), pixels: target.read()? })
    }
}

/// Pixels in one band of a banded pass: 2^18 (64 rows of a 4096-wide image, 16 MiB of
/// RGBA floats per pass). Images of up to 512² are one band: one draw per pass, as before
/// bands; larger ones trade a few more draws (vertex work only: the scissor limits the
/// fragments) for memory that does not grow with the image.
pub const BAND_PIXELS: usize = 1 << 18;

/// Rows in one band of a `width`-wide banded pass ([`BAND_PIXELS`]).
pub fn band_rows(width: usize) -> usize {
    (BAND_PIXELS / width.max(1)).max(1)
}

fn too_large(what: &str, width: usize, height: usize) -> Error {
    Error::input(format!("not enough memory for a {width}x{height} {what}"))
}

/// Depth and blending for the pass of term `k` of a material.
///
/// # Safety
/// A current context.
unsafe fn term_pass_state(gl: &Gl, k: usize) {
    if k == 0 {
        // First term: the nearest surface wins, written as is.
        gl.enable(glow::DEPTH_TEST);
        gl.depth_func(glow::LESS);
        gl.depth_mask(true);
        gl.disable(glow::BLEND);
    } else {
        // Later terms: the same fragments again (invariant gl_Position, so equal
        // depths), added to the colour; alpha keeps the first pass's coverage.
        gl.depth_func(glow::LEQUAL);
        gl.depth_mask(false);
        gl.enable(glow::BLEND);
        gl.blend_equation(glow::FUNC_ADD);
        gl.blend_func_separate(glow::ONE, glow::ONE, glow::ZERO, glow::ONE);
    }
}

/// The depth and blending defaults the other passes assume.
///
/// # Safety
/// A current context.
unsafe fn default_pass_state(gl: &Gl) {
    gl.depth_mask(true);
    gl.depth_func(glow::LESS);
    gl.disable(glow::BLEND);
}

/// A program of the shared vertex stage and a fragment stage that uses `surface()` (and the
/// parameterizations), with `defines` prepended to both.
fn mesh_program(gl: &Gl, name: &str, defines: &[(&str, String)], fragment: &str) -> Result<Program> {
    let head = header(gl, defines);
    let vs = format!("{head}{}", sources::MESH_VERT);
    let fs = format!("{head}{}\n{}\n{fragment}", sources::SURFACE, sources::PARAM);
    Program::new(gl, name, &vs, &fs)
}
