//! `brdfpaint sheet` and `brdfpaint render` as a user runs them, checked against
//! expectations computed here: the preset scene, closed-form shading at analytic sphere
//! points, projected cube edges, and `Material::eval`.

mod gl_common;
mod render_common;

use brdfpaint::brdf::Reflectance;
use std::path::Path;

use brdfpaint::brdf::SphereView;
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::{linear_to_srgb, srgb_to_linear, Rgb};
use brdfpaint::render::mesh::{cube, uv_sphere};
use brdfpaint::render::{GpuScene, ReferenceStyle, Renderer};
use brdfpaint::scene::{self, Camera, Light, Projection};
use render_common::{brdfpaint, fitted_material, listing, ok, s, write_scene};
use glam::{DVec3, Vec3};

/// 8-bit RGB codes of a PNG.
fn png(path: &Path) -> (usize, usize, Vec<[u8; 3]>) {
    let img = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).into_rgb8();
    (img.width() as usize, img.height() as usize, img.pixels().map(|p| p.0).collect())
}

/// The world-space ray through the centre of pixel (i, j) of a perspective camera at
/// `width` × `height` (aspect W/H, row 0 at the top): origin and unit direction.
fn pixel_ray(camera: &Camera, width: usize, height: usize, i: usize, j: usize) -> (DVec3, DVec3) {
    let Projection::Perspective { yfov, .. } = camera.projection else { panic!("perspective expected") };
    let t = (yfov as f64 / 2.0).tan();
    let aspect = width as f64 / height as f64;
    let x = (2.0 * (i as f64 + 0.5) / width as f64 - 1.0) * t * aspect;
    let y = (1.0 - 2.0 * (j as f64 + 0.5) / height as f64) * t;
    let m = camera.world_from_camera.as_dmat4();
    (m.transform_point3(DVec3::ZERO), m.transform_vector3(DVec3::new(x, y, -1.0)).normalize())
}

/// Where a ray first meets the sphere of `radius` at the origin.
fn hit_sphere(origin: DVec3, dir: DVec3, radius: f64) -> Option<DVec3> {
    let b = origin.dot(dir);
    let disc = b * b - (origin.length_squared() - radius * radius);
    (disc >= 0.0).then(|| origin + dir * (-b - disc.sqrt()))
}

/// Continuous image coordinates (pixel centres at +0.5) of a world point.
fn project(camera: &Camera, width: usize, height: usize, p: DVec3) -> (f64, f64) {
    let Projection::Perspective { yfov, .. } = camera.projection else { panic!("perspective expected") };
    let c = camera.world_from_camera.as_dmat4().inverse().transform_point3(p);
    let t = (yfov as f64 / 2.0).tan();
    let (x, y) = (c.x / -c.z / (t * width as f64 / height as f64), c.y / -c.z / t);
    ((x + 1.0) / 2.0 * width as f64, (1.0 - y) / 2.0 * height as f64)
}

/// Lambert + Phong of `ReferenceStyle::default()` in closed form (shaders/reference.frag).
fn lambert_phong(n: DVec3, l: DVec3, v: DVec3, e: [f64; 3]) -> [f64; 3] {
    let style = ReferenceStyle::default();
    let cos_l = n.dot(l);
    let r = 2.0 * cos_l * n - l;
    let spec = if cos_l > 0.0 { r.dot(v).max(0.0).powf(style.shininess as f64) } else { 0.0 };
    [0, 1, 2].map(|c| {
        style.ambient[c] as f64 + e[c] * (style.diffuse[c] as f64 * cos_l.max(0.0) + style.specular[c] as f64 * spec)
    })
}

/// The mask's boundary: covered pixels with an uncovered 4-neighbour (or on the image
/// border), and uncovered pixels with a covered 4-neighbour.
fn boundary(mask: &[bool], w: usize, h: usize) -> Vec<bool> {
    let mut b = vec![false; w * h];
    for j in 0..h {
        for i in 0..w {
            let k = j * w + i;
            let mut nb = vec![];
            if i > 0 {
                nb.push(k - 1);
            }
            if i + 1 < w {
                nb.push(k + 1);
            }
            if j > 0 {
                nb.push(k - w);
            }
            if j + 1 < h {
                nb.push(k + w);
            }
            let on_border = nb.len() < 4 && mask[k];
            b[k] = on_border || nb.iter().any(|&n| mask[n] != mask[k]);
        }
    }
    b
}

