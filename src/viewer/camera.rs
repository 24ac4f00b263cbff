//! The viewer's camera (orbit, pan, zoom around the object) and its movable light.

use std::f32::consts::FRAC_PI_2;

use glam::{Mat4, Vec3};

use crate::scene::preset::{FRAME_FILL, FRAME_YFOV};
use crate::scene::{BoundingSphere, Camera, Light, Projection};

/// A camera orbiting a target: azimuth `yaw` about +Y (from +Z towards +X) and elevation
/// `pitch` (positive: looking down), at `distance` from the target, +Y up. Angles in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    pub target: Vec3,
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    /// The object's bounding radius: sets clip planes and pan and zoom speeds.
    pub radius: f32,
}

/// Pitch stays this far from the poles, so "up" stays defined.
const PITCH_LIMIT: f32 = FRAC_PI_2 - 0.01;

impl OrbitCamera {
    /// The standard front view of the object (as the `front-left` preset frames it).
    pub fn framing(bound: BoundingSphere) -> OrbitCamera {
        let radius = if bound.radius > 0.0 && bound.radius.is_finite() { bound.radius } else { 1.0 };
        // The bounding sphere fills FRAME_FILL of the height (scene::frame's rule).
        let half = FRAME_FILL * (FRAME_YFOV / 2.0).tan();
        let distance = radius / half.atan().sin();
        OrbitCamera { target: bound.center, yaw: 0.0, pitch: 10f32.to_radians(), distance, radius }
    }

    /// Unit direction from the target towards the camera.
    pub fn back(&self) -> Vec3 {
        Vec3::new(self.pitch.cos() * self.yaw.sin(), self.pitch.sin(), self.pitch.cos() * self.yaw.cos())
    }

    /// World from camera: the camera looks along its -Z at the target, +Y up.
    pub fn world_from_camera(&self) -> Mat4 {
        let back = self.back();
        let eye = self.target + self.distance * back;
        let right = Vec3::Y.cross(back).normalize();
        let up = back.cross(right);
        Mat4::from_cols(right.extend(0.0), up.extend(0.0), back.extend(0.0), eye.extend(1.0))
    }

    /// The scene camera for a picture of aspect `aspect` (width / height).
    pub fn camera(&self, aspect: f32) -> Camera {
        let znear = (self.distance - 1.5 * self.radius).max(self.distance * 0.01).max(1e-4);
        let zfar = self.distance + 2.0 * self.radius;
        Camera {
            world_from_camera: self.world_from_camera(),
            projection: Projection::Perspective { yfov: FRAME_YFOV, aspect: Some(aspect), znear, zfar: Some(zfar) },
        }
    }

    /// Turns the camera by `dx`, `dy` radians (drag right: the camera moves left round the
    /// object, so the object turns right).
    pub fn rotate(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx;
        self.pitch = (self.pitch + dy).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Moves the target in the picture plane by a drag of (`dx`, `dy`) pixels (y down) in a
    /// view `height` pixels tall, so the object follows the pointer.
    pub fn pan(&mut self, dx: f32, dy: f32, height: f32) {
        let m = self.world_from_camera();
        let per_pixel = 2.0 * self.distance * (FRAME_YFOV / 2.0).tan() / height.max(1.0);
        let right = m.x_axis.truncate();
        let up = m.y_axis.truncate();
        self.target += (-dx * right + dy * up) * per_pixel;
    }

    /// Multiplies the distance by `factor`, within sensible limits.
    pub fn zoom(&mut self, factor: f32) {
        self.distance = (self.distance * factor).clamp(1.05 * self.radius, 50.0 * self.radius);
    }
}

/// A directional light given by the direction towards it: azimuth about +Y from +Z towards
/// +X, and elevation, in radians; colour × intensity scale it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightControl {
    pub azimuth: f32,
    pub elevation: f32,
    pub color: Vec3,
    pub intensity: f32,
}

impl LightControl {
    /// The key light of the `front-left` preset for a camera orbiting as `orbit` does.
    pub fn key(orbit: &OrbitCamera) -> LightControl {
        let m = orbit.world_from_camera();
        LightControl::towards(m.transform_vector3(Vec3::new(-1.0, 1.0, 1.0)).normalize())
    }

    /// A white light of intensity 1 from direction `d` (towards the light).
    pub fn towards(d: Vec3) -> LightControl {
        let d = d.normalize_or(Vec3::Z);
        LightControl {
            azimuth: d.x.atan2(d.z),
            elevation: d.y.clamp(-1.0, 1.0).asin(),
            color: Vec3::ONE,
            intensity: 1.0,
        }
    }

    /// Unit direction towards the light, world space.
    pub fn direction(&self) -> Vec3 {
        let (a, e) = (self.azimuth, self.elevation);
        Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
    }

    /// Moves the light by `dx`, `dy` radians of azimuth and elevation.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        self.azimuth += dx;
        self.elevation = (self.elevation + dy).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// The scene light (glTF: `direction` is where the light travels).
    pub fn light(&self) -> Light {
        Light::Directional { direction: -self.direction(), color: self.color, intensity: self.intensity }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_framing_matches_the_front_left_preset() {
        let meshes = crate::scene::builtin_model("sphere").unwrap();
        let preset = crate::scene::preset("front-left").unwrap();
        let scene = crate::scene::frame(meshes.clone(), &preset, 1.0);
        let orbit = OrbitCamera::framing(BoundingSphere::of(&meshes).unwrap());
        let cam = orbit.camera(1.0);
        let d = (cam.world_from_camera - scene.camera.world_from_camera).abs().to_cols_array();
        assert!(d.iter().all(|x| *x < 1e-5), "{:?} vs {:?}", cam.world_from_camera, scene.camera.world_from_camera);
        let Light::Directional { direction, .. } = scene.light else { panic!() };
        let ours = LightControl::key(&orbit).direction();
        assert!((ours + direction).length() < 1e-5, "{ours} vs {direction}");
    }

    #[test]
    fn orbit_keeps_distance_and_pitch_limits() {
        let mut o = OrbitCamera { target: Vec3::ONE, yaw: 0.0, pitch: 0.0, distance: 4.0, radius: 1.0 };
        o.rotate(1.0, 10.0);
        assert!(o.pitch <= PITCH_LIMIT);
        let eye = o.world_from_camera().w_axis.truncate();
        assert!(((eye - o.target).length() - 4.0).abs() < 1e-5);
        o.zoom(0.01);
        assert!((o.distance - 1.05).abs() < 1e-6);
        let mut l = LightControl::towards(Vec3::new(1.0, 1.0, 0.0));
        assert!((l.direction() - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        l.drag(0.0, 10.0);
        assert!(l.elevation <= PITCH_LIMIT);
    }
}
