//! Live painting without a window: painted views, the canvas, and the refit a stroke
//! triggers. The viewer's UI (`viewer`, behind the window stack) calls exactly this; tests
//! and `brdfpaint bench` script it. It needs a GL context for rendering the views' guides
//! (the headless one will do) and nothing of winit or egui.
//!
//! - [`view`]: a view to paint (scene, guides, the pixels that can be samples) and the size
//!   rule a painting of it follows.
//! - [`canvas`]: the painting, brush, eraser, fill and exact undo/redo.
//! - [`session`]: the prepared system and the refit a stroke triggers; several views feed
//!   one fit.
//! - [`full`]: once the strokes pause, `brdfpaint fit`'s own fit of the paintings (reading,
//!   base, notes) on a worker thread, shown while the paintings are the ones it read.
//! - [`watch`]: refit when another program rewrites a painting.
//! - [`sphere`]: a lit sphere or MatCap as a view, with a light the user moves.
//! - [`slots`]: the pixels of a view that are samples.
//! - [`example_painting`]: the bundled painting a first run fits.
//!
//! ```no_run
//! use brdfpaint::live::{Brush, PaintSession, PaintView};
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

pub mod canvas;
mod example;
pub mod full;
pub mod session;
pub mod slots;
pub mod sphere;
pub mod view;
pub mod watch;

pub use canvas::{blank, Brush, Canvas, CanvasRect, Painting};
pub use example::example_painting;
pub use full::{FullFit, Stamp};
pub use session::{fit_views, PaintSession, Refit};
pub use slots::Slot;
pub use sphere::SphereSession;
pub use view::{check_painting_size, read_painting_for, PaintView, DEFAULT_SIZE};
pub use watch::{WatchStatus, Watcher};