#[test]
fn sheet_round_trips_its_scene_and_its_images_agree_with_the_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sheet");
    let (w, h) = (160, 120);
    let stdout = ok(&["sheet", "--model", "sphere", "--preset", "front-left", "--size", "160x120", "--out", s(&out)]);
    assert!(stdout.contains("outline.png") && stdout.contains("fit --scene"), "{stdout}");
    let mut names: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    // The five files and the record of what brdfpaint wrote (README, "File access and outputs").
    assert_eq!(names, [".brdfpaint-owned", "mask.png", "outline.png", "page.png", "reference.png", "scene.gltf"]);
    assert_eq!(listing(dir.path()).len(), 7, "no temporary files left: {:?}", listing(dir.path()));
    // page.png: the outline's black lines, opaque, on a transparent layer.
    let page = image::open(out.join("page.png")).unwrap().into_rgba8();
    let (_, _, outline) = png(&out.join("outline.png"));
    assert_eq!(page.dimensions(), (w as u32, h as u32));
    for (p, o) in page.pixels().zip(&outline) {
        let line = o[0] < 128;
        assert_eq!(p.0, if line { [0, 0, 0, 255] } else { [0, 0, 0, 0] });
    }

    // scene.gltf is the preset scene framed at aspect W/H.
    let preset = scene::preset("front-left").unwrap();
    let want = scene::frame(scene::model_meshes("sphere").unwrap(), &preset, w as f32 / h as f32);
    let got = scene::load(out.join("scene.gltf")).unwrap();
    let close = |a: &[f32], b: &[f32], what: &str| {
        assert_eq!(a.len(), b.len(), "{what}");
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= 1e-6, "{what}: {x} vs {y}");
        }
    };
    close(&got.camera.world_from_camera.to_cols_array(), &want.camera.world_from_camera.to_cols_array(), "camera");
    let (
        Projection::Perspective { yfov: gy, aspect: ga, znear: gn, zfar: gf },
        Projection::Perspective { yfov, aspect, znear, zfar },
    ) = (got.camera.projection, want.camera.projection)
    else {
        panic!("perspective cameras expected")
    };
    close(&[gy, ga.unwrap(), gn, gf.unwrap()], &[yfov, aspect.unwrap(), znear, zfar.unwrap()], "projection");
    assert!((ga.unwrap() - w as f32 / h as f32).abs() < 1e-6);
    let (
        Light::Directional { direction: gd, color: gc, intensity: gi },
        Light::Directional { direction, color, intensity },
    ) = (got.light, want.light)
    else {
        panic!("directional lights expected")
    };
    close(
        &[gd.x, gd.y, gd.z, gc.x, gc.y, gc.z, gi],
        &[direction.x, direction.y, direction.z, color.x, color.y, color.z, intensity],
        "light",
    );
    assert_eq!(got.meshes.len(), want.meshes.len());
    for (a, b) in got.meshes.iter().zip(&want.meshes) {
        assert_eq!(a.indices, b.indices);
        let flat = |v: &[Vec3]| v.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
        close(&flat(&a.positions), &flat(&b.positions), "positions");
        close(&flat(&a.normals), &flat(&b.normals), "normals");
        let uv = |m: &scene::CpuMesh| m.uvs.as_ref().unwrap().iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>();
        close(&uv(a), &uv(b), "uvs");
    }

    // mask.png covers exactly the G-buffer's pixels.
    let (mw, mh, mask_px) = png(&out.join("mask.png"));
    assert_eq!((mw, mh), (w, h));
    assert!(mask_px.iter().all(|p| *p == [0; 3] || *p == [255; 3]), "mask is black and white");
    let mask: Vec<bool> = mask_px.iter().map(|p| p[0] == 255).collect();
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let g = r.gbuffer(&GpuScene::upload(ctx.gl(), &want).unwrap(), w, h).unwrap();
    assert_eq!(mask.iter().filter(|&&m| m).count(), g.coverage());
    for (k, px) in g.pixels.iter().enumerate() {
        assert_eq!(mask[k], px.hit, "mask pixel {k}");
    }
    // And the analytic sphere: pixel centres more than 0.5 px inside (outside) the
    // silhouette are covered (not covered).
    for j in 0..h {
        for i in 0..w {
            let (o, d) = pixel_ray(&want.camera, w, h, i, j);
            let inner = hit_sphere(o, d, 0.99).is_some();
            let outer = hit_sphere(o, d, 1.01).is_some();
            if inner || !outer {
                assert_eq!(mask[j * w + i], inner, "({i}, {j})");
            }
        }
    }

    // outline.png: black lines on white, exactly along the mask's boundary (a sphere has
    // no creases): every black pixel within 1 px of the boundary, every covered boundary
    // pixel black.
    let (_, _, outline_px) = png(&out.join("outline.png"));
    assert!(outline_px.iter().all(|p| *p == [0; 3] || *p == [255; 3]));
    let black: Vec<bool> = outline_px.iter().map(|p| p[0] == 0).collect();
    let edge = boundary(&mask, w, h);
    let near_edge = |i: usize, j: usize| {
        (j.saturating_sub(1)..(j + 2).min(h)).any(|y| (i.saturating_sub(1)..(i + 2).min(w)).any(|x| edge[y * w + x]))
    };
    let mut lines = 0;
    for j in 0..h {
        for i in 0..w {
            let k = j * w + i;
            if black[k] {
                assert!(near_edge(i, j), "outline pixel ({i}, {j}) is off the silhouette");
                lines += 1;
            }
            if edge[k] && mask[k] {
                assert!(black[k], "silhouette pixel ({i}, {j}) has no line");
            }
        }
    }
    assert!(lines > 400, "{lines} line pixels");

    // reference.png: Lambert + Phong under the preset's white light of intensity 1, so
    // exposure 1, at analytic sphere points away from the rim, after sRGB decoding.
    let (_, _, reference_px) = png(&out.join("reference.png"));
    let l = (-direction.as_dvec3()).normalize();
    let (mut checked, mut worst) = (0, 0.0f64);
    for (i, j) in [(80, 60), (60, 45), (70, 50), (100, 70), (55, 75), (90, 40), (110, 55), (80, 90)] {
        let (o, d) = pixel_ray(&want.camera, w, h, i, j);
        let p = hit_sphere(o, d, 1.0).expect("on the sphere");
        let v = (o - p).normalize();
        let want_rgb = lambert_phong(p, l, v, [1.0; 3]);
        let code = reference_px[j * w + i];
        for c in 0..3 {
            let decoded = srgb_to_linear(code[c] as f32 / 255.0) as f64;
            // Within one 8-bit step of the closed form, measured in encoded units.
            assert_within_one_code(code[c], want_rgb[c], || format!("({i}, {j}) channel {c}: decodes to {decoded}"));
            worst = worst.max((decoded - want_rgb[c]).abs());
        }
        checked += 1;
    }
    eprintln!("reference: {checked} points, worst linear difference {worst:.4}");
    assert!(worst <= 1.0 / 255.0 * 2.0);
    // The background is black.
    assert_eq!(reference_px[0], [0; 3]);
}

