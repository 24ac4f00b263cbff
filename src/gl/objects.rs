//! RAII wrappers over GL objects. Each holds a clone of the [`Gl`] function table (so the
//! context outlives it) and deletes its object on drop.
//!
//! All constructors return [`Error::Gl`] instead of panicking: allocation failures
//! (`GL_OUT_OF_MEMORY`), incomplete framebuffers and sizes beyond the implementation's limits
//! are checked where they can happen.

use glow::HasContext;

use super::context::Gl;
use super::limits::{check_error, Limits};
use crate::error::{Error, Result};

/// Bytes of a slice of plain floats or integers, for upload.
fn bytes_of<T: Copy>(data: &[T]) -> &[u8] {
    // SAFETY: only instantiated with f32, u32 and arrays of them (no padding, any bit
    // pattern valid as bytes); the length covers exactly the slice.
    unsafe { std::slice::from_raw_parts(data.as_ptr().cast::<u8>(), std::mem::size_of_val(data)) }
}

/// A buffer object: vertex attributes (`ARRAY_BUFFER`) or indices (`ELEMENT_ARRAY_BUFFER`).
pub struct Buffer {
    gl: Gl,
    raw: glow::Buffer,
    target: u32,
    len: usize,
}

impl Buffer {
    /// A static vertex buffer of floats.
    pub fn vertices(gl: &Gl, data: &[f32]) -> Result<Buffer> {
        Buffer::new(gl, glow::ARRAY_BUFFER, bytes_of(data), data.len())
    }

    /// A static index buffer of `u32` indices. Bind a [`VertexArray`] first: the element
    /// buffer binding is part of its state.
    pub fn indices(gl: &Gl, data: &[u32]) -> Result<Buffer> {
        Buffer::new(gl, glow::ELEMENT_ARRAY_BUFFER, bytes_of(data), data.len())
    }

    fn new(gl: &Gl, target: u32, bytes: &[u8], len: usize) -> Result<Buffer> {
        // SAFETY: a current context; the data slice is valid for the call.
        unsafe {
            let raw = gl.create_buffer().map_err(|e| Error::Gl(format!("cannot create a buffer: {e}")))?;
            let buffer = Buffer { gl: gl.clone(), raw, target, len };
            gl.bind_buffer(target, Some(raw));
            gl.buffer_data_u8_slice(target, bytes, glow::STATIC_DRAW);
            check_error(gl, "buffer upload")?;
            Ok(buffer)
        }
    }

    /// Binds it to its target.
    pub fn bind(&self) {
        // SAFETY: a live buffer of this context.
        unsafe { self.gl.bind_buffer(self.target, Some(self.raw)) }
    }

    /// Number of elements (floats or indices) it holds.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether it holds nothing.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The GL name.
    pub fn raw(&self) -> glow::Buffer {
        self.raw
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        self.gl.ensure_current();
        // SAFETY: the buffer belongs to this context and is deleted once.
        unsafe { self.gl.delete_buffer(self.raw) }
    }
}

/// A vertex array object: attribute bindings and the element buffer.
pub struct VertexArray {
    gl: Gl,
    raw: glow::VertexArray,
}

impl VertexArray {
    /// An empty vertex array.
    pub fn new(gl: &Gl) -> Result<VertexArray> {
        // SAFETY: a current context.
        let raw =
            unsafe { gl.create_vertex_array() }.map_err(|e| Error::Gl(format!("cannot create a vertex array: {e}")))?;
        Ok(VertexArray { gl: gl.clone(), raw })
    }

    /// Binds it (GL state: `VERTEX_ARRAY_BINDING`).
    pub fn bind(&self) {
        // SAFETY: a live vertex array of this context.
        unsafe { self.gl.bind_vertex_array(Some(self.raw)) }
    }

    /// Points attribute `location` at `components` floats per vertex of `buffer` (tightly
    /// packed). Binds this vertex array and the buffer.
    pub fn attribute(&self, location: u32, buffer: &Buffer, components: i32) {
        self.bind();
        buffer.bind();
        // SAFETY: the buffer holds floats; offset 0 and stride 0 (tightly packed).
        unsafe {
            self.gl.enable_vertex_attrib_array(location);
            self.gl.vertex_attrib_pointer_f32(location, components, glow::FLOAT, false, 0, 0);
        }
    }

