//! Materials under HDR environments (image-based lighting), beside the scene's light.
//!
//! The outgoing radiance of a factored material under an environment $L_{env}$ is
//!
//! $$ L_o(v, uv) = \int_{H^2} S(l, v, uv)\, L_{env}(l)\, d\omega_l \;+\; S(l_{key}, v, uv)\, E_{key} $$
//!
//! with the material's own $S = f_r \cos\theta_l$ (DESIGN.md) over the hemisphere $H^2$
//! above the shading normal: there an environment is a sum of directional lights, and a
//! material lit by one small bright spot looks as it does under a point light. Below the
//! horizon the surface hides the environment (a painting's unlit side is how the artist
//! painted the key light's absence; `shaders/env.frag` says more).
//!
//! # Method, and its error
//! `shaders/env.frag` estimates the integral with a fixed set of [`Lighting::samples`]
//! directions per pixel, in four strategies (uniform hemisphere, cosine, two Phong lobes around
//! the mirror direction) combined with the balance heuristic (Veach 1997, 9.2), and reads
//! the environment with filtered importance sampling (Colbert and Křivánek 2007): each
//! sample reads the mip level whose texels cover the solid angle the sample stands for.
//! It works for any material the renderer draws (any factors, inputs, terms), because each
//! sampled direction goes through the one evaluation of a term, `shaders/term.glsl`.
//!
//! Why this rather than the alternatives the issue names: importance sampling from the
//! factor tables (Lawrence et al. 2004) needs a marginal/conditional table per factor of
//! $l$ given $v$, and factors of $h$ and of $uv$ are not distributions over $l$; tables
//! prefiltered per material and environment need one table per term, view and frame
//! (5D for a general frame). The mixture needs neither and stays unbiased (the uniform
//! strategy covers every direction); only the filtering blurs.
//!
//! The error is a smooth bias from the filtering and the fixed pattern, never noise: against
//! a CPU Monte-Carlo reference of the same material and environment (tests/env_render.rs),
//! with the default 64 directions, the worst pixel is off by up to 10% of the image's
//! brightest (measured 5–8%, at the highlight of a bright source and at grazing views) and
//! the mean by 1.5% (measured 0.4–0.9%); with 256 directions 3% and 0.5%. A lobe sharper
//! than the narrow strategy's ($\cos^{80}$, about 10°) gets few directions: its reflection of
//! a small bright source is expected to show as a few overlapping soft copies rather than one
//! sharp one; more directions (`--env-samples`) shrink them. Preparing an environment is its upload and
//! mip chain ([`GpuEnvironment::upload`]); nothing depends on the material, so switching
//! materials or painting live costs nothing more.

use std::collections::hash_map::Entry;

use glam::Vec3;
use glow::HasContext;

use super::{camera::LightUniforms, mesh_program, shading, sources, GpuScene, GpuShading, Image, Renderer, View};
use crate::error::{Error, Result};
use crate::gl::{header, Gl, Program, Texture2D, VertexArray};
use crate::images::env::Environment;

/// Directions per pixel by default: with 64 the error against a Monte-Carlo reference
/// stays within tests/env_render.rs's stated tolerance (32 doubled its worst pixels).
/// A real-time view on a GPU affords it; on llvmpipe it costs seconds (BENCHMARKS.md).
pub const DEFAULT_SAMPLES: usize = 64;
/// Sample counts accepted (each strategy gets at least one sample from 8 on).
pub const SAMPLES: std::ops::RangeInclusive<usize> = 8..=1024;

/// An environment on the GPU: a mip-mapped RGBA32F panorama.
pub struct GpuEnvironment {
    texture: Texture2D,
}

impl GpuEnvironment {
    /// Uploads `env` and builds its mip chain (the prefiltering that filtered importance
    /// sampling reads).
    pub fn upload(gl: &Gl, env: &Environment) -> Result<GpuEnvironment> {
        let rgba: Vec<f32> = env.pixels.iter().flat_map(|p| [p[0], p[1], p[2], 1.0]).collect();
        Ok(GpuEnvironment { texture: Texture2D::panorama(gl, env.width, env.height, &rgba)? })
    }