#[test]
fn sheet_reference_is_exposed_for_a_physical_point_light() {
    let dir = tempfile::tempdir().unwrap();
    let gltf = dir.path().join("s.gltf");
    // A 200 cd light 3.5 units from the surface: 16x brighter than a unit sun there.
    let light_at = DVec3::new(2.0, 3.0, 3.0);
    let light = Light::Point { position: light_at.as_vec3(), color: Vec3::new(1.0, 0.9, 0.8), intensity: 200.0 };
    let scene = write_scene(&gltf, uv_sphere(Vec3::ZERO, 1.0, 256, 128), DVec3::new(0.5, 0.6, 4.0), Some(1.0), light);
    let out = dir.path().join("sheet");
    let stdout = ok(&["sheet", "--scene", s(&gltf), "--size", "120x120", "--out", s(&out)]);
    // The brightest light on the object is at the sphere point nearest the light (it faces
    // the camera here): exposure = d_min^2 / (200 * max colour).
    let d_min = light_at.length() - 1.0;
    let exposure = d_min * d_min / 200.0;
    let printed: f64 = stdout.split("exposure ").nth(1).unwrap().split(')').next().unwrap().parse().unwrap();
    assert!((printed - exposure).abs() < 2e-3 * exposure, "printed {printed}, expected {exposure}");
    let (w, h, px) = png(&out.join("reference.png"));
    // Not saturated anywhere, and the brightest pixel is bright.
    let brightest = px.iter().flat_map(|p| p.iter().copied()).max().unwrap();
    assert!(brightest < 255 && brightest > 230, "brightest code {brightest}");
    let mut checked = 0;
    for j in (10..h).step_by(13) {
        for i in (10..w).step_by(13) {
            let (o, d) = pixel_ray(&scene.camera, w, h, i, j);
            let Some(p) = hit_sphere(o, d, 1.0) else { continue };
            let v = (o - p).normalize();
            if p.dot(v) < 0.3 {
                continue;
            }
            let to_light = light_at - p;
            let e = [1.0, 0.9, 0.8].map(|c| c * 200.0 / to_light.length_squared() * exposure);
            let want = lambert_phong(p, to_light.normalize(), v, e);
            for c in 0..3 {
                assert_within_one_code(px[j * w + i][c], want[c], || format!("({i}, {j}) channel {c}: closed form"));
            }
            checked += 1;
        }
    }
    assert!(checked > 20, "{checked}");
}

