//! Camera and light uniforms from the scene contract types.

use glam::{Mat4, Vec3, Vec4};

use crate::error::{Error, Result};
use crate::gl::Program;
use crate::scene::{Camera, Light, Projection};

/// Everything the shaders need to know about the camera for one image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Clip from world.
    pub view_proj: Mat4,
    /// Camera position (world).
    pub eye: Vec3,
    /// Unit camera forward (world), the node's $-z$.
    pub forward: Vec3,
    /// Unit camera right and up (world), the node's $+x$ and $+y$: the view space a
    /// material's detail is looked up in.
    pub right: Vec3,
    pub up: Vec3,
    /// Orthographic projection: all view directions are $-$`forward`.
    pub orthographic: bool,
}

impl View {
    /// Matrices for a `width` × `height` image. The aspect is always `width / height`
    /// (DESIGN.md: the painting's pixel grid sets it; checking it against the file's
    /// aspectRatio is the scene loader's job). Orthographic cameras keep `ymag` as the
    /// vertical half extent and get `xmag = ymag · width / height`.
    ///
    /// Errors: a non-invertible camera transform, a field of view outside $(0, \pi)$,
    /// non-positive or inverted clip planes.
    pub fn new(camera: &Camera, width: usize, height: usize) -> Result<View> {
        if width == 0 || height == 0 {
            return Err(Error::input(format!("an image of {width}x{height} pixels has no area")));
        }
        let world_from_camera = camera.world_from_camera;
        let det = world_from_camera.determinant();
        if !world_from_camera.is_finite() || det.abs() < 1e-12 {
            return Err(Error::input("the camera transform is not invertible"));
        }
        let camera_from_world = world_from_camera.inverse();
        let aspect = width as f32 / height as f32;
        let proj = match camera.projection {
            Projection::Perspective { yfov, znear, zfar, .. } => {
                if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(Error::input(format!("camera yfov {yfov} rad is outside (0, pi)")));
                }
                if !(znear > 0.0 && znear.is_finite()) {
                    return Err(Error::input(format!("camera znear {znear} must be positive")));
                }
                match zfar {
                    Some(far) if !(far > znear && far.is_finite()) => {
                        return Err(Error::input(format!("camera zfar {far} must exceed znear {znear}")));
                    }
                    Some(far) => glam::camera::rh::proj::opengl::perspective(yfov, aspect, znear, far),
                    None => infinite_perspective(yfov, aspect, znear),
                }
            }
            Projection::Orthographic { ymag, znear, zfar, .. } => {
                if !(ymag > 0.0 && ymag.is_finite()) {
                    return Err(Error::input(format!("orthographic camera ymag {ymag} must be positive")));
                }
                if !(zfar > znear && znear >= 0.0 && zfar.is_finite()) {
                    return Err(Error::input(format!(
                        "orthographic camera clip planes znear {znear}, zfar {zfar} must satisfy 0 <= znear < zfar"
                    )));
                }
                let xmag = ymag * aspect;
                glam::camera::rh::proj::opengl::orthographic(-xmag, xmag, -ymag, ymag, znear, zfar)
            }
        };
        Ok(View {
            view_proj: proj * camera_from_world,
            eye: world_from_camera.transform_point3(Vec3::ZERO),
            forward: world_from_camera.transform_vector3(-Vec3::Z).normalize(),
            right: world_from_camera.transform_vector3(Vec3::X).normalize(),
            up: world_from_camera.transform_vector3(Vec3::Y).normalize(),
            orthographic: matches!(camera.projection, Projection::Orthographic { .. }),
        })
    }

    /// Sets `u_view_proj`, `u_ortho`, `u_eye`, `u_toward_eye`, `u_view_axis`, `u_view_right`
    /// and `u_view_up` on the bound `program`.
    pub(crate) fn apply(&self, program: &Program) {
        program.set_mat4("u_view_proj", &self.view_proj);
        program.set_i32("u_ortho", self.orthographic as i32);
        program.set_vec3("u_eye", self.eye);
        program.set_vec3("u_toward_eye", -self.forward);
        program.set_vec3("u_view_axis", self.forward);
        program.set_vec3("u_view_right", self.right);
        program.set_vec3("u_view_up", self.up);
    }
}

/// The OpenGL projection with an infinite far plane (glTF 2.0, "Infinite perspective
/// projection"): as `perspective` with $f \to \infty$.
fn infinite_perspective(yfov: f32, aspect: f32, znear: f32) -> Mat4 {
    let f = 1.0 / (0.5 * yfov).tan();
    Mat4::from_cols(
        Vec4::new(f / aspect, 0.0, 0.0, 0.0),
        Vec4::new(0.0, f, 0.0, 0.0),
        Vec4::new(0.0, 0.0, -1.0, -1.0),
        Vec4::new(0.0, 0.0, -2.0 * znear, 0.0),
    )
}

