//! Drawing the live 3D view into a rectangle of the window, and reading the window back.
//!
//! The model is drawn with the factored shader into a float target (linear values, alpha 1
//! on the object, 0 elsewhere), then copied 1:1 into the window with the sRGB transfer
//! function applied in the shader and the background under alpha. egui then draws its panels
//! around and over it. Doing the encoding ourselves keeps the window's pixels identical to
//! the PNGs the tool writes, whatever sRGB support the window's framebuffer has.

use glow::HasContext;

use crate::error::{Error, Result};
use crate::gl::{header, Framebuffer, Gl, Program, VertexArray};
use crate::images::tone::Tonemap;
use crate::render::{GpuScene, GpuShading, Lighting, Renderer};

const BLIT_VERT: &str = r#"
// A triangle covering the viewport; no vertex buffer.
void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"#;

const BLIT_FRAG: &str = r#"
uniform sampler2D u_image;   // linear RGBA, the view's pixels
uniform ivec2 u_origin;      // window pixel of the image's lower-left corner
uniform vec2 u_ratio;        // image texels per window pixel (1 at full resolution)
uniform vec3 u_background;   // sRGB-encoded
uniform float u_exposure;    // linear scale, 2^EV (1 without an environment)
uniform int u_tonemap;       // 0 clamp, 1 Khronos PBR Neutral, 2 ACES (Hill): images::tone
uniform int u_opaque;        // 1: the image covers the view (the environment behind the object)
layout(location = 0) out vec4 o_color;

// images::tone's operators, transcribed: the window shows what `render` writes to a PNG.
vec3 pbr_neutral(vec3 c) {
    const float start = 0.8 - 0.04;
    const float desaturation = 0.15;
    float x = min(c.r, min(c.g, c.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    c -= offset;
    float peak = max(c.r, max(c.g, c.b));
    if (peak < start) return c;
    float d = 1.0 - start;
    float new_peak = 1.0 - d * d / (peak + d - start);
    c *= new_peak / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(c, vec3(new_peak), g);
}

vec3 aces_hill(vec3 c) {
    vec3 v = vec3(dot(vec3(0.59719, 0.35458, 0.04823), c), dot(vec3(0.07600, 0.90834, 0.01566), c),
                  dot(vec3(0.02840, 0.13383, 0.83777), c));
    vec3 a = v * (v + 0.0245786) - 0.000090537;
    vec3 b = v * (0.983729 * v + 0.432951) + 0.238081;
    v = a / b;
    vec3 o = vec3(dot(vec3(1.60475, -0.53108, -0.07367), v), dot(vec3(-0.10208, 1.10813, -0.00605), v),
                  dot(vec3(-0.00327, -0.07276, 1.07602), v));
    return clamp(o, 0.0, 1.0);
}

vec3 develop(vec3 c) {
    c = max(c * u_exposure, vec3(0.0));
    if (u_tonemap == 1) return pbr_neutral(c);
    if (u_tonemap == 2) return aces_hill(c / 0.6);
    return min(c, vec3(1.0));
}

// The sRGB transfer function, linear to encoded (IEC 61966-2-1), after clamping to [0, 1].
vec3 encode(vec3 x) {
    x = clamp(x, 0.0, 1.0);
    vec3 lo = 12.92 * x;
    vec3 hi = 1.055 * pow(x, vec3(1.0 / 2.4)) - 0.055;
    return mix(hi, lo, vec3(lessThanEqual(x, vec3(0.0031308))));
}

void main() {
    vec4 c;
    if (u_ratio.x >= 1.0 && u_ratio.y >= 1.0) {
        // 1:1 copy: window pixel -> image texel, no filtering.
        c = texelFetch(u_image, ivec2(gl_FragCoord.xy) - u_origin, 0);
    } else {
        // A reduced render scale: bilinear between the four nearest texels, by hand (float
        // textures need not be filterable).
        vec2 p = (gl_FragCoord.xy - vec2(u_origin)) * u_ratio - 0.5;
        ivec2 top = textureSize(u_image, 0) - 1;
        ivec2 i0 = clamp(ivec2(floor(p)), ivec2(0), top);
        ivec2 i1 = clamp(i0 + 1, ivec2(0), top);
        vec2 f = clamp(p - floor(p), 0.0, 1.0);
        vec4 lo = mix(texelFetch(u_image, i0, 0), texelFetch(u_image, ivec2(i1.x, i0.y), 0), f.x);
        vec4 hi = mix(texelFetch(u_image, ivec2(i0.x, i1.y), 0), texelFetch(u_image, i1, 0), f.x);
        c = mix(lo, hi, f.y);
    }
    vec3 shown = encode(develop(c.rgb));
    o_color = vec4(u_opaque == 1 ? shown : mix(u_background, shown, clamp(c.a, 0.0, 1.0)), 1.0);
}
"#;

/// The smallest render scale of the 3D view.
pub const MIN_SCALE: f32 = 0.25;

/// A window rectangle in physical pixels, top-left origin.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct WindowRect {
    pub x: i32,
    pub y: i32,
    pub width: i32,
    pub height: i32,
}

/// How the view's linear pixels become the window's: the exposure and tone mapping `render`
/// develops its PNGs with (`images::tone`), and whether the image covers the whole view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Develop {
    /// Linear scale, $2^{EV}$.
    pub scale: f32,
    pub tonemap: Tonemap,
    /// The environment is drawn behind the object: no viewer background under alpha 0.
    pub opaque: bool,
}

impl Default for Develop {
    /// The view as it always was: the material's values, clamped, on the viewer's background.
    fn default() -> Develop {
        Develop { scale: 1.0, tonemap: Tonemap::None, opaque: false }
    }
}

