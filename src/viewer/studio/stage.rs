//! What the 3D view draws: the model on the GPU, the camera around it, the light, the
//! uploaded material and the render scale.

use std::time::Instant;

use super::super::camera::{LightControl, OrbitCamera};
use super::super::render_scale::RenderScale;
use crate::error::Result;
use crate::material::Material;
use crate::render::{GpuScene, GpuShading, Renderer};
use crate::scene::{BoundingSphere, CpuMesh, Scene};

pub struct Stage {
    pub gpu_model: GpuScene,
    pub bound: BoundingSphere,
    pub orbit: OrbitCamera,
    pub light: LightControl,
    /// The shown material, uploaded.
    pub shading: Option<GpuShading>,
    /// The shown material changed since the upload.
    pub shading_dirty: bool,
    pub render_scale: RenderScale,
}

fn bound_of(meshes: &[CpuMesh]) -> BoundingSphere {
    BoundingSphere::of(meshes).unwrap_or(BoundingSphere { center: glam::Vec3::ZERO, radius: 1.0 })
}

impl Stage {
    /// `meshes` framed by the standard front view, under the key light.
    pub fn new(renderer: &Renderer, meshes: &[CpuMesh], render_scale: RenderScale) -> Result<Stage> {
        let bound = bound_of(meshes);
        let orbit = OrbitCamera::framing(bound);
        let light = LightControl::key(&orbit);
        let scene = Scene { meshes: meshes.to_vec(), camera: orbit.camera(1.0), light: light.light() };
        let gpu_model = GpuScene::upload(renderer.gl(), &scene)?;
        Ok(Stage { gpu_model, bound, orbit, light, shading: None, shading_dirty: true, render_scale })
    }

    /// Shows other meshes, framed anew from the same direction.
    pub fn show_model(&mut self, renderer: &Renderer, meshes: &[CpuMesh]) -> Result<()> {
        let bound = bound_of(meshes);
        let scene = Scene { meshes: meshes.to_vec(), camera: self.orbit.camera(1.0), light: self.light.light() };
        self.gpu_model = GpuScene::upload(renderer.gl(), &scene)?;
        self.bound = bound;
        let (yaw, pitch) = (self.orbit.yaw, self.orbit.pitch);
        self.orbit = OrbitCamera { yaw, pitch, ..OrbitCamera::framing(bound) };
        Ok(())
    }

    /// The standard framing and the key light again.
    pub fn reset_view(&mut self) {
        self.orbit = OrbitCamera::framing(self.bound);
        self.light = LightControl::key(&self.orbit);
    }

    /// Uploads `material` when the shown material changed; the upload's milliseconds when
    /// one ran. Errors: the material cannot be drawn (nothing is drawn then).
    pub fn upload(&mut self, renderer: &mut Renderer, material: Option<&Material>) -> Result<Option<f64>> {
        if !self.shading_dirty {
            return Ok(None);
        }
        self.shading_dirty = false;
        let t = Instant::now();
        self.shading = None;
        if let Some(m) = material {
            self.shading = Some(renderer.upload(m)?);
        }
        Ok(Some(t.elapsed().as_secs_f64() * 1e3))
    }
}
