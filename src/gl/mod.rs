//! The GL layer: headless contexts, RAII wrappers over GL objects, shader loading.
//!
//! Layers, bottom up: [`HeadlessContext`] (EGL, no window) or a window's context wrapped
//! with [`Gl::from_glow`]; the [`Gl`] function table every object holds a clone of; RAII
//! objects ([`Buffer`], [`VertexArray`], [`Texture2D`], [`Framebuffer`], [`Shader`],
//! [`Program`]) that delete themselves on drop; the renderer
//! ([`crate::render`]) above them.
//!
//! Errors are [`Error::Gl`](crate::Error::Gl) with a readable message, never a panic.
//!
//! ```no_run
//! use brdfpaint::gl::{Framebuffer, HeadlessContext};
//! let ctx = HeadlessContext::new()?; // llvmpipe unless told otherwise
//! let target = Framebuffer::new(ctx.gl(), 64, 64)?;
//! let pixels = target.read()?; // RGBA f32, row 0 at the top
//! assert_eq!(pixels.len(), 64 * 64);
//! # Ok::<(), brdfpaint::Error>(())
//! ```

mod context;
mod limits;
mod objects;
mod shader;

pub use context::{missing_gl_message, ApiPreference, DevicePreference, Gl, HeadlessContext, GL_PACKAGES};
pub use limits::{check_error, Limits};
pub use objects::{Buffer, Filter, Framebuffer, TexelFormat, Texture2D, VertexArray};
pub use shader::{header, Program, Shader, Stage};

#[cfg(test)]
mod tests {
    use super::*;
    use glow::HasContext;

    #[test]
    fn headless_context_renders_a_clear_colour_and_reads_it_back_top_down() {
        let ctx = HeadlessContext::new().unwrap();
        let gl = ctx.gl();
        let target = Framebuffer::new(gl, 5, 3).unwrap();
        target.bind();
        // SAFETY: plain state calls on the current context.
        unsafe {
            gl.clear_color(0.25, 0.5, 2.0, 1.0);
            gl.clear(glow::COLOR_BUFFER_BIT);
            // Paint the bottom GL row (image row 2) differently with a scissored clear.
            gl.enable(glow::SCISSOR_TEST);
            gl.scissor(0, 0, 5, 1);
            gl.clear_color(-1.0, 0.0, 0.0, 0.0);
            gl.clear(glow::COLOR_BUFFER_BIT);
            gl.disable(glow::SCISSOR_TEST);
        }
        let px = target.read().unwrap();
        assert_eq!(px[0], [0.25, 0.5, 2.0, 1.0], "float values above 1 survive");
        assert_eq!(px[2 * 5 + 4], [-1.0, 0.0, 0.0, 0.0], "GL's bottom row is the image's last row");
    }

    #[test]
    fn absurd_sizes_are_errors() {
        let ctx = HeadlessContext::new().unwrap();
        for (w, h) in [(0, 0), (0, 10), (100_000, 100_000), (1, 100_000)] {
            let e = Framebuffer::new(ctx.gl(), w, h).err().expect("must fail");
            assert!(matches!(e, crate::Error::Gl(_)), "{w}x{h}: {e}");
        }
        assert!(Texture2D::new(ctx.gl(), 0, 1, TexelFormat::Rgb32F, Filter::Linear, None).is_err());
        let e = Texture2D::new(ctx.gl(), 2, 1, TexelFormat::Rgb32F, Filter::Linear, Some(&[0.0; 5])).err().unwrap();
        assert!(e.to_string().contains("5 floats"), "{e}");
    }

    #[test]
    fn a_compile_error_is_an_error_with_the_log_and_the_line() {
        let ctx = HeadlessContext::new().unwrap();
        let src = format!("{}out vec4 o;\nvoid main() {{\n  o = vec4(undeclared_thing);\n}}\n", header(ctx.gl(), &[]));
        let e = Shader::compile(ctx.gl(), Stage::Fragment, "broken", &src).err().expect("must fail");
        let msg = e.to_string();
        assert!(msg.contains("fragment shader 'broken'"), "{msg}");
        assert!(msg.contains("undeclared_thing"), "the log or source names the culprit: {msg}");
        assert!(msg.contains("|   o = vec4(undeclared_thing);"), "the offending line is shown: {msg}");
    }
}
