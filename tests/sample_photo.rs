//! Photographs with known normals: geometry against the analytic sphere and the renderer's
//! G-buffer, normal-map files, and a BRDF recovered from photographs of an analytic sphere,
//! judged on held-out lights and views.

mod gl_common;

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{held_out_views, Analytic, SphereView};
use brdfpaint::study::sphere_rms;
use brdfpaint::factor::{Mapping, Settings};
use brdfpaint::images::Painting;
use brdfpaint::material::{Material, Provenance};
use brdfpaint::pipeline::solve as fit;
use brdfpaint::sample::{Erosion, NormalMap, Photo, PhotoCamera, PhotoLight, Samples, SceneSampler};
use glam::{DMat3, DVec3};
use gl_common::*;

/// The unit sphere's normal at pixel (i, j) of an orthographic `res`² view from `camera`
/// (world space), as `SphereView` places it.
fn sphere_map(camera: DVec3, res: usize) -> NormalMap {
    NormalMap::from_fn(res, res, |i, j| sphere_normal(camera, res, i, j)).unwrap()
}

/// The camera basis of SphereView as a rotation from camera space to world.
fn camera_rotation(camera: DVec3) -> DMat3 {
    let (r, u, b) = basis(camera);
    DMat3::from_cols(r, u, b)
}

#[test]
fn a_world_space_orthographic_photo_matches_sphere_view_queries() {
    let camera = DVec3::new(0.3, 0.4, 0.87).normalize();
    let photo = Photo { normals: sphere_map(camera, 64), camera: PhotoCamera::Orthographic, camera_to_frame: camera_rotation(camera) };
    let light = PhotoLight { direction: DVec3::new(-0.6, 0.2, 0.5), rgb: [1.0, 2.0, 3.0] };
    let g = photo.geometry(&light, Erosion::default()).unwrap();
    let mut n = 0;
    for j in 0..64 {
        for i in 0..64 {
            let k = j * 64 + i;
            if !g.usable[k] {
                continue;
            }
            let normal = sphere_normal(camera, 64, i, j).unwrap();
            let want = SphereView::query(normal, light.direction.normalize(), camera);
            let q = g.pixels[k].unwrap().query;
            assert!((q.l - want.l).length() < 1e-12 && (q.v - want.v).length() < 1e-12, "({i}, {j})");
            assert_eq!(q.uv, glam::DVec2::new((i as f64 + 0.5) / 64.0, (j as f64 + 0.5) / 64.0));
            n += 1;
        }
    }
    // pi (32 - 1)^2 = 3019 pixels inside the eroded disc.
    assert!((n as f64 - 3019.0).abs() < 80.0, "{n}");
}

/// A world-space normal map read off the G-buffer of a perspective scene, with the scene's
/// camera as a perspective photograph: the photo's l and v are the renderer's.
#[test]
fn a_perspective_photo_agrees_with_the_renderer() {
    let res = 80;
    let eye = DVec3::new(0.5, 0.8, 3.5);
    let toward = DVec3::new(0.5, 0.3, 1.0).normalize();
    let scene = perspective_sphere(eye, 0.7, sun(toward, [1.0; 3]));
    let mut sampler = SceneSampler::new().unwrap();
    let gbuffer = sampler.gbuffer(&scene, res, res).unwrap();
    let normals = NormalMap::from_fn(res, res, |i, j| {
        let p = gbuffer.at(i, j);
        p.hit.then(|| p.normal.as_dvec3())
    })
    .unwrap();
    let rotation = glam::Mat3::from_mat4(scene.camera.world_from_camera).as_dmat3();
    let photo = Photo { normals, camera: PhotoCamera::Perspective { yfov: 0.7 }, camera_to_frame: rotation };
    let g = photo.geometry(&PhotoLight { direction: toward, rgb: [1.0; 3] }, Erosion::default()).unwrap();
    let mut n = 0;
    for j in 0..res {
        for i in 0..res {
            let k = j * res + i;
            if !g.usable[k] {
                continue;
            }
            let (got, want) = (g.pixels[k].unwrap().query, gbuffer.at(i, j).query().unwrap());
            // Same normal; the view ray through the pixel centre is the renderer's eye - p
            // (up to f32 positions); the frames agree away from the poles.
            assert!((got.v.z - want.v.z).abs() < 1e-4 && (got.l.z - want.l.z).abs() < 1e-5, "({i}, {j}) {got:?} vs {want:?}");
            if gbuffer.at(i, j).normal.y.abs() < 0.98 {
                assert!((got.v - want.v).length() < 2e-3 && (got.l - want.l).length() < 2e-3, "({i}, {j})");
            }
            n += 1;
        }
    }
    assert!(n > 1500, "{n}");
}