/// What the 3D view draws: the model, its material (none: only the background) and, under
/// an environment, how it is lit.
pub struct Subject<'a> {
    pub scene: &'a GpuScene,
    pub shading: Option<&'a GpuShading>,
    pub lighting: Option<Lighting<'a>>,
}

/// The 3D view: its float target and the copy program.
pub struct View3d {
    gl: Gl,
    target: Option<Framebuffer>,
    blit: Program,
    vao: VertexArray,
    /// sRGB-encoded background, 0..1.
    pub background: [f32; 3],
    /// How the next draw develops its pixels (set per frame, as the environment changes).
    pub develop: Develop,
}

impl View3d {
    pub fn new(gl: &Gl) -> Result<View3d> {
        let head = header(gl, &[]);
        let blit = Program::new(gl, "view blit", &format!("{head}{BLIT_VERT}"), &format!("{head}{BLIT_FRAG}"))?;
        Ok(View3d { gl: gl.clone(), target: None, blit, vao: VertexArray::new(gl)?, background: [0.16, 0.17, 0.19], develop: Develop::default() })
    }

    /// Draws the subject's scene with its shading into `rect` of a window `window_height`
    /// pixels tall (the default framebuffer, which is left bound), under its lighting when
    /// there is one (the renderer's environment pass) and developed by [`View3d::develop`]. Without a shading, only the
    /// background.
    /// `scale` (clamped to [`MIN_SCALE`]..=1) renders the model at that fraction of the
    /// rectangle's resolution and magnifies it: on a software rasterizer the 3D pass costs in
    /// proportion to its pixels.
    pub fn draw(
        &mut self,
        renderer: &mut Renderer,
        subject: &Subject,
        rect: WindowRect,
        window_height: i32,
        scale: f32,
    ) -> Result<()> {
        if rect.width <= 0 || rect.height <= 0 {
            return Ok(());
        }
        let scale = if scale.is_finite() { scale.clamp(MIN_SCALE, 1.0) } else { 1.0 };
        let reduced = |n: i32| ((n as f32 * scale).round() as usize).max(1);
        let (w, h) = (reduced(rect.width), reduced(rect.height));
        let target = Framebuffer::sized(&mut self.target, &self.gl, w, h)?;
        target.begin_pass();
        let gl = &self.gl;
        let (scene, shading) = (subject.scene, subject.shading);
        match (shading, subject.lighting.as_ref()) {
            (Some(shading), Some(lighting)) => renderer.draw_lit(scene, shading, lighting, w, h)?,
            (Some(shading), None) => renderer.draw_factored(scene, shading, w, h)?,
            (None, _) => {}
        }
        // Copy into the window: GL's window origin is the lower-left corner.
        let origin_y = window_height - (rect.y + rect.height);
        // SAFETY: state changes on the current context; the default framebuffer is 0.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            gl.viewport(rect.x, origin_y, rect.width, rect.height);
            gl.disable(glow::DEPTH_TEST);
            gl.disable(glow::BLEND);
        }
        self.blit.bind();
        target.color().bind(0);
        self.blit.set_i32("u_image", 0);
        if let Some(loc) = self.blit.location("u_origin") {
            // SAFETY: the program is bound.
            unsafe { gl.uniform_2_i32(Some(&loc), rect.x, origin_y) };
        }
        if let Some(loc) = self.blit.location("u_ratio") {
            // SAFETY: the program is bound.
            unsafe { gl.uniform_2_f32(Some(&loc), w as f32 / rect.width as f32, h as f32 / rect.height as f32) };
        }
        self.blit.set_vec3("u_background", glam::Vec3::from_array(self.background));
        let develop = self.develop;
        self.blit.set_f32("u_exposure", develop.scale);
        let tonemap = match develop.tonemap {
            Tonemap::None => 0,
            Tonemap::Neutral => 1,
            Tonemap::Aces => 2,
        };
        self.blit.set_i32("u_tonemap", tonemap);
        // Without a material nothing is drawn under the environment either: keep the background.
        self.blit.set_i32("u_opaque", (develop.opaque && shading.is_some()) as i32);
        self.vao.bind();
        // SAFETY: a bound program and vertex array; three vertices from gl_VertexID.
        unsafe { gl.draw_arrays(glow::TRIANGLES, 0, 3) };
        crate::gl::check_error(gl, "3D view")
    }
}

/// The default framebuffer's pixels, `width` × `height`, RGB 8-bit, row 0 at the top.
pub fn read_window(gl: &Gl, width: u32, height: u32) -> Result<image::RgbImage> {
    let (w, h) = (width as usize, height as usize);
    let mut raw = vec![0u8; w * h * 4];
    // SAFETY: the buffer holds w·h RGBA bytes; PACK_ALIGNMENT 4 divides the row size.
    unsafe {
        gl.bind_framebuffer(glow::FRAMEBUFFER, None);
        gl.pixel_store_i32(glow::PACK_ALIGNMENT, 4);
        gl.read_pixels(
            0,
            0,
            width as i32,
            height as i32,
            glow::RGBA,
            glow::UNSIGNED_BYTE,
            glow::PixelPackData::Slice(Some(&mut raw)),
        );
    }
    crate::gl::check_error(gl, "window read-back")?;
    let mut rgb = Vec::with_capacity(w * h * 3);
    // glReadPixels rows come bottom-up.
    for row in raw.chunks_exact(w * 4).rev() {
        for px in row.chunks_exact(4) {
            rgb.extend_from_slice(&px[..3]);
        }
    }
    image::RgbImage::from_raw(width, height, rgb).ok_or_else(|| Error::Gl("window read-back size".into()))
}
