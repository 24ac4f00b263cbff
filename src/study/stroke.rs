//! The headless stroke → frame measurement of the live path (`brdfpaint bench` and the
//! viewer tests run it; BENCHMARKS.md, "Live painting").

use std::time::Instant;

use glam::Vec2;
use glow::HasContext;

use super::median;
use crate::error::{Error, Result};
use crate::factor::{Channels, Mapping, Settings};
use crate::gl::{Framebuffer, HeadlessContext};
use crate::live::{Brush, PaintSession, PaintView};
use crate::render::{GpuScene, Renderer};

/// The headless stroke → refit → frame measurement (DESIGN.md: live painting must fit in one
/// 60 Hz frame), medians in milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct StrokeTiming {
    /// Painting side in pixels.
    pub size: usize,
    /// Samples of the painting.
    pub samples: usize,
    /// Unknowns of the prepared system.
    pub unknowns: usize,
    pub strokes: usize,
    /// Applying the stroke to the canvas.
    pub stroke_ms: f64,
    /// Painted colours → sample values.
    pub values_ms: f64,
    /// `solve_tables` and the material.
    pub solve_ms: f64,
    /// Material → textures.
    pub upload_ms: f64,
    /// Drawing the model with the new material at `size`², to `glFinish`.
    pub frame_ms: f64,
    /// All of the above, per stroke.
    pub total_ms: f64,
    /// The same, while the full fit runs on its worker (the window's settling).
    pub total_during_fit_ms: f64,
    /// The background prepare for the painting (once per set of painted pixels).
    pub prepare_ms: f64,
    /// One full fit of the painting on its worker, start to result (`fit`'s reading and fit,
    /// prepared without a cache): how long after the pause the window settles.
    pub full_fit_ms: f64,
}

/// Measures stroke → samples → solve → upload → frame on a headless context (Mesa's software
/// device): `model` (built-in name or file) in the front-left standard view, a `size`²
/// painting (the reference image, fully painted), then `strokes` short strokes over the
/// painted object, each refitting and drawing a `size`² frame of the model with the new
/// material. Then as many strokes again with the full fit (`fit`'s reading and fit, what the
/// window settles on) running on its worker the whole time: a stroke's cost while the worker
/// shares the CPU.
pub fn measure_stroke_to_frame(model: &str, size: usize, strokes: usize, channels: Channels) -> Result<StrokeTiming> {
    let ctx = HeadlessContext::new()?;
    let gl = ctx.gl().clone();
    let mut renderer = Renderer::new(&gl)?;
    let mut view = PaintView::standard(&mut renderer, model, "front-left", size)?;
    let painting = view.reference_painting();
    view.canvas.set_painting(&painting)?;
    let gpu = GpuScene::upload(&gl, &view.scene)?;
    let mut session = PaintSession::new(Settings { channels, ..Settings::default() }, Mapping::Auto);
    session.add_view(view);
    let t = Instant::now();
    session.settle()?;
    let prepare_ms = t.elapsed().as_secs_f64() * 1e3;
    let mut loop_ = StrokeLoop { gl: &gl, renderer: &mut renderer, gpu: &gpu, target: Framebuffer::new(&gl, size, size)?, size };
    let rows = loop_.run(&mut session, strokes, false)?;
    let during = loop_.run(&mut session, strokes, true)?;
    // The last worker finishes (its result is stale: dropped), then one full fit is timed.
    session.wait_full()?;
    let t = Instant::now();
    session.start_full();
    session.wait_full()?;
    let full_fit_ms = t.elapsed().as_secs_f64() * 1e3;
    let column = |i: usize| if rows.is_empty() { 0.0 } else { median(&rows.iter().map(|r| r[i]).collect::<Vec<_>>()) };
    let total = |rows: &[[f64; 5]]| if rows.is_empty() { 0.0 } else { median(&rows.iter().map(|r| r.iter().sum()).collect::<Vec<f64>>()) };
    let prepared = session.prepared_samples().unwrap_or(0);
    Ok(StrokeTiming {
        size,
        samples: prepared,
        unknowns: session.settings().unknowns(),
        strokes,
        stroke_ms: column(0),
        values_ms: column(1),
        solve_ms: column(2),
        upload_ms: column(3),
        frame_ms: column(4),
        total_ms: total(&rows),
        total_during_fit_ms: total(&during),
        prepare_ms,
        full_fit_ms,
    })
}

/// The strokes of one measurement and the frame each is drawn into.
struct StrokeLoop<'a> {
    gl: &'a glow::Context,
    renderer: &'a mut Renderer,
    gpu: &'a GpuScene,
    target: Framebuffer,
    size: usize,
}

impl StrokeLoop<'_> {
    /// `strokes` timed strokes after a few untimed ones, each a row of milliseconds: stroke,
    /// values, solve, upload, frame. `during_fit`: a full fit runs on the worker throughout
    /// (each stroke leaves it stale; when it ends the next starts).
    fn run(&mut self, session: &mut PaintSession, strokes: usize, during_fit: bool) -> Result<Vec<[f64; 5]>> {
        let gl = self.gl;
        let warm = strokes / 10 + 2;
        let mut rows: Vec<[f64; 5]> = Vec::with_capacity(strokes);
        let s = self.size as f32;
        for k in 0..warm + strokes {
            if during_fit {
                session.take_full()?;
                session.start_full();
            }
            // A short stroke across the middle of the object, its colour changing every time.
            let phase = k as f32 / (warm + strokes) as f32;
            let brush = Brush {
                color: [0.2 + 0.6 * phase, 0.3, 0.8 - 0.5 * phase],
                radius: s / 40.0,
                hardness: 0.6,
                opacity: 0.8,
                erase: false,
            };
            let y = s * (0.45 + 0.1 * phase);
            let t0 = Instant::now();
            session.views[0].canvas.stroke(brush, &[Vec2::new(0.42 * s, y), Vec2::new(0.58 * s, y)]);
            let t1 = Instant::now();
            let refit = session.refit()?.ok_or_else(|| Error::Numeric("no refit".into()))?;
            let t2 = Instant::now();
            let material = session.material().expect("refit made one");
            let shading = self.renderer.upload(material)?;
            let t3 = Instant::now();
            self.target.bind();
            // SAFETY: plain state calls on the current context.
            unsafe {
                gl.clear_color(0.0, 0.0, 0.0, 0.0);
                gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
                gl.enable(glow::DEPTH_TEST);
            }
            self.renderer.draw_factored(self.gpu, &shading, self.size, self.size)?;
            // SAFETY: waits for the GPU on the current context.
            unsafe { gl.finish() };
            let t4 = Instant::now();
            if k >= warm {
                let ms = |a: Instant, b: Instant| (b - a).as_secs_f64() * 1e3;
                rows.push([ms(t0, t1), refit.values_ms, ms(t1, t2) - refit.values_ms, ms(t2, t3), ms(t3, t4)]);
            }
        }
        Ok(rows)
    }
}