/// Distance from point p to segment ab in the image plane.
fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    ((p.0 - a.0 - t * dx).powi(2) + (p.1 - a.1 - t * dy).powi(2)).sqrt()
}

#[test]
fn sheet_outline_lies_on_the_projected_edges_of_a_cube() {
    let dir = tempfile::tempdir().unwrap();
    let gltf = dir.path().join("cube.gltf");
    let eye = DVec3::new(2.2, 1.8, 3.0);
    let (w, h) = (150, 120);
    let scene = write_scene(
        &gltf,
        cube(Vec3::ZERO, 0.5),
        eye,
        Some(1.25),
        gl_common::sun(DVec3::new(-0.3, 1.0, 0.5), [1.0; 3]),
    );
    let out = dir.path().join("sheet");
    ok(&["sheet", "--scene", s(&gltf), "--size", "150x120", "--out", s(&out)]);
    // The cube's edges whose faces are not both turned away from the camera: silhouette
    // and crease edges, every line the outline may draw.
    let mut edges = Vec::new();
    for a in 0..8u32 {
        for axis in 0..3 {
            if a & (1 << axis) != 0 {
                continue;
            }
            let corner = |k: u32| {
                DVec3::new(
                    [-0.5, 0.5][(k & 1) as usize],
                    [-0.5, 0.5][(k >> 1 & 1) as usize],
                    [-0.5, 0.5][(k >> 2 & 1) as usize],
                )
            };
            let (p, q) = (corner(a), corner(a | 1 << axis));
            let mid = 0.5 * (p + q);
            // The two faces at this edge have normals along the other two axes.
            let visible = (0..3).filter(|&o| o != axis).any(|o| {
                let mut n = DVec3::ZERO;
                n[o] = mid[o].signum();
                n.dot(eye - n * 0.5) > 0.0
            });
            if visible {
                edges.push((project(&scene.camera, w, h, p), project(&scene.camera, w, h, q)));
            }
        }
    }
    assert_eq!(edges.len(), 9, "a cube seen from a corner shows 9 edges");
    let (_, _, px) = png(&out.join("outline.png"));
    let black: Vec<bool> = px.iter().map(|p| p[0] == 0).collect();
    let dist = |i: usize, j: usize| {
        edges.iter().map(|&(a, b)| segment_distance((i as f64 + 0.5, j as f64 + 0.5), a, b)).fold(f64::MAX, f64::min)
    };
    let mut n = 0;
    for j in 0..h {
        for i in 0..w {
            if black[j * w + i] {
                let d = dist(i, j);
                assert!(d <= 1.0 + 1e-3, "outline pixel ({i}, {j}) is {d:.2} px from every cube edge");
                n += 1;
            }
        }
    }
    // And every edge is drawn: points along it (1 px from its ends) have a black pixel
    // within 1 px.
    for &(a, b) in &edges {
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let steps = (len * 2.0) as usize;
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            if t * len < 1.0 || (1.0 - t) * len < 1.0 {
                continue;
            }
            let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            let found = (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).any(|(i, j)| {
                black[j * w + i] && ((i as f64 + 0.5 - x).powi(2) + (j as f64 + 0.5 - y).powi(2)).sqrt() <= 1.0
            });
            assert!(found, "edge {a:?}-{b:?}: no line near ({x:.1}, {y:.1})");
        }
    }
    eprintln!("cube outline: {n} line pixels on {} edges", edges.len());
}

#[test]
fn sheet_over_an_earlier_sheet_keeps_other_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sheet");
    ok(&["sheet", "--model", "sphere", "--size", "40x40", "--out", s(&out)]);
    std::fs::write(out.join("painting.png"), b"my painting").unwrap();
    let before = std::fs::read(out.join("scene.gltf")).unwrap();
    ok(&["sheet", "--model", "sphere", "--preset", "back", "--size", "40x40", "--out", s(&out)]);
    assert_eq!(std::fs::read(out.join("painting.png")).unwrap(), b"my painting");
    assert_ne!(std::fs::read(out.join("scene.gltf")).unwrap(), before, "the scene was replaced");
    assert_eq!(listing(dir.path()).len(), 8, "{:?}", listing(dir.path()));
}

