//! Standard scenes: every built-in model under every preset is framed inside the view frustum,
//! with the camera and light where the preset says.

use std::path::Path;

use brdfpaint::scene::{self, Light, Projection, Scene};
use glam::{Mat4, Vec3};

/// A bounding sphere computed here, independently of the library: centre of the axis-aligned
/// box, radius to the farthest vertex.
fn bounding_sphere(scene: &Scene) -> (Vec3, f32) {
    let points: Vec<Vec3> = scene.meshes.iter().flat_map(|m| m.positions.iter().copied()).collect();
    let lo = points.iter().fold(Vec3::splat(f32::INFINITY), |a, &b| a.min(b));
    let hi = points.iter().fold(Vec3::splat(f32::NEG_INFINITY), |a, &b| a.max(b));
    let centre = (lo + hi) / 2.0;
    let radius = points.iter().map(|p| p.distance(centre)).fold(0.0, f32::max);
    (centre, radius)
}

#[test]
fn framing_puts_the_bounding_sphere_inside_the_frustum() {
    for &model in scene::builtin_models() {
        for preset in scene::preset_names() {
            let scene = Scene::from_preset(model, preset).unwrap_or_else(|e| panic!("{model} {preset}: {e}"));
            let what = format!("{model} under {preset}");
            let Projection::Perspective { yfov, aspect: Some(aspect), znear, zfar: Some(zfar) } = scene.camera.projection
            else {
                panic!("{what}: not a perspective camera with aspect and zfar: {:?}", scene.camera.projection)
            };
            assert_eq!(aspect, 1.0, "{what}");

            let (centre, radius) = bounding_sphere(&scene);
            let view = scene.camera.world_from_camera.inverse();
            let c = view.transform_point3(centre);
            // The frustum's side planes pass through the eye; their inward unit normals in
            // view space (looking along -z) are, with h the half field of view,
            // top (0, -cos h, -sin h), bottom (0, cos h, -sin h), and the same in x with the
            // horizontal half angle w, tan w = aspect tan h. The sphere is inside when its
            // centre is at least r from every plane.
            let h = yfov / 2.0;
            let w = (aspect * h.tan()).atan();
            let planes = [
                Vec3::new(0.0, -h.cos(), -h.sin()),
                Vec3::new(0.0, h.cos(), -h.sin()),
                Vec3::new(-w.cos(), 0.0, -w.sin()),
                Vec3::new(w.cos(), 0.0, -w.sin()),
            ];
            for n in planes {
                assert!(n.dot(c) >= radius * (1.0 - 1e-5), "{what}: centre {c} only {} from plane {n}, r = {radius}", n.dot(c));
            }
            assert!(-c.z - radius > znear, "{what}: near plane {znear} cuts the sphere (depth {})", -c.z);
            assert!(-c.z + radius < zfar, "{what}: far plane {zfar} cuts the sphere (depth {})", -c.z);

            // Every vertex projects inside the picture, within the 85% the framing fills, and
            // the object is not a speck.
            let t = h.tan();
            let mut widest = 0.0f32;
            for p in scene.meshes.iter().flat_map(|m| &m.positions) {
                let q = view.transform_point3(*p);
                assert!(-q.z > znear && -q.z < zfar, "{what}: vertex depth {}", -q.z);
                let ndc = (q.x / (-q.z * t * aspect)).abs().max((q.y / (-q.z * t)).abs());
                widest = widest.max(ndc);
            }
            assert!(widest <= scene::preset::FRAME_FILL + 1e-4, "{what}: a vertex at {widest} of the half-frame");
            assert!(widest > 0.4, "{what}: the object fills only {widest} of the half-frame");
        }
    }
}