    /// Binds it on `unit` and sets the lookup uniforms of `env.glsl`.
    fn apply(&self, program: &Program, unit: u32, rotate_deg: f32) {
        self.texture.bind(unit);
        program.set_i32("u_env", unit as i32);
        program.set_f32("u_env_turn", rotate_deg / 360.0);
        program.set_vec2("u_env_size", glam::Vec2::new(self.texture.width() as f32, self.texture.height() as f32));
    }
}

impl std::fmt::Debug for GpuEnvironment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "GpuEnvironment({}x{})", self.texture.width(), self.texture.height())
    }
}

/// What is behind the object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// The environment itself, seen along each camera ray (sharp, level 0).
    Environment,
    /// A flat linear colour (black is `Color(Vec3::ZERO)`).
    Color(Vec3),
}

/// How a frame is lit: the environment, its rotation, the key light, the background.
#[derive(Clone, Copy, Debug)]
pub struct Lighting<'a> {
    pub environment: &'a GpuEnvironment,
    /// Rotation of the environment about $+y$ in degrees (`images::env`, Convention).
    pub rotate_deg: f32,
    /// Adds the scene's light (the key light) to the environment.
    pub key_light: bool,
    pub background: Background,
    /// Directions per pixel ([`SAMPLES`]).
    pub samples: usize,
}

impl<'a> Lighting<'a> {
    /// The environment alone, unrotated, shown behind the object, [`DEFAULT_SAMPLES`].
    pub fn new(environment: &'a GpuEnvironment) -> Lighting<'a> {
        Lighting { environment, rotate_deg: 0.0, key_light: false, background: Background::Environment, samples: DEFAULT_SAMPLES }
    }
}

/// Samples per strategy: uniform, cosine, wide lobe, narrow lobe. An eighth uniform keeps
/// the mixture density positive everywhere; the rest favours the cosine and the lobes,
/// which carry most of a painted material's energy.
fn strategy_counts(samples: usize) -> [usize; 4] {
    let uniform = (samples / 8).max(1);
    let cosine = (samples * 3 / 8).max(1);
    let wide = (samples - uniform - cosine) / 2;
    [uniform, cosine, wide, samples - uniform - cosine - wide]
}

/// Texture unit of the environment (after the factors' and the coefficients' units).
const ENV_UNIT: u32 = shading::COEF_UNIT + 1;

/// The background program and the empty vertex array its attribute-less triangle needs.
pub(super) struct BackgroundPass {
    program: Program,
    vao: VertexArray,
}

impl BackgroundPass {
    fn new(gl: &Gl) -> Result<BackgroundPass> {
        let head = header(gl, &[]);
        let vs = format!("{head}{}", sources::BACKGROUND_VERT);
        let fs = format!("{head}{}\n{}", sources::ENV, sources::BACKGROUND_FRAG);
        Ok(BackgroundPass { program: Program::new(gl, "background", &vs, &fs)?, vao: VertexArray::new(gl)? })
    }
}

impl Renderer {
    /// The factored material under `lighting`, with the background drawn behind it. Alpha
    /// is 1 on the object, 0 elsewhere.
    pub fn lit(
        &mut self,
        scene: &GpuScene,
        shading: &GpuShading,
        lighting: &Lighting,
        width: usize,
        height: usize,
    ) -> Result<Image> {
        self.begin(width, height)?;
        self.draw_lit(scene, shading, lighting, width, height)?;
        self.read()
    }

