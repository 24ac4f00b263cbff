//! Headless OpenGL contexts through EGL (no window system, no X server).
//!
//! The recipe (DESIGN.md, "Technology"): enumerate EGL devices, pick one, open a display on
//! it, choose a config with no surface type, create a GL 3.3 core context (GLES 3.0 as a
//! fallback) and make it current *surfaceless*. Rendering then goes to framebuffer objects.
//!
//! A context is current on the thread that created it, so [`HeadlessContext`] is neither
//! `Send` nor `Sync` (the glutin context inside it is not). Make one context per thread; many
//! threads with one context each work in one process, which is what `cargo test` does.

use std::ffi::CStr;
use std::rc::Rc;

use glow::HasContext;
use glutin::api::egl::context::PossiblyCurrentContext;
use glutin::api::egl::device::Device;
use glutin::api::egl::display::Display;
use glutin::config::{Api, ConfigSurfaceTypes, ConfigTemplateBuilder};
use glutin::context::{ContextApi, ContextAttributesBuilder, GlProfile, Version};
use glutin::prelude::*;

use crate::error::{Error, Result};

/// Which EGL device to open.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DevicePreference {
    /// Mesa's software rasterizer (`EGL_MESA_device_software`, llvmpipe), else a hardware
    /// device. The default, so that tests produce the same pixels on every machine that has
    /// Mesa; a machine with a GPU driver and no Mesa (a GPU server) still renders, on its GPU.
    #[default]
    Software,
    /// A hardware device when one exists, else the software one.
    Hardware,
}

/// Which API to ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ApiPreference {
    /// Desktop GL 3.3 core, else GLES 3.0.
    #[default]
    Auto,
    /// Desktop GL 3.3 core only.
    DesktopGl,
    /// GLES 3.0 only (tests the GLES code path on a desktop machine).
    Gles,
}

/// A GL function table shared by every GL object made from it.
///
/// Objects ([`Texture2D`](super::Texture2D), [`Program`](super::Program), …) hold a clone,
/// so the native context outlives them and their `Drop` can delete them. It derefs to
/// [`glow::Context`].
#[derive(Clone)]
pub struct Gl(Rc<GlShared>);

struct GlShared {
    // Field order is drop order: the function table goes first, then whatever owns the
    // native context (for headless contexts, the EGL context and display).
    glow: glow::Context,
    owner: Option<Owner>,
}

/// The EGL objects behind a headless [`Gl`]. Dropping it releases the context from this
/// thread (if current) so EGL can destroy it; glutin then destroys the context. The display
/// is never terminated (other threads share it; see glutin's `DisplayInner::drop`).
struct Owner {
    context: PossiblyCurrentContext,
    _display: Display,
}

impl Drop for Owner {
    fn drop(&mut self) {
        if self.context.is_current() {
            // Failure here only means the context stays current until the thread ends.
            let _ = self.context.make_not_current_in_place();
        }
    }
}

impl Gl {
    /// Wraps a `glow::Context` whose native context is owned elsewhere (e.g. a window).
    /// The caller keeps that context current while objects made from it are used or dropped.
    pub fn from_glow(glow: glow::Context) -> Self {
        Gl(Rc::new(GlShared { glow, owner: None }))
    }

    /// `true` for OpenGL ES (shaders get `#version 300 es`), `false` for desktop GL.
    pub fn is_gles(&self) -> bool {
        self.0.glow.version().is_embedded
    }

    /// Makes the headless context behind this table current on this thread if another one
    /// is. GL objects call it before deleting themselves, so a thread may hold several
    /// contexts. A no-op for contexts owned elsewhere.
    pub fn ensure_current(&self) {
        if let Some(owner) = &self.0.owner {
            if !owner.context.is_current() {
                let _ = owner.context.make_current_surfaceless();
            }
        }
    }
}

impl std::ops::Deref for Gl {
    type Target = glow::Context;
    fn deref(&self) -> &glow::Context {
        &self.0.glow
    }
}

/// An OpenGL context with no window: an EGL display on a device, a surfaceless current
/// context, and its [`glow`] function table. Not `Send`: use it on the thread that made it.
pub struct HeadlessContext {
    gl: Gl,
    version: String,
    renderer: String,
    device: String,
}

