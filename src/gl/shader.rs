//! Shaders and programs. One GLSL code path serves GL 3.3 core and GLES 3.0: the `.glsl`
//! files in `shaders/` have no `#version` line; [`header`] prepends it, with the precision
//! statements GLES needs and any feature `#define`s.

use std::cell::RefCell;
use std::collections::HashMap;

use glam::{Mat4, Vec2, Vec3, Vec4};
use glow::HasContext;

use super::context::Gl;
use crate::error::{Error, Result};

/// A shader stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    Vertex,
    Fragment,
}

impl Stage {
    fn gl(self) -> u32 {
        match self {
            Stage::Vertex => glow::VERTEX_SHADER,
            Stage::Fragment => glow::FRAGMENT_SHADER,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Stage::Vertex => "vertex",
            Stage::Fragment => "fragment",
        }
    }
}

/// The text every shader starts with: the `#version` line (`330 core` or `300 es`), highp
/// precision on GLES, `#define GLES 1` there, then `defines` as `#define NAME VALUE` lines.
pub fn header(gl: &Gl, defines: &[(&str, String)]) -> String {
    let mut s = if gl.is_gles() {
        // highp everywhere: factor coordinates need float32 to match the CPU tables.
        String::from(
            "#version 300 es\n#define GLES 1\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n",
        )
    } else {
        String::from("#version 330 core\n")
    };
    for (name, value) in defines {
        s.push_str(&format!("#define {name} {value}\n"));
    }
    s
}

/// A compiled shader stage.
pub struct Shader {
    gl: Gl,
    raw: glow::Shader,
    stage: Stage,
}

impl Shader {
    /// Compiles `source` (already with its [`header`]). A compile error becomes
    /// [`Error::Gl`] with the stage, the `name`, the driver's log and the numbered source
    /// lines the log points at (or the whole source when it points nowhere recognizable).
    pub fn compile(gl: &Gl, stage: Stage, name: &str, source: &str) -> Result<Shader> {
        // SAFETY: a current context; the source string is valid for the call.
        unsafe {
            let raw = gl
                .create_shader(stage.gl())
                .map_err(|e| Error::Gl(format!("cannot create a {} shader: {e}", stage.name())))?;
            let shader = Shader { gl: gl.clone(), raw, stage };
            gl.shader_source(raw, source);
            gl.compile_shader(raw);
            if !gl.get_shader_compile_status(raw) {
                let log = gl.get_shader_info_log(raw);
                return Err(Error::Gl(format!(
                    "{} shader '{name}' does not compile:\n{}\n{}",
                    stage.name(),
                    log.trim_end(),
                    excerpt(source, &log)
                )));
            }
            Ok(shader)
        }
    }

    pub fn stage(&self) -> Stage {
        self.stage
    }
}

impl Drop for Shader {
    fn drop(&mut self) {
        self.gl.ensure_current();
        // SAFETY: the shader belongs to this context and is deleted once.
        unsafe { self.gl.delete_shader(self.raw) }
    }
}

