//! The real-time viewer (`brdfpaint view`): the window, the UI and the camera. Everything
//! winit, glutin-winit and egui lives here; the live-painting core it drives is
//! [`crate::live`], which has no window.
//!
//! - [`camera`]: orbit camera and movable light.
//! - [`render_scale`]: the 3D view's render scale, picked from frame times.
//! - The window (winit + glutin + egui_glow): [`run`] with [`Options`]; the state and the
//!   panel: [`Studio`].

mod app;
pub mod camera;
mod display;
pub mod render_scale;
mod studio;

pub use app::{run, Options, ScreenshotInfo};
pub use display::{WindowRect, MIN_SCALE as MIN_RENDER_SCALE};
pub use studio::shortcuts::{take_shortcuts, Shortcut};
pub use studio::{Env, EnvStart, Layout, Mode, Stage, Start, Studio, Timings, Tool, PANEL_WIDTH};