impl HeadlessContext {
    /// A context on the software device (llvmpipe), so results agree everywhere, unless the
    /// environment says `BRDFPAINT_GL_DEVICE=hardware` (how the GL tests are run on a GPU);
    /// on a machine without Mesa, on a hardware device ([`DevicePreference::Software`]).
    pub fn new() -> Result<Self> {
        let hardware = std::env::var("BRDFPAINT_GL_DEVICE").is_ok_and(|v| v.eq_ignore_ascii_case("hardware"));
        Self::with_preference(if hardware { DevicePreference::Hardware } else { DevicePreference::Software })
    }

    /// A context on a hardware device when there is one, else on the software device.
    pub fn new_preferring_hardware() -> Result<Self> {
        Self::with_preference(DevicePreference::Hardware)
    }

    /// A context on the device `preference` picks.
    pub fn with_preference(preference: DevicePreference) -> Result<Self> {
        Self::with_options(preference, ApiPreference::Auto)
    }

    /// A context on the device `preference` picks, with the API `api` asks for.
    ///
    /// Every failure says which Debian packages to install ([`missing_gl_message`]): on a
    /// working machine none happens, and on a fresh one the cause is almost always a
    /// missing libEGL, Mesa EGL vendor or Mesa driver.
    pub fn with_options(preference: DevicePreference, api: ApiPreference) -> Result<Self> {
        Self::try_options(preference, api).map_err(|e| match e {
            Error::Gl(detail) => Error::Gl(missing_gl_message(&detail)),
            other => other,
        })
    }

    fn try_options(preference: DevicePreference, api: ApiPreference) -> Result<Self> {
        let devices: Vec<Device> =
            Device::query_devices().map_err(|e| Error::Gl(format!("cannot list EGL devices: {e}")))?.collect();
        let is_software = |d: &Device| d.extensions().contains("EGL_MESA_device_software");
        // Candidates in order of preference; a device that fails to open is skipped.
        let (software, hardware): (Vec<&Device>, Vec<&Device>) = devices.iter().partition(|d| is_software(d));
        let candidates: Vec<&Device> = match preference {
            DevicePreference::Software => software.into_iter().chain(hardware).collect(),
            DevicePreference::Hardware => hardware.into_iter().chain(software).collect(),
        };
        if candidates.is_empty() {
            return Err(Error::Gl(format!(
                "no suitable EGL device among {} (wanted {preference:?}; is Mesa's EGL installed?)",
                devices.len()
            )));
        }
        let mut failures = Vec::new();
        for device in candidates {
            match Self::on_device(device, api) {
                Ok(ctx) => return Ok(ctx),
                Err(Error::Gl(m)) => failures.push(m),
                Err(e) => failures.push(e.to_string()),
            }
        }
        Err(Error::Gl(failures.join("; ")))
    }

    fn on_device(device: &Device, api: ApiPreference) -> Result<Self> {
        let device_name =
            format!("{} ({})", device.name().unwrap_or("unnamed device"), device.vendor().unwrap_or("unknown vendor"));

        // SAFETY: no raw display handle is passed, which `with_device` documents as valid.
        let display = unsafe { Display::with_device(device, None) }
            .map_err(|e| Error::Gl(format!("cannot open an EGL display on {device_name}: {e}")))?;

        // Try desktop GL 3.3 core first, then GLES 3.0.
        let attempts = vec![
            (
                Api::OPENGL,
                ContextAttributesBuilder::new()
                    .with_context_api(ContextApi::OpenGl(Some(Version::new(3, 3))))
                    .with_profile(GlProfile::Core)
                    .build(None),
            ),
            (
                Api::GLES3,
                ContextAttributesBuilder::new()
                    .with_context_api(ContextApi::Gles(Some(Version::new(3, 0))))
                    .build(None),
            ),
        ];
        let attempts = attempts.into_iter().filter(|(a, _)| match api {
            ApiPreference::Auto => true,
            ApiPreference::DesktopGl => *a == Api::OPENGL,
            ApiPreference::Gles => *a == Api::GLES3,
        });
        let mut failures = Vec::new();
        let mut made = None;
        for (api, attributes) in attempts {
            // No surface type: we never draw to a window or pbuffer, only to FBOs.
            let template =
                ConfigTemplateBuilder::new().with_surface_type(ConfigSurfaceTypes::empty()).with_api(api).build();
            // SAFETY: the template refers to no native window.
            let config = match unsafe { display.find_configs(template) } {
                Ok(mut configs) => configs.next(),
                Err(e) => {
                    failures.push(format!("{api:?}: no config ({e})"));
                    continue;
                }
            };
            let Some(config) = config else {
                failures.push(format!("{api:?}: no config"));
                continue;
            };
            // SAFETY: the attributes refer to no native window.
            match unsafe { display.create_context(&config, &attributes) } {
                Ok(not_current) => match not_current.make_current_surfaceless() {
                    Ok(current) => {
                        made = Some(current);
                        break;
                    }
                    Err(e) => failures.push(format!("{api:?}: make_current_surfaceless: {e}")),
                },
                Err(e) => failures.push(format!("{api:?}: create_context: {e}")),
            }
        }
        let context = made.ok_or_else(|| {
            Error::Gl(format!("cannot create a GL context on {device_name}: {}", failures.join("; ")))
        })?;

        // SAFETY: the context is current on this thread; the loader returns its functions.
        let glow = unsafe { glow::Context::from_loader_function_cstr(|s: &CStr| display.get_proc_address(s)) };
        // SAFETY: plain string queries on a current context.
        let (version, renderer) =
            unsafe { (glow.get_parameter_string(glow::VERSION), glow.get_parameter_string(glow::RENDERER)) };
        let owner = Owner { context, _display: display };
        let gl = Gl(Rc::new(GlShared { glow, owner: Some(owner) }));
        Ok(HeadlessContext { gl, version, renderer, device: device_name })
    }