    /// Draws the background and the lit material into the bound framebuffer (a window's,
    /// for the viewer), whose viewport covers `width` × `height`; depth is cleared by the
    /// caller. Terms after the first are added with blending, as in
    /// [`Renderer::draw_factored`].
    pub fn draw_lit(
        &mut self,
        scene: &GpuScene,
        shading: &GpuShading,
        lighting: &Lighting,
        width: usize,
        height: usize,
    ) -> Result<()> {
        if !SAMPLES.contains(&lighting.samples) {
            return Err(Error::input(format!(
                "{} environment samples per pixel; {} to {} are drawn",
                lighting.samples,
                SAMPLES.start(),
                SAMPLES.end()
            )));
        }
        let view = View::new(&scene.camera, width, height)?;
        let light = LightUniforms::new(&scene.light)?;
        self.draw_background(&view, lighting)?;

        let counts = strategy_counts(lighting.samples);
        let mut keys = Vec::with_capacity(shading.terms.len());
        for term in &shading.terms {
            let key = format!("env:{}:{}", lighting.samples, term.key);
            if let Entry::Vacant(slot) = self.factored.entry(key.clone()) {
                let mut defines: Vec<(&str, String)> = term.defines.iter().map(|(n, v)| (*n, v.clone())).collect();
                defines.push(("ENV_SAMPLES", lighting.samples.to_string()));
                for (name, n) in ["ENV_UNIFORM", "ENV_COSINE", "ENV_WIDE", "ENV_NARROW"].into_iter().zip(counts) {
                    defines.push((name, n.to_string()));
                }
                let fragment = format!("{}\n{}\n{}", sources::ENV, sources::TERM, sources::ENV_FRAG);
                slot.insert(mesh_program(&self.gl, "environment", &defines, &fragment)?);
            }
            keys.push(key);
        }
        let gl = &self.gl;
        for (k, key) in keys.iter().enumerate() {
            let program = &self.factored[key];
            program.bind();
            view.apply(program);
            light.apply(program);
            shading.apply(k, program);
            lighting.environment.apply(program, ENV_UNIT, lighting.rotate_deg);
            program.set_f32("u_key", if lighting.key_light { 1.0 } else { 0.0 });
            // SAFETY: state changes on the current context (as draw_factored).
            unsafe { super::term_pass_state(gl, k) };
            for mesh in &scene.meshes {
                mesh.draw(gl);
            }
        }
        // SAFETY: restore the defaults the other passes assume.
        unsafe { super::default_pass_state(gl) };
        crate::gl::check_error(gl, "environment shading")
    }

    /// The background over the whole viewport, without touching depth.
    fn draw_background(&mut self, view: &View, lighting: &Lighting) -> Result<()> {
        if self.background.is_none() {
            self.background = Some(BackgroundPass::new(&self.gl)?);
        }
        let pass = self.background.as_ref().expect("made above");
        let gl = &self.gl;
        let p = &pass.program;
        p.bind();
        p.set_mat4("u_world_from_clip", &view.view_proj.inverse());
        lighting.environment.apply(p, ENV_UNIT, lighting.rotate_deg);
        let (show, colour) = match lighting.background {
            Background::Environment => (1, Vec3::ZERO),
            Background::Color(c) => (0, c),
        };
        p.set_i32("u_show_env", show);
        p.set_vec3("u_background", colour);
        pass.vao.bind();
        // SAFETY: state changes on the current context; the triangle needs no attributes.
        unsafe {
            gl.disable(glow::DEPTH_TEST);
            gl.depth_mask(false);
            gl.disable(glow::BLEND);
            gl.draw_arrays(glow::TRIANGLES, 0, 3);
            gl.depth_mask(true);
            gl.enable(glow::DEPTH_TEST);
        }
        crate::gl::check_error(gl, "background")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_strategy_gets_samples_and_they_add_up() {
        for n in SAMPLES.step_by(7).chain([32, 64]) {
            let c = strategy_counts(n);
            assert_eq!(c.iter().sum::<usize>(), n, "{n}");
            assert!(c.iter().all(|&k| k >= 1), "{n}: {c:?}");
        }
        assert_eq!(strategy_counts(32), [4, 12, 8, 8]);
    }
}
