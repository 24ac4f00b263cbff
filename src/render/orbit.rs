//! Image sequences: a camera or a light orbiting the scene's vertical axis.
//!
//! The axis is world $+y$ (glTF is $y$-up) through the centre of the meshes' bounding
//! sphere. Frame $k$ of $N$ turns by $\varphi_k = 2\pi k / N$, counter-clockwise seen from
//! above (a right-handed rotation about $+y$), so frame 0 is the scene as given.

use std::f32::consts::TAU;

use glam::{Mat4, Vec3};

use crate::scene::{Camera, Light, Scene};

/// What moves in a sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Orbit {
    /// The camera orbits the vertical axis (a turntable); the light stays where it is.
    Camera,
    /// The light orbits the vertical axis; the camera stays where it is.
    Light,
}

/// The vertical axis's point: the centre of the meshes' bounding sphere (origin if none).
pub fn orbit_centre(scene: &Scene) -> Vec3 {
    scene.bounding_sphere().map_or(Vec3::ZERO, |b| b.center)
}

/// Angle of frame `k` of `n`: $2\pi k / n$.
pub fn orbit_angle(k: usize, n: usize) -> f32 {
    TAU * k as f32 / n.max(1) as f32
}

/// $T(c)\,R_y(\varphi)\,T(-c)$: rotation by `angle` about the vertical line through `centre`.
fn about_axis(centre: Vec3, angle: f32) -> Mat4 {
    Mat4::from_translation(centre) * Mat4::from_rotation_y(angle) * Mat4::from_translation(-centre)
}

/// `camera` turned by `angle` about the vertical axis through `centre` (its projection kept).
pub fn orbit_camera(camera: &Camera, centre: Vec3, angle: f32) -> Camera {
    Camera { world_from_camera: about_axis(centre, angle) * camera.world_from_camera, ..*camera }
}

/// `light` turned by `angle` about the vertical axis through `centre`: a directional light's
/// direction, a point light's position. Colour and intensity are kept.
pub fn orbit_light(light: &Light, centre: Vec3, angle: f32) -> Light {
    let m = about_axis(centre, angle);
    match *light {
        Light::Directional { direction, color, intensity } => {
            Light::Directional { direction: m.transform_vector3(direction), color, intensity }
        }
        Light::Point { position, color, intensity } => {
            Light::Point { position: m.transform_point3(position), color, intensity }
        }
    }
}

/// The camera and light of frame `k` of `n` of `orbit`, around `centre`.
pub fn orbit_frame(camera: &Camera, light: &Light, centre: Vec3, orbit: Orbit, k: usize, n: usize) -> (Camera, Light) {
    let angle = orbit_angle(k, n);
    match orbit {
        Orbit::Camera => (orbit_camera(camera, centre, angle), *light),
        Orbit::Light => (*camera, orbit_light(light, centre, angle)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Projection;

    #[test]
    fn a_quarter_turn_moves_plus_z_to_plus_x_about_the_centre() {
        let centre = Vec3::new(1.0, 2.0, 3.0);
        let camera = Camera {
            world_from_camera: Mat4::from_translation(centre + Vec3::new(0.0, 0.5, 4.0)),
            projection: Projection::Perspective { yfov: 0.5, aspect: None, znear: 0.1, zfar: None },
        };
        let c = orbit_camera(&camera, centre, orbit_angle(1, 4));
        assert!((c.position() - (centre + Vec3::new(4.0, 0.5, 0.0))).length() < 1e-5, "{}", c.position());
        // Still looks the same way relative to the axis: from +z it looked along -z, now -x.
        assert!((c.forward() - -Vec3::X).length() < 1e-6);
        assert_eq!(c.projection, camera.projection);
        let light = Light::Point { position: centre + Vec3::new(0.0, 0.0, 2.0), color: Vec3::ONE, intensity: 5.0 };
        let Light::Point { position, intensity, .. } = orbit_light(&light, centre, orbit_angle(1, 4)) else { panic!() };
        assert!((position - (centre + Vec3::new(2.0, 0.0, 0.0))).length() < 1e-5 && intensity == 5.0);
        let sun = Light::Directional { direction: Vec3::new(0.0, -1.0, -1.0), color: Vec3::ONE, intensity: 1.0 };
        let Light::Directional { direction, .. } = orbit_light(&sun, centre, orbit_angle(2, 4)) else { panic!() };
        assert!((direction - Vec3::new(0.0, -1.0, 1.0)).length() < 1e-5, "{direction}");
        // Frame 0 is the scene as given.
        assert_eq!(orbit_frame(&camera, &sun, centre, Orbit::Camera, 0, 7), (camera, sun));
    }
}
