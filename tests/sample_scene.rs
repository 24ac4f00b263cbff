//! Sampling scenes: the G-buffer geometry against the analytic sphere, silhouette erosion,
//! light and falloff divided out (against the GL factored pass), aspect and model checks,
//! and every way a painting can carry no usable sample.

mod gl_common;

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{Analytic, SphereView};
use brdfpaint::factor::{prepare, Mapping, Settings};
use brdfpaint::images::Painting;
use brdfpaint::render::{mesh::cube, GpuScene};
use brdfpaint::sample::{
    check_aspect, check_same_model, scene::geometry_from_gbuffer, Erosion, Neighbours, PaintedView, Samples,
    SceneSampler,
};
use brdfpaint::scene::{Camera, Light, Projection, Scene};
use glam::{DVec3, Mat4, Vec3};
use gl_common::*;

const RES: usize = 96;

fn view(name: &str, geometry: brdfpaint::sample::Geometry, painting: Painting) -> PaintedView {
    PaintedView { name: name.into(), source: "scene.gltf".into(), geometry, painting }
}

/// l, v and uv at pixel centres match `SphereView::query` on an orthographic sphere scene.
#[test]
fn sphere_samples_match_the_analytic_sphere() {
    let mut sampler = SceneSampler::new().unwrap();
    let camera = DVec3::new(0.3, 0.4, 0.87).normalize();
    let toward = DVec3::new(-0.6, 0.2, 0.5).normalize();
    let scene = ortho_sphere(camera, sun(toward, [1.0, 0.5, 0.25]));
    let g = sampler.geometry(&scene, RES, RES, Erosion::default()).unwrap();
    let (mut n_px, mut worst) = (0, 0.0f64);
    for j in 0..RES {
        for i in 0..RES {
            let k = j * RES + i;
            if !g.usable[k] {
                continue;
            }
            // Every usable pixel sees the analytic sphere at least a pixel inside its rim.
            let n = sphere_normal(camera, RES, i, j).unwrap_or_else(|| panic!("({i}, {j}) usable off the sphere"));
            let px = g.pixels[k].unwrap();
            let want = SphereView::query(n, toward, camera);
            let (dl, dv) = ((px.query.l - want.l).length(), (px.query.v - want.v).length());
            assert!(px.query.v.z > 0.0);
            assert_eq!(px.light, [1.0, 0.5, 0.25], "directional: colour x intensity, no falloff");
            // Tessellation error grows toward the rim as 1/cos; the G-buffer test bounds it
            // by 2e-3 where the surface faces the camera (v_z >= 0.2), and the eroded rim
            // (v_z down to ~0.1 at 96 px) stays within 0.02.
            let bound = if want.v.z >= 0.2 { 2e-3 } else { 2e-2 };
            // Near the poles the mesh's tangent (per-vertex azimuth, interpolated) turns
            // away from SphereView's, which rotates l and v about the normal: compare the
            // cosines there, the whole vectors elsewhere.
            let (dl, dv) = if n.y.abs() < 0.98 { (dl, dv) } else { ((px.query.l.z - want.l.z).abs(), (px.query.v.z - want.v.z).abs()) };
            assert!(dl < bound && dv < bound, "({i}, {j}): {:?} vs {want:?}", px.query);
            let pos = px.position.unwrap();
            assert!((pos - n).length() < 2e-3 * (1.0 / want.v.z).min(10.0), "({i}, {j}) position {pos}");
            let uv = SphereView::uv(n);
            if uv.x > 0.02 && uv.x < 0.98 && n.y.abs() < 0.98 {
                assert!((px.query.uv - uv).length() < 1e-3, "({i}, {j}) uv {} vs {uv}", px.query.uv);
            }
            worst = worst.max(dl.max(dv));
            n_px += 1;
        }
    }
    eprintln!("{n_px} samples, worst direction error {worst:.2e}");
    // The eroded disc: pi (48 - 1)^2 = 6940 pixels, give or take the ring's discretization.
    assert!((n_px as f64 - 6940.0).abs() < 150.0, "{n_px}");
}

