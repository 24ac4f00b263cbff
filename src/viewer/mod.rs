//! The real-time viewer (`brdfpaint view`) and its headless live-painting core.
//!
//! - [`paint`]: painted views, the prepared system and the refit a stroke triggers, with no
//!   window (tests and `brdfpaint bench` use it; [`paint::measure_stroke_to_frame`]).
//! - [`canvas`]: the painting, brush, eraser, fill and exact undo/redo.
//! - [`watch`]: refit when another program rewrites a painting.
//! - [`camera`]: orbit camera and movable light.
//! - [`sample`]: painting → samples and material → shading (small, swappable).
//! - The window (winit + glutin + egui_glow): [`run`] with [`Options`].
//!
//! ```no_run
//! use brdfpaint::viewer::paint::{PaintSession, PaintView};
//! use brdfpaint::viewer::canvas::Brush;
//! use brdfpaint::factor::{Mapping, Settings};
//! use brdfpaint::gl::HeadlessContext;
//! use brdfpaint::render::Renderer;
//!
//! let ctx = HeadlessContext::new()?;
//! let mut renderer = Renderer::new(ctx.gl())?;
//! let mut session = PaintSession::new(Settings::default(), Mapping::Auto);
//! let k = session.add_view(PaintView::standard(&mut renderer, "sphere", "front-left", 256)?);
//! let all = session.views[k].object_pixels();
//! let base = Brush { color: [0.6, 0.25, 0.08], ..Brush::default() };
//! session.views[k].canvas.fill(base, &all);                            // a base colour
//! session.settle()?;                                                   // prepare once
//! let highlight = Brush { color: [1.0; 3], radius: 10.0, ..Brush::default() };
//! session.views[k].canvas.stroke(highlight, &[glam::Vec2::new(90.0, 80.0)]);
//! session.refit()?;                                                    // a fraction of a millisecond
//! let material = session.material().unwrap();
//! # Ok::<(), brdfpaint::Error>(())
//! ```

mod app;
pub mod camera;
pub mod canvas;
mod display;
pub mod paint;
pub mod sample;
mod studio;
pub mod watch;

pub use app::{run, Options, ScreenshotInfo};
pub use display::MIN_SCALE as MIN_RENDER_SCALE;
pub use studio::{example_painting, Mode, Start, Studio, Timings};