    /// Attribute `location` reads the constant `value` for every vertex (no array).
    pub fn constant(&self, location: u32, value: [f32; 4]) {
        self.bind();
        // SAFETY: the current attribute value is context state, set while this VAO is bound.
        unsafe {
            self.gl.disable_vertex_attrib_array(location);
            self.gl.vertex_attrib_4_f32(location, value[0], value[1], value[2], value[3]);
        }
    }

    /// The GL name.
    pub fn raw(&self) -> glow::VertexArray {
        self.raw
    }
}

impl Drop for VertexArray {
    fn drop(&mut self) {
        self.gl.ensure_current();
        // SAFETY: the vertex array belongs to this context and is deleted once.
        unsafe { self.gl.delete_vertex_array(self.raw) }
    }
}

/// Texel format of a float texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexelFormat {
    /// Three 32-bit floats per texel (factor tables, coefficients).
    Rgb32F,
    /// Four 32-bit floats per texel (render targets).
    Rgba32F,
}

impl TexelFormat {
    /// Floats per texel.
    pub fn channels(self) -> usize {
        match self {
            TexelFormat::Rgb32F => 3,
            TexelFormat::Rgba32F => 4,
        }
    }

    fn gl(self) -> (i32, u32) {
        match self {
            TexelFormat::Rgb32F => (glow::RGB32F as i32, glow::RGB),
            TexelFormat::Rgba32F => (glow::RGBA32F as i32, glow::RGBA),
        }
    }
}

/// How a texture is filtered when sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Bilinear (`GL_LINEAR`, no mipmaps): what factor tables need.
    Linear,
    /// Nearest texel.
    Nearest,
}

/// A 2D float texture, clamped to its edges, without mipmaps.
pub struct Texture2D {
    gl: Gl,
    raw: glow::Texture,
    width: usize,
    height: usize,
    format: TexelFormat,
}