/// The erosion removes exactly the hit pixels with a background neighbour (8 or 4), and
/// those lie on the silhouette ring.
#[test]
fn erosion_removes_exactly_the_border_ring() {
    let mut sampler = SceneSampler::new().unwrap();
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::new(0.0, 0.3, 1.0), [1.0; 3]));
    let gbuffer = sampler.gbuffer(&scene, RES, RES).unwrap();
    let all = geometry_from_gbuffer(&gbuffer, &scene.light, true, Erosion::NONE).unwrap();
    let hit = |i: isize, j: isize| i >= 0 && j >= 0 && i < RES as isize && j < RES as isize && gbuffer.at(i as usize, j as usize).hit;
    for neighbours in [Neighbours::Eight, Neighbours::Four] {
        let g = geometry_from_gbuffer(&gbuffer, &scene.light, true, Erosion { radius: 1, neighbours }).unwrap();
        let mut ring = 0;
        for j in 0..RES as isize {
            for i in 0..RES as isize {
                let k = j as usize * RES + i as usize;
                let offsets: &[(isize, isize)] = match neighbours {
                    Neighbours::Four => &[(1, 0), (-1, 0), (0, 1), (0, -1)],
                    Neighbours::Eight => &[(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)],
                };
                let border = offsets.iter().any(|&(di, dj)| !hit(i + di, j + dj));
                assert_eq!(g.usable[k], all.usable[k] && !border, "({i}, {j}) {neighbours:?}");
                if all.usable[k] && border {
                    ring += 1;
                    // On the ring: the centre lies within 1.5 px inside the silhouette circle.
                    let (x, y) = (i as f64 + 0.5 - 48.0, j as f64 + 0.5 - 48.0);
                    let d = (x * x + y * y).sqrt() - 48.0;
                    assert!((-1.5..0.0).contains(&d), "ring pixel ({i}, {j}) at {d} px");
                }
            }
        }
        // About the circumference: 2 pi 48 = 302, more with diagonal neighbours.
        assert!((230..=420).contains(&ring), "{neighbours:?}: ring of {ring}");
    }
    // Without erosion every front-facing hit pixel is usable.
    assert_eq!(all.usable_count(), gbuffer.pixels.iter().filter(|p| p.hit && p.v.z > 0.0).count());
}

/// A mesh whose shading normals all face away from the camera has hits but no samples.
#[test]
fn back_facing_pixels_are_not_samples() {
    let mut sampler = SceneSampler::new().unwrap();
    let mut mesh = cube(Vec3::ZERO, 0.5);
    mesh.normals.iter_mut().for_each(|n| *n = -*n);
    let scene = Scene { meshes: vec![mesh], ..ortho_sphere(DVec3::new(0.3, 0.4, 1.0), sun(DVec3::Z, [1.0; 3])) };
    let gbuffer = sampler.gbuffer(&scene, 48, 48).unwrap();
    assert!(gbuffer.coverage() > 300, "the cube is drawn");
    let g = geometry_from_gbuffer(&gbuffer, &scene.light, true, Erosion::NONE).unwrap();
    assert_eq!(g.usable_count(), 0);
    let painting = Painting::opaque(48, 48, vec![[0.5; 3]; 48 * 48]).unwrap();
    let e = Samples::gather(&[view("p.png", g, painting)]).unwrap_err().to_string();
    assert!(e.contains("does not see the object") && e.contains("p.png"), "{e}");
}

/// The GL factored pass applies colour × intensity × 1/d²; sampling its image divides them
/// out and gives back the shading function at each query.
#[test]
fn point_light_falloff_and_colour_are_divided_out() {
    let mut sampler = SceneSampler::new().unwrap();
    let light = Light::Point { position: Vec3::new(1.5, 2.0, 2.5), color: Vec3::new(1.0, 0.6, 0.3), intensity: 9.0 };
    let scene = perspective_sphere(DVec3::new(0.5, 0.8, 3.5), 0.7, light);
    // A material: the default fit of Blinn-Phong on an analytic sphere view.
    let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 48).pattern();
    let settings = Settings::default();
    let model = &Analytic::suite()[2];
    let fit = prepare(&pattern, &settings).unwrap().solve(&pattern.shade(|q| model.shading(q)), Mapping::Auto).unwrap();
    let shading = brdfpaint::material::Material::from_fit(&settings, &fit, Default::default()).unwrap();
    let gpu = GpuScene::upload(sampler.context().gl(), &scene).unwrap();
    let gpu_shading = sampler.renderer().upload(&shading).unwrap();
    let image = sampler.renderer().factored(&gpu, &gpu_shading, RES, RES).unwrap();
    let painting = Painting::opaque(RES, RES, image.pixels.iter().map(|p| [p[0], p[1], p[2]]).collect()).unwrap();
    let g = sampler.geometry(&scene, RES, RES, Erosion::default()).unwrap();
    for px in g.pixels.iter().flatten() {
        let d2 = (light_position(&light) - px.position.unwrap()).length_squared();
        let want = [1.0, 0.6, 0.3].map(|c| c * 9.0 / d2);
        for c in 0..3 {
            assert!((px.light[c] - want[c]).abs() < 1e-5 * want[c], "{:?} vs {want:?}", px.light);
        }
    }
    let samples = Samples::gather(&[view("render.exr", g, painting)]).unwrap();
    assert!(samples.len() > 3000);
    let mut worst = 0.0f64;
    for (q, value) in samples.pattern.queries.iter().zip(&samples.values) {
        let s = fit.eval(&settings, q);
        let scale = s.iter().fold(0.05f64, |m, &x| m.max(x));
        for c in 0..3 {
            let e = (value[c] - s[c]).abs() / scale;
            assert!(e < 1e-3, "{q:?}: sampled {value:?} vs S {s:?}");
            worst = worst.max(e);
        }
    }
    eprintln!("worst relative disagreement {worst:.2e}");
}