/// Line numbers a driver log mentions: Mesa writes `0:12(5): error`, others `ERROR: 0:12:`
/// or `0(12) :`.
fn log_lines(log: &str) -> Vec<usize> {
    let mut out = Vec::new();
    for line in log.lines() {
        // Find "0:" or "0(" followed by digits.
        let b = line.as_bytes();
        for i in 0..b.len().saturating_sub(2) {
            if b[i] == b'0' && (b[i + 1] == b':' || b[i + 1] == b'(') && (i == 0 || !b[i - 1].is_ascii_digit()) {
                let digits: String = line[i + 2..].chars().take_while(|c| c.is_ascii_digit()).collect();
                if let Ok(n) = digits.parse::<usize>() {
                    out.push(n);
                    break;
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The numbered source lines around those the log names (two lines of context), or the
/// whole numbered source.
fn excerpt(source: &str, log: &str) -> String {
    let lines: Vec<&str> = source.lines().collect();
    let wanted = log_lines(log);
    let show = |k: usize| wanted.is_empty() || wanted.iter().any(|&n| k + 2 >= n && k <= n + 2);
    let mut out = String::from("source:\n");
    let mut skipped = false;
    for (i, text) in lines.iter().enumerate() {
        let k = i + 1;
        if show(k) {
            if skipped {
                out.push_str("   ...\n");
            }
            out.push_str(&format!("{k:4} | {text}\n"));
            skipped = false;
        } else {
            skipped = true;
        }
    }
    out.trim_end().to_string()
}

/// A linked program with a cache of uniform locations.
pub struct Program {
    gl: Gl,
    raw: glow::Program,
    name: String,
    uniforms: RefCell<HashMap<String, Option<glow::UniformLocation>>>,
}

impl Program {
    /// Compiles both stages (each source already with its [`header`]) and links them.
    pub fn new(gl: &Gl, name: &str, vertex: &str, fragment: &str) -> Result<Program> {
        let vs = Shader::compile(gl, Stage::Vertex, name, vertex)?;
        let fs = Shader::compile(gl, Stage::Fragment, name, fragment)?;
        Program::link(gl, name, &[&vs, &fs])
    }

    /// Links compiled shaders.
    pub fn link(gl: &Gl, name: &str, shaders: &[&Shader]) -> Result<Program> {
        // SAFETY: a current context; the shaders are live objects of it.
        unsafe {
            let raw = gl.create_program().map_err(|e| Error::Gl(format!("cannot create a program: {e}")))?;
            let program = Program { gl: gl.clone(), raw, name: name.to_string(), uniforms: RefCell::default() };
            for s in shaders {
                gl.attach_shader(raw, s.raw);
            }
            gl.link_program(raw);
            for s in shaders {
                gl.detach_shader(raw, s.raw);
            }
            if !gl.get_program_link_status(raw) {
                let log = gl.get_program_info_log(raw);
                return Err(Error::Gl(format!("program '{name}' does not link:\n{}", log.trim_end())));
            }
            Ok(program)
        }
    }

    /// Makes it the current program (GL state: `CURRENT_PROGRAM`).
    pub fn bind(&self) {
        // SAFETY: a live program of this context.
        unsafe { self.gl.use_program(Some(self.raw)) }
    }

    /// The program's name, as given at creation.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The location of uniform `name`, `None` when the program has no active uniform of that
    /// name (setting it is then a no-op, as in GL).
    pub fn location(&self, name: &str) -> Option<glow::UniformLocation> {
        if let Some(l) = self.uniforms.borrow().get(name) {
            return *l;
        }
        // SAFETY: a live program of this context.
        let l = unsafe { self.gl.get_uniform_location(self.raw, name) };
        self.uniforms.borrow_mut().insert(name.to_string(), l);
        l
    }

    // The setters below act on the *bound* program: call `bind` first.

    pub fn set_i32(&self, name: &str, x: i32) {
        // SAFETY: uniform upload to the bound program; a missing location is a no-op.
        unsafe { self.gl.uniform_1_i32(self.location(name).as_ref(), x) }
    }

    pub fn set_f32(&self, name: &str, x: f32) {
        // SAFETY: as above.
        unsafe { self.gl.uniform_1_f32(self.location(name).as_ref(), x) }
    }

    pub fn set_vec2(&self, name: &str, v: Vec2) {
        // SAFETY: as above.
        unsafe { self.gl.uniform_2_f32(self.location(name).as_ref(), v.x, v.y) }
    }

    pub fn set_vec3(&self, name: &str, v: Vec3) {
        // SAFETY: as above.
        unsafe { self.gl.uniform_3_f32(self.location(name).as_ref(), v.x, v.y, v.z) }
    }

    pub fn set_vec4(&self, name: &str, v: Vec4) {
        // SAFETY: as above.
        unsafe { self.gl.uniform_4_f32(self.location(name).as_ref(), v.x, v.y, v.z, v.w) }
    }

    pub fn set_mat4(&self, name: &str, m: &Mat4) {
        // SAFETY: as above; glam matrices are column-major like GL.
        unsafe { self.gl.uniform_matrix_4_f32_slice(self.location(name).as_ref(), false, &m.to_cols_array()) }
    }

    /// The GL name.
    pub fn raw(&self) -> glow::Program {
        self.raw
    }
}

impl Drop for Program {
    fn drop(&mut self) {
        self.gl.ensure_current();
        // SAFETY: the program belongs to this context and is deleted once.
        unsafe { self.gl.delete_program(self.raw) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_line_numbers_are_found_in_common_formats() {
        assert_eq!(log_lines("0:12(5): error: `x' undeclared"), vec![12]);
        assert_eq!(log_lines("ERROR: 0:7: 'foo' : syntax error"), vec![7]);
        assert_eq!(log_lines("0(33) : error C0000"), vec![33]);
        assert!(log_lines("no numbers here").is_empty());
    }

    #[test]
    fn excerpt_shows_context_around_the_error() {
        let src = (1..=20).map(|i| format!("line{i}")).collect::<Vec<_>>().join("\n");
        let e = excerpt(&src, "0:10(1): error");
        assert!(e.contains("  10 | line10") && e.contains("   8 | line8") && !e.contains("line3\n"));
    }
}