#[test]
fn normal_maps_read_from_exr_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let map = sphere_map(DVec3::Z, 32);
    // EXR: components as stored; background alpha 0.
    let exr = Painting {
        width: 32,
        height: 32,
        pixels: map.normals.iter().map(|n| n.map_or([0.0; 3], |n| n.as_vec3().to_array())).collect(),
        alpha: map.normals.iter().map(|n| if n.is_some() { 1.0 } else { 0.0 }).collect(),
        saturated: vec![false; 32 * 32],
    };
    // Negative components go through encode_exr unchanged (the painting decoder would
    // refuse them; the normal-map reader takes them).
    let path = dir.path().join("n.exr");
    std::fs::write(&path, exr.encode_exr().unwrap()).unwrap();
    let back = NormalMap::read(&path).unwrap();
    for (a, b) in map.normals.iter().zip(&back.normals) {
        match (a, b) {
            (Some(a), Some(b)) => assert!((*a - *b).length() < 1e-6),
            (None, None) => {}
            _ => panic!("coverage differs"),
        }
    }
    // PNG, 16 bit: c = (n + 1) / 2, raw codes; black background.
    let raw: Vec<u16> = map
        .normals
        .iter()
        .flat_map(|n| match n {
            Some(n) => [n.x, n.y, n.z].map(|x| ((x + 1.0) / 2.0 * 65535.0).round() as u16),
            None => [0; 3],
        })
        .collect();
    let path = dir.path().join("n.png");
    image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(32, 32, raw).unwrap().save(&path).unwrap();
    let back = NormalMap::read(&path).unwrap();
    for (a, b) in map.normals.iter().zip(&back.normals) {
        match (a, b) {
            (Some(a), Some(b)) => assert!((*a - *b).length() < 1e-4),
            (None, None) => {}
            _ => panic!("coverage differs"),
        }
    }
    // A mask removes more.
    let mut mask = Painting::opaque(32, 32, vec![[1.0; 3]; 32 * 32]).unwrap();
    mask.pixels[..32 * 16].fill([0.0; 3]);
    let masked = back.clone().masked(&mask, "mask.png").unwrap();
    assert!(masked.normals[..32 * 16].iter().all(Option::is_none));
    assert_eq!(masked.normals[32 * 16..], back.normals[32 * 16..]);
    let e = back.masked(&Painting::opaque(8, 8, vec![[1.0; 3]; 64]).unwrap(), "mask.png").unwrap_err().to_string();
    assert!(e.contains("mask.png") && e.contains("8x8"), "{e}");
    std::fs::write(dir.path().join("bad.png"), b"\x89PNG\r\n\x1a\n garbage").unwrap();
    let e = NormalMap::read(&dir.path().join("bad.png")).unwrap_err().to_string();
    assert!(e.contains("bad.png"), "{e}");
}

/// Photographs of an analytic sphere under three lights (16-bit PNG and EXR, light
/// colours divided out) recover the BRDF on held-out lights and views.
#[test]
fn photographs_of_an_analytic_sphere_recover_the_brdf() {
    let dir = tempfile::tempdir().unwrap();
    let res = 128;
    let photo = Photo::view_space(sphere_map(DVec3::Z, res), PhotoCamera::Orthographic);
    let lights = [
        PhotoLight { direction: DVec3::new(-0.5, 0.5, 1.0), rgb: [1.0, 0.8, 0.6] },
        PhotoLight { direction: DVec3::new(0.8, 0.3, 0.5), rgb: [0.5, 0.5, 0.5] },
        PhotoLight { direction: DVec3::new(0.1, -0.4, 0.9), rgb: [0.6, 0.7, 0.9] },
    ];
    let settings = Settings::default();
    // (model, bound on held-out relative RMS): measured 0.0003 (Lambert), 0.0029
    // (Blinn-Phong 32), 0.047 (GGX 0.4), 0.032 (Oren-Nayar).
    let cases = [(0usize, 0.01), (2, 0.01), (5, 0.08), (8, 0.08)];
    let suite = Analytic::suite();
    for (index, bound) in cases {
        let model = &suite[index];
        // Expose each model so its brightest pixel is 0.95: a photograph does not clip.
        let peak = lights
            .iter()
            .flat_map(|light| {
                (0..res * res).filter_map(move |k| sphere_normal(DVec3::Z, res, k % res, k / res).map(|n| (light, n)))
            })
            .map(|(light, n)| {
                let q = SphereView::query(n, light.direction.normalize(), DVec3::Z);
                let s = model.shading(&q);
                (0..3).map(|c| s[c] * light.rgb[c]).fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        let exposed: Vec<PhotoLight> =
            lights.iter().map(|l| PhotoLight { rgb: l.rgb.map(|c| c * 0.95 / peak), ..*l }).collect();
        let mut views = Vec::new();
        for (k, light) in exposed.iter().enumerate() {
            // The photograph, computed independently of the sampler: S at SphereView's
            // query of each pixel centre, times the light.
            let l = light.direction.normalize();
            let mut image = Painting::opaque(res, res, vec![[0.0; 3]; res * res]).unwrap();
            for j in 0..res {
                for i in 0..res {
                    if let Some(n) = sphere_normal(DVec3::Z, res, i, j) {
                        let q = SphereView::query(n, l, DVec3::Z);
                        let s = model.shading(&q);
                        image.pixels[j * res + i] = [0, 1, 2].map(|c| (s[c] * light.rgb[c]) as f32);
                    }
                }
            }
            assert!(image.pixels.iter().flatten().all(|&x| x < 1.0), "{}: the PNG would clip", model.name());
            let path = dir.path().join(format!("{}-{k}.{}", model.name(), if k == 1 { "exr" } else { "png" }));
            image.write(&path).unwrap();
            let decoded = Painting::read(&path).unwrap();
            views.push(photo.view(light, decoded, &path.display().to_string(), Erosion::default()).unwrap());
        }
        let samples = Samples::gather(&views).unwrap();
        let fitted = fit(&samples, &settings, Mapping::Auto, None).unwrap();
        let material = Material::from_fit(&settings, &fitted.fit, Provenance::default()).unwrap();
        let e = sphere_rms(&held_out_views(48), |q| model.shading(q), |q| material.shading(q));
        eprintln!("{}: {} samples, train {:.4}, held-out {e:.4}", model.name(), samples.len(), fitted.fit.errors.rms_relative);
        assert!(e < bound, "{}: held-out relative RMS {e} (bound {bound})", model.name());
    }
    // The image must have the normal map's size.
    let small = Painting::opaque(8, 8, vec![[0.5; 3]; 64]).unwrap();
    let e = photo.view(&lights[0], small, "small.png", Erosion::default()).unwrap_err().to_string();
    assert!(e.contains("small.png") && e.contains("8x8"), "{e}");
}