fn light_position(light: &Light) -> DVec3 {
    match light {
        Light::Point { position, .. } => position.as_dvec3(),
        _ => unreachable!(),
    }
}

#[test]
fn camera_aspect_must_match_the_painting_within_one_percent() {
    let camera = |projection| Camera { world_from_camera: Mat4::IDENTITY, projection };
    let square = camera(Projection::Perspective { yfov: 0.5, aspect: Some(1.0), znear: 0.1, zfar: None });
    let e = check_aspect(&square, 640, 480, "painting.png").unwrap_err().to_string();
    assert_eq!(e, "painting.png is 640x480 but the scene camera's aspect is 1.0");
    assert!(check_aspect(&square, 101, 100, "p.png").is_ok(), "1% is allowed");
    assert!(check_aspect(&square, 102, 100, "p.png").is_err());
    let free = camera(Projection::Perspective { yfov: 0.5, aspect: None, znear: 0.1, zfar: None });
    assert!(check_aspect(&free, 640, 480, "p.png").is_ok(), "no aspectRatio: the painting sets it");
    let ortho = camera(Projection::Orthographic { xmag: 2.0, ymag: 1.5, znear: 0.1, zfar: 10.0 });
    assert!(check_aspect(&ortho, 640, 480, "p.png").is_ok());
    let e = check_aspect(&ortho, 480, 480, "p.png").unwrap_err().to_string();
    assert!(e.contains("480x480") && e.contains("1.3333"), "{e}");
}

#[test]
fn views_must_show_the_same_model() {
    let a = Scene::from_preset("sphere", "front-left").unwrap();
    let b = Scene::from_preset("sphere", "rim").unwrap();
    check_same_model(&a, "a.gltf", &b, "b.gltf").unwrap();
    let teapot = Scene::from_preset("teapot", "front-left").unwrap();
    let e = check_same_model(&a, "a.gltf", &teapot, "t.gltf").unwrap_err().to_string();
    assert!(e.contains("t.gltf") && e.contains("a.gltf") && e.contains("vertices"), "{e}");
    let mut moved = a.clone();
    moved.meshes[0].positions.iter_mut().for_each(|p| p.x += 0.5);
    let e = check_same_model(&a, "a.gltf", &moved, "m.gltf").unwrap_err().to_string();
    assert!(e.contains("bounds"), "{e}");
}

#[test]
fn paintings_without_usable_samples_are_errors_naming_the_file() {
    let mut sampler = SceneSampler::new().unwrap();
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::new(-0.5, 0.5, 1.0), [1.0; 3]));
    let g = sampler.geometry(&scene, 64, 64, Erosion::default()).unwrap();
    let base = Painting::opaque(64, 64, vec![[0.3, 0.2, 0.1]; 64 * 64]).unwrap();
    let err = |p: Painting| Samples::gather(&[view("p.png", g.clone(), p)]).unwrap_err().to_string();

    let mut transparent = base.clone();
    transparent.alpha.fill(0.0);
    let e = err(transparent);
    assert!(e.contains("p.png") && e.contains("transparent"), "{e}");

    // Painted only in a corner, off the sphere.
    let mut corner = base.clone();
    corner.alpha.iter_mut().enumerate().for_each(|(k, a)| *a = if k % 64 < 4 && k / 64 < 4 { 1.0 } else { 0.0 });
    let e = err(corner);
    assert!(e.contains("p.png") && e.contains("misses the object"), "{e}");

    let mut black = base.clone();
    black.pixels.fill([0.0; 3]);
    let e = err(black);
    assert!(e.contains("p.png") && e.contains("black"), "{e}");

    let mut white = base.clone();
    white.pixels.fill([1.0; 3]);
    white.saturated.fill(true);
    let e = err(white);
    assert!(e.contains("p.png") && e.contains("saturated"), "{e}");

    let small = Painting::opaque(32, 64, vec![[0.3; 3]; 32 * 64]).unwrap();
    let e = err(small);
    assert!(e.contains("p.png") && e.contains("32x64") && e.contains("64x64"), "{e}");

    // Partly black or saturated is fine, and unpainted pixels are not samples.
    let mut partial = base.clone();
    partial.pixels[..64 * 32].fill([0.0; 3]);
    partial.alpha[64 * 40..].fill(0.0);
    let s = Samples::gather(&[view("p.png", g.clone(), partial.clone())]).unwrap();
    assert_eq!(s.len(), (0..64 * 40).filter(|&k| g.usable[k]).count());
    assert!(s.origin.iter().all(|&(v, k)| v == 0 && k < 64 * 40));
}