#[test]
fn render_exr_and_png_equal_material_eval_times_the_light() {
    let dir = tempfile::tempdir().unwrap();
    let (mat, material) = fitted_material(dir.path());
    let gltf = dir.path().join("s.gltf");
    let light_at = DVec3::new(2.0, 1.5, 2.5);
    let rgb = [1.0, 0.8, 0.6].map(|c| c * 9.0);
    let light = Light::Point { position: light_at.as_vec3(), color: Vec3::new(1.0, 0.8, 0.6), intensity: 9.0 };
    let (w, h) = (96, 72);
    let scene =
        write_scene(&gltf, uv_sphere(Vec3::ZERO, 1.0, 256, 128), DVec3::new(0.5, 0.8, 3.5), Some(96.0 / 72.0), light);
    let exr = dir.path().join("r.exr");
    let png_path = dir.path().join("r.png");
    // Default size: 512 high at the camera's aspect.
    ok(&["render", s(&mat), "--scene", s(&gltf), "--out", s(&exr)]);
    let big = Rgb::read_exr(&exr).unwrap();
    assert_eq!((big.width, big.height), (683, 512));
    ok(&["render", s(&mat), "--scene", s(&gltf), "--size", "96x72", "--out", s(&exr)]);
    ok(&["render", s(&mat), "--scene", s(&gltf), "--size", "96x72", "--out", s(&png_path)]);
    let image = Rgb::read_exr(&exr).unwrap();
    let (_, _, codes) = png(&png_path);
    assert_eq!((image.width, image.height), (w, h));
    let (mut n, mut worst) = (0, 0.0f64);
    for j in 0..h {
        for i in 0..w {
            let got = image.pixels[j * w + i];
            let (o, d) = pixel_ray(&scene.camera, w, h, i, j);
            let Some(p) = hit_sphere(o, d, 1.0) else {
                if hit_sphere(o, d, 1.02).is_none() {
                    assert_eq!(got, [0.0; 3], "background ({i}, {j})");
                    assert_eq!(codes[j * w + i], [0; 3]);
                }
                continue;
            };
            let v = (o - p).normalize();
            let uv = SphereView::uv(p);
            // Away from the rim (steep interpolation) and the uv seam and poles.
            if p.dot(v) < 0.3 || uv.x < 0.02 || uv.x > 0.98 || p.y.abs() > 0.98 {
                continue;
            }
            let to_light = light_at - p;
            let q = SphereView::query(p, to_light.normalize(), v);
            let s_val = material.shading(&q);
            let want = [0, 1, 2].map(|c| s_val[c] * rgb[c] / to_light.length_squared());
            for c in 0..3 {
                // The tessellated sphere's normals are within ~1e-4 rad of the analytic ones.
                let e = (got[c] as f64 - want[c]).abs() / want[c].abs().max(0.05);
                assert!(e < 2e-3, "({i}, {j}) channel {c}: EXR {} vs Material::eval x light {}", got[c], want[c]);
                worst = worst.max(e);
                assert_within_one_code(codes[j * w + i][c], want[c], || format!("({i}, {j}) channel {c}: PNG"));
            }
            n += 1;
        }
    }
    eprintln!("render: {n} pixels, worst relative error {worst:.2e}");
    assert!(n > 1500, "{n}");
}