impl Texture2D {
    /// A `width` × `height` texture. `data` holds `width·height·channels` floats, row by row
    /// with row 0 at texture coordinate $t = 0$, or is `None` for uninitialized storage.
    pub fn new(
        gl: &Gl,
        width: usize,
        height: usize,
        format: TexelFormat,
        filter: Filter,
        data: Option<&[f32]>,
    ) -> Result<Texture2D> {
        let limits = Limits::query(gl);
        limits.check_texture(width, height)?;
        if let Some(d) = data {
            let want = width * height * format.channels();
            if d.len() != want {
                return Err(Error::Gl(format!(
                    "texture data has {} floats, but {width}x{height} {format:?} needs {want}",
                    d.len()
                )));
            }
            if let Some(bad) = d.iter().position(|x| !x.is_finite()) {
                return Err(Error::input(format!("texture value {} at index {bad} is not finite", d[bad])));
            }
        }
        if filter == Filter::Linear && !limits.float_linear {
            return Err(Error::Gl("this GL cannot filter float textures (OES_texture_float_linear missing)".into()));
        }
        let (internal, pixel_format) = format.gl();
        let gl_filter = match filter {
            Filter::Linear => glow::LINEAR,
            Filter::Nearest => glow::NEAREST,
        } as i32;
        // SAFETY: a current context; sizes checked above; data length checked above.
        unsafe {
            let raw = gl.create_texture().map_err(|e| Error::Gl(format!("cannot create a texture: {e}")))?;
            let texture = Texture2D { gl: gl.clone(), raw, width, height, format };
            gl.bind_texture(glow::TEXTURE_2D, Some(raw));
            // Rows of RGB floats are 12·width bytes: always a multiple of 4, the default
            // alignment, but set it so no earlier state can break the upload.
            gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 4);
            gl.tex_image_2d(
                glow::TEXTURE_2D,
                0,
                internal,
                width as i32,
                height as i32,
                0,
                pixel_format,
                glow::FLOAT,
                glow::PixelUnpackData::Slice(data.map(bytes_of)),
            );
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, gl_filter);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, gl_filter);
            // Lookups outside [0,1] read the edge texel: table coordinates are clamped, and
            // the half-texel margin of node-based tables stays inside the texture anyway.
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_S, glow::CLAMP_TO_EDGE as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_T, glow::CLAMP_TO_EDGE as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAX_LEVEL, 0);
            check_error(gl, "texture upload")?;
            Ok(texture)
        }
    }

    /// An equirectangular panorama: RGBA32F from `rgba` (row 0 at $t = 0$), with a full mip
    /// chain made by `glGenerateMipmap` (2×2 box filter per level) and trilinear filtering,
    /// `REPEAT` in $s$ (filtering wraps across the $u = 0$ seam, so no column shows it) and
    /// `CLAMP_TO_EDGE` in $t$ (the poles).
    pub fn panorama(gl: &Gl, width: usize, height: usize, rgba: &[f32]) -> Result<Texture2D> {
        let texture = Texture2D::new(gl, width, height, TexelFormat::Rgba32F, Filter::Linear, Some(rgba))?;
        // SAFETY: a live texture of this context, bound by `new`.
        unsafe {
            gl.bind_texture(glow::TEXTURE_2D, Some(texture.raw));
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAX_LEVEL, 1000);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, glow::LINEAR_MIPMAP_LINEAR as i32);
            gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_WRAP_S, glow::REPEAT as i32);
            gl.generate_mipmap(glow::TEXTURE_2D);
            check_error(gl, "panorama mipmaps")?;
        }
        Ok(texture)
    }

    /// Binds it to texture unit `unit` (GL state: the active texture unit changes).
    pub fn bind(&self, unit: u32) {
        // SAFETY: a live texture of this context.
        unsafe {
            self.gl.active_texture(glow::TEXTURE0 + unit);
            self.gl.bind_texture(glow::TEXTURE_2D, Some(self.raw));
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    pub fn format(&self) -> TexelFormat {
        self.format
    }

    /// The GL name.
    pub fn raw(&self) -> glow::Texture {
        self.raw
    }
}

impl Drop for Texture2D {
    fn drop(&mut self) {
        self.gl.ensure_current();
        // SAFETY: the texture belongs to this context and is deleted once.
        unsafe { self.gl.delete_texture(self.raw) }
    }
}

/// An offscreen render target: an RGBA32F colour texture and a 32-bit float depth buffer.
pub struct Framebuffer {
    gl: Gl,
    raw: glow::Framebuffer,
    color: Texture2D,
    depth: glow::Renderbuffer,
}

impl Framebuffer {
    /// A `width` × `height` target. Sizes of zero, or beyond the implementation's texture,
    /// renderbuffer or viewport limits, or beyond [`Limits::MAX_PIXELS`], are an error.
    pub fn new(gl: &Gl, width: usize, height: usize) -> Result<Framebuffer> {
        let limits = Limits::query(gl);
        limits.check_target(width, height)?;
        if !limits.float_render {
            return Err(Error::Gl("this GL cannot render to float textures (EXT_color_buffer_float missing)".into()));
        }
        let color = Texture2D::new(gl, width, height, TexelFormat::Rgba32F, Filter::Nearest, None)?;
        // SAFETY: a current context; sizes checked above.
        unsafe {
            let raw = gl.create_framebuffer().map_err(|e| Error::Gl(format!("cannot create a framebuffer: {e}")))?;
            let depth = match gl.create_renderbuffer() {
                Ok(d) => d,
                Err(e) => {
                    gl.delete_framebuffer(raw);
                    return Err(Error::Gl(format!("cannot create a renderbuffer: {e}")));
                }
            };
            let fb = Framebuffer { gl: gl.clone(), raw, color, depth };
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth));
            gl.renderbuffer_storage(glow::RENDERBUFFER, glow::DEPTH_COMPONENT32F, width as i32, height as i32);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(raw));
            gl.framebuffer_texture_2d(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::TEXTURE_2D,
                Some(fb.color.raw()),
                0,
            );
            gl.framebuffer_renderbuffer(glow::FRAMEBUFFER, glow::DEPTH_ATTACHMENT, glow::RENDERBUFFER, Some(depth));
            check_error(gl, "framebuffer setup")?;
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(Error::Gl(format!(
                    "a {width}x{height} RGBA32F framebuffer is incomplete (status 0x{status:x})"
                )));
            }
            Ok(fb)
        }
    }

    /// Binds it for drawing and reading, with the viewport covering it (GL state:
    /// `FRAMEBUFFER` binding and viewport).
    pub fn bind(&self) {
        // SAFETY: a live framebuffer of this context.
        unsafe {
            self.gl.bind_framebuffer(glow::FRAMEBUFFER, Some(self.raw));
            self.gl.viewport(0, 0, self.width() as i32, self.height() as i32);
        }
    }

    /// The target kept in `slot`, made (or remade) when there is none of this size.
    pub fn sized<'a>(slot: &'a mut Option<Framebuffer>, gl: &Gl, width: usize, height: usize) -> Result<&'a Framebuffer> {
        if slot.as_ref().is_none_or(|t| t.width() != width || t.height() != height) {
            // The old target is freed before the new one is made.
            *slot = None;
            *slot = Some(Framebuffer::new(gl, width, height)?);
        }
        Ok(slot.as_ref().expect("made above"))
    }

    /// Binds it for an opaque, depth-tested pass: no scissor, blending or culling (meshes are
    /// drawn two-sided), all colour channels written, colour cleared to (0, 0, 0, 0) and
    /// depth to 1, depth test `LESS`. The scissor and colour mask are set before the clear,
    /// which they would otherwise clip (egui leaves a scissor behind).
    pub fn begin_pass(&self) {
        self.begin_pass_scissored(None);
    }

    fn begin_pass_scissored(&self, band: Option<std::ops::Range<usize>>) {
        self.bind();
        let gl = &self.gl;
        // SAFETY: state changes on the current context.
        unsafe {
            match band {
                Some(rows) => {
                    // GL counts rows from the bottom.
                    let (h, rows) = (self.height(), rows.start.min(self.height())..rows.end.min(self.height()));
                    gl.enable(glow::SCISSOR_TEST);
                    gl.scissor(0, (h - rows.end) as i32, self.width() as i32, rows.len() as i32);
                }
                None => gl.disable(glow::SCISSOR_TEST),
            }
            gl.disable(glow::BLEND);
            gl.disable(glow::CULL_FACE);
            gl.color_mask(true, true, true, true);
            gl.clear_color(0.0, 0.0, 0.0, 0.0);
            gl.clear_depth_f32(1.0);
            gl.depth_mask(true);
            gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
            gl.enable(glow::DEPTH_TEST);
            gl.depth_func(glow::LESS);
        }
    }

    /// Like [`Framebuffer::begin_pass`], but only rows `rows` (counted from the **top**, as
    /// images are) are cleared and drawn: the scissor test is left on for the pass. A pixel
    /// inside the band gets exactly the value a full pass gives it (same viewport, same
    /// rasterization; the scissor only discards fragments), so an image can be drawn and
    /// read back band by band with the memory of one band ([`Framebuffer::read_rows`]).
    /// The scissor stays on after the pass: whoever bands turns it off when done
    /// (`begin_pass` does too).
    pub fn begin_band(&self, rows: std::ops::Range<usize>) {
        self.begin_pass_scissored(Some(rows));
    }

    pub fn width(&self) -> usize {
        self.color.width()
    }

    pub fn height(&self) -> usize {
        self.color.height()
    }

    /// The colour texture.
    pub fn color(&self) -> &Texture2D {
        &self.color
    }

    /// Reads the colour buffer back as RGBA floats, row 0 at the **top** (glReadPixels
    /// returns rows bottom-up; they are flipped here).
    pub fn read(&self) -> Result<Vec<[f32; 4]>> {
        self.read_rows(0..self.height())
    }

    /// Reads rows `rows` of the colour buffer (counted from the top; clipped to the
    /// target) as RGBA floats, top row first. Rows are flipped in place: no second copy of
    /// the pixels is made.
    pub fn read_rows(&self, rows: std::ops::Range<usize>) -> Result<Vec<[f32; 4]>> {
        let (w, h) = (self.width(), self.height());
        let rows = rows.start.min(h)..rows.end.min(h);
        let n = rows.len();
        let mut out = vec![[0.0f32; 4]; w * n];
        self.bind();
        // SAFETY: the buffer holds exactly w·n RGBA float texels; PACK_ALIGNMENT 4 divides
        // the 16-byte texel; the rectangle lies inside the target.
        unsafe {
            self.gl.pixel_store_i32(glow::PACK_ALIGNMENT, 4);
            let bytes = std::slice::from_raw_parts_mut(out.as_mut_ptr().cast::<u8>(), w * n * 16);
            self.gl.read_pixels(
                0,
                (h - rows.end) as i32,
                w as i32,
                n as i32,
                glow::RGBA,
                glow::FLOAT,
                glow::PixelPackData::Slice(Some(bytes)),
            );
        }
        check_error(&self.gl, "read back")?;
        // Flip: GL row 0 is the bottom of the image.
        for j in 0..n / 2 {
            let (top, bottom) = out.split_at_mut((n - 1 - j) * w);
            top[j * w..(j + 1) * w].swap_with_slice(&mut bottom[..w]);
        }
        Ok(out)
    }
}

impl Drop for Framebuffer {
    fn drop(&mut self) {
        self.gl.ensure_current();
        // SAFETY: both objects belong to this context and are deleted once; the colour
        // texture deletes itself afterwards.
        unsafe {
            self.gl.delete_framebuffer(self.raw);
            self.gl.delete_renderbuffer(self.depth);
        }
    }
}