#[test]
fn presets_place_camera_and_light_as_named() {
    let deg = |d: f32| d.to_radians();
    let scene_of = |p: &str| Scene::from_preset("sphere", p).unwrap();
    // The built-in sphere is centred at the origin, so the eye direction is the view direction.
    let eye = |s: &Scene| s.camera.position().normalize();
    let light_towards = |s: &Scene| match s.light {
        Light::Directional { direction, color, intensity } => {
            assert_eq!((color, intensity), (Vec3::ONE, 1.0));
            -direction
        }
        other => panic!("preset light is not directional: {other:?}"),
    };
    let near = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;

    // front-left, by hand: the camera is at azimuth 0, 10° up: back = (0, sin 10°, cos 10°),
    // right = +X, up = back × right = (0, cos 10°, -sin 10°); the light comes from
    // (-right + up + back)/√3.
    let s = scene_of("front-left");
    let back = Vec3::new(0.0, deg(10.0).sin(), deg(10.0).cos());
    let up = Vec3::new(0.0, deg(10.0).cos(), -deg(10.0).sin());
    assert!(near(eye(&s), back), "{}", eye(&s));
    assert!(near(s.camera.world_from_camera.transform_vector3(Vec3::X), Vec3::X));
    assert!(near(s.camera.world_from_camera.transform_vector3(Vec3::Y), up));
    assert!(near(light_towards(&s), (-Vec3::X + up + back) / 3f32.sqrt()), "{}", light_towards(&s));
    // front-right mirrors it in x.
    assert!(near(light_towards(&scene_of("front-right")), (Vec3::X + up + back) / 3f32.sqrt()));
    // front: a headlight.
    assert!(near(light_towards(&scene_of("front")), back));
    // rim: the light is behind the object (away from the camera) and above.
    let rim = light_towards(&scene_of("rim"));
    assert!(rim.dot(back) < -0.7 && rim.y > 0.0, "{rim}");
    // top: 60° up.
    assert!(near(eye(&scene_of("top")), Vec3::new(0.0, deg(60.0).sin(), deg(60.0).cos())));
    // side: from +X; its right is -Z.
    let s = scene_of("side");
    assert!(near(eye(&s), Vec3::new(deg(10.0).cos(), deg(10.0).sin(), 0.0)));
    assert!(near(s.camera.world_from_camera.transform_vector3(Vec3::X), -Vec3::Z));
    // back: from -Z; its right is -X; the key light still comes from the picture's upper left.
    let s = scene_of("back");
    assert!(near(eye(&s), Vec3::new(0.0, deg(10.0).sin(), -deg(10.0).cos())));
    assert!(near(s.camera.world_from_camera.transform_vector3(Vec3::X), -Vec3::X));
    assert!(light_towards(&s).x > 0.0, "left of a camera at -Z is +X");

    // Every camera matrix is a rigid motion.
    for p in scene::preset_names() {
        let m = scene_of(p).camera.world_from_camera;
        let r = glam::Mat3::from_mat4(m);
        assert!((r.transpose() * r).abs_diff_eq(glam::Mat3::IDENTITY, 1e-6) && (r.determinant() - 1.0).abs() < 1e-6, "{p}");
        assert_eq!(m.row(3), glam::Vec4::W, "{p}");
    }
}

#[test]
fn model_paths_frame_like_built_in_names() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/models/bunny/bunny.glb");
    let a = Scene::from_preset(&file, "rim").unwrap();
    let b = Scene::from_preset("bunny", "rim").unwrap();
    assert_eq!(a.camera, b.camera);
    assert_eq!(a.light, b.light);
    assert_eq!(a.meshes[0].positions, b.meshes[0].positions);
    // Framing depends on the bounding sphere only: scaling the model by 2 about its centre
    // doubles the eye's distance from that centre and changes nothing else.
    let (centre, _) = bounding_sphere(&b);
    let mut meshes = b.meshes.clone();
    for m in &mut meshes {
        m.transform(Mat4::from_translation(centre) * Mat4::from_scale(Vec3::splat(2.0)) * Mat4::from_translation(-centre));
    }
    let scaled = scene::frame(meshes, &scene::preset("rim").unwrap(), 1.0);
    let (d1, d2) = (b.camera.position().distance(centre), scaled.camera.position().distance(centre));
    assert!((d2 / d1 - 2.0).abs() < 1e-4, "{d1} -> {d2}");
    assert!((scaled.camera.forward() - b.camera.forward()).length() < 1e-5);
    assert_eq!(scaled.light, b.light);
}

#[test]
fn unknown_names_list_the_valid_ones() {
    let message = Scene::from_preset("sphere", "sunset").unwrap_err().to_string();
    for name in ["front-left", "front-right", "front", "top", "side", "back", "rim"] {
        assert!(message.contains(name), "{message} lacks {name}");
    }
    assert!(message.contains("sunset"));
    let message = Scene::from_preset("cow", "top").unwrap_err().to_string();
    for name in ["sphere", "bunny", "suzanne", "teapot", "apple", "fox"] {
        assert!(message.contains(name), "{message} lacks {name}");
    }
    let message = Scene::from_preset("/nonexistent/cow.glb", "top").unwrap_err().to_string();
    assert!(message.contains("/nonexistent/cow.glb"), "{message}");
}