    /// The GL function table (derefs to [`glow::Context`]); clone it into GL objects.
    pub fn gl(&self) -> &Gl {
        &self.gl
    }

    /// Makes this context current again on this thread (only needed when one thread uses
    /// several contexts; objects are made in whichever context is current).
    pub fn make_current(&self) -> Result<()> {
        match &self.gl.0.owner {
            Some(owner) => owner
                .context
                .make_current_surfaceless()
                .map_err(|e| Error::Gl(format!("cannot make the context current: {e}"))),
            None => Ok(()),
        }
    }

    /// `GL_VERSION`, e.g. "4.5 (Core Profile) Mesa 24.2.8".
    pub fn version(&self) -> &str {
        &self.version
    }

    /// `GL_RENDERER`, e.g. "llvmpipe (LLVM 19.1.7, 256 bits)".
    pub fn renderer(&self) -> &str {
        &self.renderer
    }

    /// The EGL device's name and vendor.
    pub fn device(&self) -> &str {
        &self.device
    }

    /// `true` when the context is OpenGL ES rather than desktop GL.
    pub fn is_gles(&self) -> bool {
        self.gl.is_gles()
    }
}

/// The Debian packages headless rendering needs: the EGL loader, Mesa's EGL vendor, and
/// Mesa's drivers (llvmpipe).
pub const GL_PACKAGES: &str = "libegl1 libegl-mesa0 libgl1-mesa-dri";

/// The one-line message for a headless context that could not be made: what failed, and
/// the command that installs what is usually missing. `detail` is the EGL failure, e.g.
/// "cannot list EGL devices: not found" (no libEGL), "Enumerating devices is not supported
/// by the EGL instance" (no Mesa EGL vendor), or a failed display or context on the
/// software device (no Mesa driver).
pub fn missing_gl_message(detail: &str) -> String {
    let detail = detail.split_whitespace().collect::<Vec<_>>().join(" ");
    format!(
        "cannot create a headless GL context ({detail}); rendering needs Mesa's EGL and GL driver (Debian packages {GL_PACKAGES}): sudo apt-get install {GL_PACKAGES}"
    )
}

impl std::fmt::Debug for HeadlessContext {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HeadlessContext")
            .field("version", &self.version)
            .field("renderer", &self.renderer)
            .field("device", &self.device)
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The errors seen on machines without the packages (issue 14) each become one line
    /// naming the packages and the install command.
    #[test]
    fn missing_libraries_name_the_packages_to_install() {
        for detail in [
            "cannot list EGL devices: not found",
            "cannot list EGL devices: Enumerating devices is not supported by the EGL instance",
            "cannot open an EGL display on unnamed device (unknown vendor): [3001] initialization failed\nMESA-LOADER: failed to open swrast",
        ] {
            let m = Error::Gl(missing_gl_message(detail)).to_string();
            assert!(!m.contains('\n'), "{m}");
            assert!(m.ends_with("sudo apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri"), "{m}");
            assert!(m.starts_with("OpenGL: cannot create a headless GL context (cannot "), "{m}");
        }
    }
}