#[test]
fn turntable_and_light_sweep_write_n_frames_that_agree() {
    let dir = tempfile::tempdir().unwrap();
    let (mat, _) = fitted_material(dir.path());
    let out = dir.path().join("frames");
    std::fs::create_dir(&out).unwrap();
    let common = ["--model", "sphere", "--preset", "front-left", "--size", "64x64"];
    let run = |extra: &[&str], name: &str| {
        let mut args = vec!["render", s(&mat)];
        args.extend(common);
        args.extend(extra);
        let path = out.join(name);
        args.extend(["--out", s(&path)]);
        ok(&args);
    };
    run(&[], "single.exr");
    run(&["--turntable", "4"], "t.exr");
    run(&["--light-sweep", "4"], "l.exr");
    let read = |name: &str| Rgb::read_exr(&out.join(name)).unwrap().pixels;
    let mut names: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    assert_eq!(
        names,
        [
            ".brdfpaint-owned",
            "l-000.exr",
            "l-001.exr",
            "l-002.exr",
            "l-003.exr",
            "single.exr",
            "t-000.exr",
            "t-001.exr",
            "t-002.exr",
            "t-003.exr"
        ]
    );
    let diff = |a: &[[f32; 3]], b: &[[f32; 3]]| {
        a.iter().zip(b).flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs())).fold(0.0f32, f32::max)
    };
    let single = read("single.exr");
    assert!(
        diff(&read("t-000.exr"), &single) < 1e-5 && diff(&read("l-000.exr"), &single) < 1e-5,
        "frame 0 is the scene as given"
    );
    for k in 1..4 {
        let (t, l) = (read(&format!("t-{k:03}.exr")), read(&format!("l-{k:03}.exr")));
        assert!(diff(&t, &single) > 0.05, "turntable frame {k} differs from frame 0");
        assert!(diff(&l, &single) > 0.05, "light-sweep frame {k} differs from frame 0");
        // Turning the camera by 90k degrees is turning the light by -90k degrees: the
        // sphere (64 segments) and a 1D (isotropic) material are symmetric under it.
        // Pixels on the silhouette may flip; all others agree.
        let mirrored = read(&format!("l-{:03}.exr", (4 - k) % 4));
        let off = t.iter().zip(&mirrored).filter(|(p, q)| (0..3).any(|c| (p[c] - q[c]).abs() > 1e-4)).count();
        assert!(off <= 8, "turntable frame {k} vs light sweep frame {}: {off} pixels differ", (4 - k) % 4);
    }
}

/// An 8-bit sRGB code within one step of the linear value `want` encoded, measured in
/// encoded units; `what` says where, for the message.
fn assert_within_one_code(code: u8, want: f64, what: impl Fn() -> String) {
    let step = (code as f64 / 255.0 - linear_to_srgb(want as f32) as f64).abs();
    assert!(step <= 1.0 / 255.0 + 1e-6, "{}: code {code} vs linear {want}", what());
}

/// `--uv` (one rule for `render`, `view` and the demo): by default a model without texture
/// coordinates gets a spherical projection, with a note; on the built-in sphere, whose own
/// layout is that projection, `--uv mesh` and `--uv spherical` draw the same picture; a box
/// projection draws another.
#[test]
fn uv_rule_projects_coordinates_where_a_model_has_none() {
    let dir = tempfile::tempdir().unwrap();
    let (_, base) = fitted_material(dir.path());
    // Coefficients that grow with u: the left and right of the picture differ.
    let mut m = base.clone();
    m.terms[0].coefficients = Some(brdfpaint::material::Coefficients::grey(2, &[0.1, 1.0, 0.1, 1.0]));
    let mat = dir.path().join("uv-mat");
    m.save(&mat).unwrap();
    let render = |extra: &[&str], name: &str| -> (String, Vec<[u8; 3]>) {
        let out = dir.path().join(name);
        let mut args = vec!["render", s(&mat), "--size", "48x48", "--out", s(&out)];
        args.extend_from_slice(extra);
        let (code, _, stderr) = brdfpaint(&args);
        assert_eq!(code, 0, "{args:?}: {stderr}");
        (stderr, png(&out).2)
    };
    let (note, bunny) = render(&["--model", "bunny"], "bunny.png");
    assert!(note.contains("spherical projection") && note.lines().count() == 1, "{note}");
    assert!(bunny.iter().any(|p| p[0] > 0), "the bunny is drawn");
    let (quiet, mesh) = render(&["--model", "sphere", "--uv", "mesh"], "mesh.png");
    assert!(quiet.is_empty(), "{quiet}");
    let (_, spherical) = render(&["--model", "sphere", "--uv", "spherical"], "spherical.png");
    let differ = |a: &[[u8; 3]], b: &[[u8; 3]]| a.iter().zip(b).filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 2)).count();
    // Pixels at the seam (u wraps) may differ.
    assert!(differ(&mesh, &spherical) <= 12, "{} pixels differ", differ(&mesh, &spherical));
    let (_, boxed) = render(&["--model", "sphere", "--uv", "box"], "box.png");
    assert!(differ(&mesh, &boxed) > 200, "a box projection is another layout");
    let (code, _, stderr) = brdfpaint(&["render", s(&mat), "--model", "sphere", "--uv", "cube", "--out", s(&dir.path().join("x.png"))]);
    assert_eq!((code, stderr.lines().count()), (2, 1), "{stderr}");
}