/// The light as the shaders take it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightUniforms {
    /// 0 directional, 1 point.
    pub kind: i32,
    /// Directional: unit direction toward the light. Point: its position.
    pub vector: Vec3,
    /// Colour × intensity.
    pub rgb: Vec3,
}

impl LightUniforms {
    /// From the scene light. Errors: a zero or non-finite direction, non-finite values.
    pub fn new(light: &Light) -> Result<LightUniforms> {
        let (kind, vector, color, intensity) = match *light {
            Light::Directional { direction, color, intensity } => {
                if !direction.is_finite() || direction.length_squared() < 1e-20 {
                    return Err(Error::input(format!("directional light direction {direction} is not a direction")));
                }
                // The scene stores the direction the light travels; shaders want the
                // direction toward it.
                (0, -direction.normalize(), color, intensity)
            }
            Light::Point { position, color, intensity } => {
                if !position.is_finite() {
                    return Err(Error::input(format!("point light position {position} is not finite")));
                }
                (1, position, color, intensity)
            }
        };
        let rgb = color * intensity;
        if !rgb.is_finite() {
            return Err(Error::input(format!("light colour {color} x intensity {intensity} is not finite")));
        }
        Ok(LightUniforms { kind, vector, rgb })
    }

    /// Sets `u_light_kind`, `u_light_vec`, `u_light_rgb` on the bound `program`.
    pub(crate) fn apply(&self, program: &Program) {
        program.set_i32("u_light_kind", self.kind);
        program.set_vec3("u_light_vec", self.vector);
        program.set_vec3("u_light_rgb", self.rgb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn perspective_camera(zfar: Option<f32>) -> Camera {
        Camera {
            world_from_camera: Mat4::from_translation(Vec3::new(0.0, 0.0, 5.0)),
            projection: Projection::Perspective { yfov: 1.0, aspect: None, znear: 0.1, zfar },
        }
    }

    #[test]
    fn a_point_on_the_optical_axis_projects_to_the_centre_and_depth_is_ordered() {
        for zfar in [Some(100.0), None] {
            let v = View::new(&perspective_camera(zfar), 200, 100).unwrap();
            let near = v.view_proj * Vec4::new(0.0, 0.0, 4.0, 1.0);
            let far = v.view_proj * Vec4::new(0.0, 0.0, -20.0, 1.0);
            assert!((near.x / near.w).abs() < 1e-6 && (near.y / near.w).abs() < 1e-6);
            assert!(near.z / near.w < far.z / far.w, "{zfar:?}");
            // A point at the top edge of the field of view lands at NDC y = 1.
            let d = 5.0;
            let top = v.view_proj * Vec4::new(0.0, d * (0.5f32).tan(), 0.0, 1.0);
            assert!((top.y / top.w - 1.0).abs() < 1e-5, "{zfar:?}: {}", top.y / top.w);
            // And the aspect comes from the image: x spans twice as far.
            let right = v.view_proj * Vec4::new(2.0 * d * (0.5f32).tan(), 0.0, 0.0, 1.0);
            assert!((right.x / right.w - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn orthographic_keeps_ymag_and_the_image_aspect() {
        let cam = Camera {
            world_from_camera: Mat4::from_translation(Vec3::new(0.0, 0.0, 3.0)),
            projection: Projection::Orthographic { xmag: 1.0, ymag: 2.0, znear: 0.0, zfar: 10.0 },
        };
        let v = View::new(&cam, 300, 100).unwrap();
        let p = v.view_proj * Vec4::new(6.0, 2.0, 0.0, 1.0);
        assert!((p.x - 1.0).abs() < 1e-6 && (p.y - 1.0).abs() < 1e-6);
        assert!(v.orthographic && (v.forward - -Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn bad_cameras_and_lights_are_errors() {
        let mut cam = perspective_camera(Some(1.0));
        cam.projection = Projection::Perspective { yfov: 0.0, aspect: None, znear: 0.1, zfar: None };
        assert!(View::new(&cam, 10, 10).is_err());
        let cam = Camera { world_from_camera: Mat4::ZERO, ..perspective_camera(None) };
        assert!(View::new(&cam, 10, 10).is_err());
        assert!(View::new(&perspective_camera(Some(0.01)), 10, 10).is_err());
        let light = Light::Directional { direction: Vec3::ZERO, color: Vec3::ONE, intensity: 1.0 };
        assert!(LightUniforms::new(&light).is_err());
        let light = Light::Directional { direction: Vec3::new(0.0, -2.0, 0.0), color: Vec3::ONE, intensity: 3.0 };
        let u = LightUniforms::new(&light).unwrap();
        assert_eq!((u.kind, u.vector, u.rgb), (0, Vec3::Y, Vec3::splat(3.0)));
    }
}
