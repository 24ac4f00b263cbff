//! Implementation limits and capabilities, and GL error checks.

use glow::HasContext;

use super::context::Gl;
use crate::error::{Error, Result};

/// What the current GL can do, as far as this crate cares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    pub max_texture_size: usize,
    pub max_renderbuffer_size: usize,
    pub max_viewport: [usize; 2],
    /// Texture units a fragment shader can use (`MAX_TEXTURE_IMAGE_UNITS`, at least 16).
    pub max_texture_units: usize,
    /// Float textures can be linearly filtered (always on desktop GL 3.3; GLES needs
    /// `OES_texture_float_linear`).
    pub float_linear: bool,
    /// RGBA32F is colour-renderable (desktop GL; GLES needs `EXT_color_buffer_float`).
    pub float_render: bool,
    /// RGBA32F targets can be blended (desktop GL; GLES needs `EXT_float_blend`).
    pub float_blend: bool,
}

impl Limits {
    /// Largest image this crate renders, in pixels: 2^24 (e.g. 4096 × 4096). A G-buffer of
    /// that size already takes over a gigabyte on the host.
    pub const MAX_PIXELS: usize = 1 << 24;

    /// Queries the current context.
    pub fn query(gl: &Gl) -> Limits {
        // SAFETY: plain queries on a current context.
        unsafe {
            let int = |p| gl.get_parameter_i32(p).max(0) as usize;
            let mut viewport = [0i32; 2];
            gl.get_parameter_i32_slice(glow::MAX_VIEWPORT_DIMS, &mut viewport);
            let ext = gl.supported_extensions();
            let has = |name: &str| ext.contains(name) || ext.contains(&format!("GL_{name}"));
            let gles = gl.is_gles();
            Limits {
                max_texture_size: int(glow::MAX_TEXTURE_SIZE),
                max_renderbuffer_size: int(glow::MAX_RENDERBUFFER_SIZE),
                max_viewport: [viewport[0].max(0) as usize, viewport[1].max(0) as usize],
                max_texture_units: int(glow::MAX_TEXTURE_IMAGE_UNITS),
                float_linear: !gles || has("OES_texture_float_linear"),
                float_render: !gles || has("EXT_color_buffer_float"),
                float_blend: !gles || has("EXT_float_blend"),
            }
        }
    }

    /// A texture of `width` × `height` is possible.
    pub fn check_texture(&self, width: usize, height: usize) -> Result<()> {
        if width == 0 || height == 0 || width > self.max_texture_size || height > self.max_texture_size {
            return Err(Error::Gl(format!(
                "a {width}x{height} texture is outside this GL's limits (1 to {} per side)",
                self.max_texture_size
            )));
        }
        Ok(())
    }

    /// A render target of `width` × `height` is possible.
    pub fn check_target(&self, width: usize, height: usize) -> Result<()> {
        let side = self.max_texture_size.min(self.max_renderbuffer_size);
        let (mw, mh) = (side.min(self.max_viewport[0]), side.min(self.max_viewport[1]));
        if width == 0 || height == 0 || width > mw || height > mh {
            return Err(Error::Gl(format!(
                "an image of {width}x{height} pixels is outside this GL's limits (1x1 to {mw}x{mh})"
            )));
        }
        if width * height > Self::MAX_PIXELS {
            return Err(Error::Gl(format!(
                "an image of {width}x{height} pixels is more than the {} pixels this renderer accepts",
                Self::MAX_PIXELS
            )));
        }
        Ok(())
    }
}

// Image files are refused from their header above the renderer's size (crate::images).
const _: () = assert!(Limits::MAX_PIXELS == crate::images::MAX_PIXELS);

/// Drains `glGetError`; any error becomes [`Error::Gl`] naming `what` was being done.
pub fn check_error(gl: &Gl, what: &str) -> Result<()> {
    let mut errors = Vec::new();
    // SAFETY: plain query on a current context. The loop is bounded: each call clears one
    // flag, and there are few flags.
    unsafe {
        for _ in 0..16 {
            match gl.get_error() {
                glow::NO_ERROR => break,
                e => errors.push(error_name(e)),
            }
        }
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(Error::Gl(format!("{what} failed: {}", errors.join(", "))))
    }
}

fn error_name(e: u32) -> String {
    match e {
        glow::INVALID_ENUM => "GL_INVALID_ENUM".into(),
        glow::INVALID_VALUE => "GL_INVALID_VALUE".into(),
        glow::INVALID_OPERATION => "GL_INVALID_OPERATION".into(),
        glow::INVALID_FRAMEBUFFER_OPERATION => "GL_INVALID_FRAMEBUFFER_OPERATION".into(),
        glow::OUT_OF_MEMORY => "GL_OUT_OF_MEMORY".into(),
        other => format!("GL error 0x{other:x}"),
    }
}

/// In debug builds, returns early with [`Error::Gl`] if GL reported an error since the last
/// check; in release builds it costs nothing. Put one after each stage of GL work.
#[macro_export]
macro_rules! gl_check {
    ($gl:expr, $what:expr) => {
        if cfg!(debug_assertions) {
            $crate::gl::check_error(&$gl, $what)?;
        }
    };
}
