//! Reference shading, mask, outline, G-buffer and GGX passes against closed forms on
//! analytic spheres and a cube; bad input.

mod gl_common;

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{Analytic, SphereView};
use brdfpaint::factor::{CustomInput, Domain, Input, LogMap, Param};
use brdfpaint::gl::{header, HeadlessContext, Program};
use brdfpaint::render::mesh::{cube, uv_sphere};
use brdfpaint::material::{Factor, Term};
use brdfpaint::render::{Ggx, GpuScene, Mesh, OutlineStyle, ReferenceStyle, Renderer, MAX_TERMS};
use brdfpaint::scene::{Camera, CpuMesh, Light, Projection, Scene};
use gl_common::*;
use glam::{DVec3, Mat4, Vec3};

const RES: usize = 96;

fn setup() -> (HeadlessContext, Renderer) {
    let ctx = HeadlessContext::new().unwrap();
    let r = Renderer::new(ctx.gl()).unwrap();
    (ctx, r)
}

/// Distance in pixels of pixel (i, j)'s centre from the silhouette circle of the unit sphere
/// in an orthographic `res`² view with ymag = 1: negative inside.
fn circle_distance(res: usize, i: usize, j: usize) -> f64 {
    let half = res as f64 / 2.0;
    let (x, y) = (i as f64 + 0.5 - half, j as f64 + 0.5 - half);
    (x * x + y * y).sqrt() - half
}

/// Lambert + Phong in closed form at the analytic sphere, ortho view from +z.
#[test]
fn reference_shading_matches_lambert_phong_on_a_sphere() {
    let (ctx, mut r) = setup();
    let style = ReferenceStyle::default();
    let toward = DVec3::new(-0.5, 0.6, 0.8).normalize();
    let point = DVec3::new(1.5, 2.0, 2.5);
    for light in
        [sun(toward, [1.0, 0.9, 0.7]), Light::Point { position: point.as_vec3(), color: Vec3::ONE, intensity: 8.0 }]
    {
        let scene = ortho_sphere(DVec3::Z, light);
        let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
        let image = r.reference(&gpu, &style, RES, RES).unwrap();
        let (mut n_px, mut worst) = (0, 0.0f64);
        for j in 0..RES {
            for i in 0..RES {
                let got = image.at(i, j);
                let Some(n) = sphere_normal(DVec3::Z, RES, i, j) else {
                    if circle_distance(RES, i, j) > 0.05 {
                        assert_eq!(got, [0.0; 4], "background ({i}, {j})");
                    }
                    continue;
                };
                if n.z < 0.2 {
                    continue; // steep rim: tessellation error grows as 1/cos
                }
                // The sphere point is n itself (unit sphere at the origin).
                let (l, e) = match light {
                    Light::Directional { color, .. } => (toward, color.as_dvec3()),
                    Light::Point { intensity, .. } => {
                        let d = point - n;
                        (d.normalize(), DVec3::splat(intensity as f64 / d.length_squared()))
                    }
                };
                let v = DVec3::Z;
                let cos_l = n.dot(l);
                let rf = 2.0 * cos_l * n - l;
                let spec = if cos_l > 0.0 { rf.dot(v).max(0.0).powf(style.shininess as f64) } else { 0.0 };
                let want = [0, 1, 2].map(|c| {
                    style.ambient[c] as f64
                        + e[c] * (style.diffuse[c] as f64 * cos_l.max(0.0) + style.specular[c] as f64 * spec)
                });
                let err = rel_err(got, want, 1.0);
                assert!(err < 2e-3, "({i}, {j}) n {n}: GL {got:?} vs closed form {want:?}");
                assert_eq!(got[3], 1.0);
                worst = worst.max(err);
                n_px += 1;
            }
        }
        eprintln!("reference under {light:?}: {n_px} pixels, worst error {worst:.2e}");
        assert!(n_px > 5000);
    }
}

/// Mask against the analytic disc, orthographic: every pixel whose centre is more than
/// 0.05 px from the circle agrees (the 256-segment polygon lies within 0.004 px of it).
#[test]
fn mask_matches_the_analytic_disc_orthographic() {
    let (ctx, mut r) = setup();
    let camera = DVec3::new(0.2, -0.3, 0.9);
    let gpu = GpuScene::upload(ctx.gl(), &ortho_sphere(camera, sun(DVec3::Z, [1.0; 3]))).unwrap();
    let mask = r.mask(&gpu, RES, RES).unwrap();
    let (mut count, mut analytic) = (0, 0);
    for j in 0..RES {
        for i in 0..RES {
            let d = circle_distance(RES, i, j);
            let hit = mask.at(i, j)[0] == 1.0;
            if d.abs() > 0.05 {
                assert_eq!(hit, d < 0.0, "pixel ({i}, {j}) at {d:.3} px from the silhouette");
            }
            count += hit as usize;
            analytic += (d < 0.0) as usize;
        }
    }
    assert!(count.abs_diff(analytic) <= 2, "{count} vs {analytic}");
}

/// Perspective: the silhouette of a unit sphere seen from distance D is the cone of half
/// angle asin(1/D); a pixel centre's ray is inside it iff its tangent-plane offset is below
/// tan(asin(1/D)). Non-square image, so the aspect is exercised.
#[test]
fn mask_matches_the_analytic_cone_in_perspective() {
    let (ctx, mut r) = setup();
    let (w, h, yfov, dist) = (128usize, 96usize, 0.9f64, 3.0f64);
    let eye = DVec3::new(1.0, 2.0, 2.0).normalize() * dist;
    let gpu = GpuScene::upload(ctx.gl(), &perspective_sphere(eye, yfov as f32, sun(DVec3::Z, [1.0; 3]))).unwrap();
    let mask = r.mask(&gpu, w, h).unwrap();
    let tan_half = (yfov / 2.0).tan();
    let aspect = w as f64 / h as f64;
    let limit = (1.0 / dist).asin().tan();
    let px_per_unit = h as f64 / 2.0 / tan_half;
    let mut checked = 0;
    for j in 0..h {
        for i in 0..w {
            let x = (2.0 * (i as f64 + 0.5) / w as f64 - 1.0) * tan_half * aspect;
            let y = (1.0 - 2.0 * (j as f64 + 0.5) / h as f64) * tan_half;
            // Distance of the ray's image-plane point from the silhouette circle, in pixels
            // (approximately: the silhouette is a circle in the plane at unit distance).
            let d = ((x * x + y * y).sqrt() - limit) * px_per_unit;
            let hit = mask.at(i, j)[0] == 1.0;
            if d.abs() > 0.05 {
                assert_eq!(hit, d < 0.0, "pixel ({i}, {j}) at {d:.3} px");
                checked += 1;
            }
        }
    }
    assert!(checked > w * h - 100);
}

/// Row 0 is the top and +x is to the right: a small sphere at world (+1.5, +1, 0) seen
/// from +z appears in the upper right.
#[test]
fn images_are_upright() {
    let (ctx, mut r) = setup();
    let scene = Scene {
        meshes: vec![uv_sphere(Vec3::ZERO, 1.0, 64, 32), uv_sphere(Vec3::new(1.5, 1.0, 0.0), 0.3, 64, 32)],
        camera: Camera {
            world_from_camera: Mat4::from_translation(Vec3::new(0.0, 0.0, 5.0)),
            projection: Projection::Orthographic { xmag: 2.0, ymag: 2.0, znear: 0.1, zfar: 20.0 },
        },
        light: sun(DVec3::Z, [1.0; 3]),
    };
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let m = r.mask(&gpu, 100, 100).unwrap();
    // Small sphere centre: NDC (0.75, 0.5) -> pixel (87.5, 25).
    assert_eq!(m.at(87, 25)[0], 1.0);
    assert_eq!(m.at(87, 74)[0], 0.0, "not mirrored vertically");
    assert_eq!(m.at(12, 25)[0], 0.0, "not mirrored horizontally");
    assert_eq!(m.at(50, 50)[0], 1.0);
}

/// Every pass covers exactly the same pixels (the sampler gets the pixels the outline and
/// reference showed): a cube partly hiding a sphere, in perspective, non-square.
#[test]
fn all_passes_cover_the_same_pixels() {
    let (ctx, mut r) = setup();
    let scene = Scene {
        meshes: vec![uv_sphere(Vec3::ZERO, 1.0, 48, 24), cube(Vec3::new(0.8, -0.3, 1.2), 0.5)],
        camera: Camera {
            world_from_camera: looking_at_origin(DVec3::new(0.7, 0.9, 4.0)),
            projection: Projection::Perspective { yfov: 0.8, aspect: None, znear: 0.1, zfar: None },
        },
        light: Light::Point { position: Vec3::new(-2.0, 3.0, 3.0), color: Vec3::ONE, intensity: 20.0 },
    };
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let (w, h) = (120, 80);
    let shading = uniform(Term { base: None,
        factors: vec![random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 8), 1)],
        map: LogMap::Identity { floor: [1e-3; 3] },
        coefficients: None,
    });
    let covered =
        |im: &brdfpaint::render::Image, on: fn([f32; 4]) -> bool| im.pixels.iter().map(|&p| on(p)).collect::<Vec<_>>();
    let g = r.gbuffer(&gpu, w, h).unwrap();
    let hits: Vec<bool> = g.pixels.iter().map(|p| p.hit).collect();
    let alpha = |p: [f32; 4]| p[3] == 1.0;
    let white = |p: [f32; 4]| p[0] == 1.0;
    assert_eq!(covered(&r.mask(&gpu, w, h).unwrap(), white), hits, "mask");
    assert_eq!(covered(&r.reference(&gpu, &ReferenceStyle::default(), w, h).unwrap(), alpha), hits, "reference");
    assert_eq!(covered(&r.factored(&gpu, &r.upload(&shading).unwrap(), w, h).unwrap(), alpha), hits, "factored");
    assert_eq!(covered(&r.ggx(&gpu, &Ggx::default(), w, h).unwrap(), alpha), hits, "ggx");
    assert_eq!(g.mask().pixels.iter().map(|p| p[0] == 1.0).collect::<Vec<_>>(), hits);
    let n = hits.iter().filter(|&&x| x).count();
    assert!(n > 1500 && n < w * h / 2, "{n}");
    // The outline also has the cube's creases and its occlusion contour over the sphere:
    // more line pixels than the outer silhouette alone.
    let lines = g.lines(&OutlineStyle { width: 1, ..Default::default() });
    let silhouette = (0..w * h)
        .filter(|&k| {
            let (i, j) = (k % w, k / w);
            hits[k]
                && [(i.wrapping_sub(1), j), (i + 1, j), (i, j.wrapping_sub(1)), (i, j + 1)]
                    .iter()
                    .any(|&(x, y)| x >= w || y >= h || !hits[y * w + x])
        })
        .count();
    let total = lines.iter().filter(|&&x| x).count();
    assert!(total > silhouette + 20, "{total} lines, {silhouette} silhouette pixels");
}

/// Outline of a sphere: only the silhouette, on the boundary pixels (width 1), within 1 px
/// of the analytic circle; with width 2 also the background ring, still within 1 px.
#[test]
fn outline_of_a_sphere_is_its_silhouette() {
    let (ctx, mut r) = setup();
    let gpu = GpuScene::upload(ctx.gl(), &ortho_sphere(DVec3::new(0.3, 0.5, 0.8), sun(DVec3::Z, [1.0; 3]))).unwrap();
    for width in [1, 2] {
        let style = OutlineStyle { width, ..Default::default() };
        let page = r.outline(&gpu, &style, RES, RES).unwrap();
        let mut lines = 0;
        for j in 0..RES {
            for i in 0..RES {
                let d = circle_distance(RES, i, j);
                let line = page.at(i, j)[0] == 0.0;
                let p = page.at(i, j);
                assert!(p == [0.0, 0.0, 0.0, 1.0] || p == [1.0; 4], "black or white: {p:?}");
                if line {
                    lines += 1;
                    // A line pixel has a neighbour across the silhouette: within 1 px of it.
                    let (lo, hi) = if width == 1 { (-1.0, 0.05) } else { (-1.0, 1.0) };
                    assert!(
                        d > lo - 0.05 && d < hi + 0.05,
                        "width {width}: line at ({i}, {j}), {d:.3} px from the circle"
                    );
                } else if d < -0.05 {
                    // Inside pixels within 0.7 px of the circle have an outside 4-neighbour.
                    assert!(d < -0.75, "width {width}: missing line at ({i}, {j}), {d:.3} px inside");
                }
            }
        }
        // A digital circle's 8-connected boundary has ~2 sqrt(2)/pi = 0.90 pixels per unit
        // of circumference, per side.
        let circumference = std::f64::consts::PI * RES as f64;
        assert!(lines as f64 > 0.8 * width as f64 * circumference, "width {width}: {lines} line pixels");
        assert!((lines as f64) < 1.6 * width as f64 * circumference, "width {width}: {lines} line pixels");
    }
}

/// Outline of a cube seen along its diagonal: the three visible creases and no lines inside
/// the faces.
#[test]
fn outline_of_a_cube_has_its_creases() {
    let (ctx, mut r) = setup();
    let diag = DVec3::ONE.normalize();
    let scene = Scene {
        meshes: vec![cube(Vec3::ZERO, 1.0)],
        camera: Camera {
            world_from_camera: looking_at_origin(diag * 6.0),
            projection: Projection::Orthographic { xmag: 2.0, ymag: 2.0, znear: 0.1, zfar: 20.0 },
        },
        light: sun(diag, [1.0; 3]),
    };
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let n = 128;
    let page = r.outline(&gpu, &OutlineStyle { width: 1, ..Default::default() }, n, n).unwrap();
    let (right, up, _) = basis(diag);
    let to_pixel = |p: DVec3| {
        let (x, y) = (p.dot(right) / 2.0, p.dot(up) / 2.0);
        ((x + 1.0) / 2.0 * n as f64, (1.0 - y) / 2.0 * n as f64)
    };
    let line_near = |(x, y): (f64, f64), radius: i64| {
        let (ci, cj) = (x.floor() as i64, y.floor() as i64);
        (-radius..=radius)
            .any(|dj| (-radius..=radius).any(|di| page.at((ci + di) as usize, (cj + dj) as usize)[0] == 0.0))
    };
    let corner = DVec3::ONE;
    for end in [DVec3::new(1.0, 1.0, -1.0), DVec3::new(1.0, -1.0, 1.0), DVec3::new(-1.0, 1.0, 1.0)] {
        for k in 2..=8 {
            let p = corner.lerp(end, k as f64 / 10.0);
            assert!(
                line_near(to_pixel(p), 1),
                "crease {corner}-{end} at {k}/10: no line within 1 px of {:?}",
                to_pixel(p)
            );
        }
    }
    for face in [DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 1.0)] {
        // Face centre shifted off the creases: no line within 3 px.
        assert!(!line_near(to_pixel(face - 0.3 * (DVec3::ONE - face)), 3), "line inside face {face}");
    }
}

/// G-buffer against the analytic sphere: positions, normals, tangents, uv, local l and v.
#[test]
fn gbuffer_matches_the_analytic_sphere() {
    let (ctx, mut r) = setup();
    let camera = DVec3::new(0.3, 0.4, 0.87).normalize();
    let toward = DVec3::new(-0.6, 0.2, 0.5).normalize();
    let gpu = GpuScene::upload(ctx.gl(), &ortho_sphere(camera, sun(toward, [1.0; 3]))).unwrap();
    let g = r.gbuffer(&gpu, RES, RES).unwrap();
    let (mut worst_normal, mut n_px) = (0.0f64, 0);
    for j in 0..RES {
        for i in 0..RES {
            let px = g.at(i, j);
            let Some(n) = sphere_normal(camera, RES, i, j) else {
                assert!(!px.hit || circle_distance(RES, i, j) < 0.05);
                continue;
            };
            assert!(px.hit || circle_distance(RES, i, j) > -0.05, "({i}, {j}) not covered");
            let uv = SphereView::uv(n);
            if n.dot(camera) < 0.2 || n.y.abs() > 0.98 || uv.x < 0.02 || uv.x > 0.98 {
                continue;
            }
            let angle = px.normal.as_dvec3().angle_between(n);
            worst_normal = worst_normal.max(angle);
            // Tessellation: the ray meets the flat triangle up to sagitta / cos = 4e-4 away
            // from the sphere point; measured worst 6.9e-4 rad.
            assert!(angle < 1.5e-3, "({i}, {j}): normal {} vs {n}", px.normal);
            assert!((px.position.as_dvec3() - n).length() < 2e-3, "({i}, {j}): position {}", px.position);
            let (t, _, _) = SphereView::frame(n);
            assert!((px.tangent.truncate().as_dvec3() - t).length() < 2e-3 && px.tangent.w == 1.0);
            assert!((px.uv.as_dvec2() - uv).length() < 1e-3, "({i}, {j}): uv {} vs {uv}", px.uv);
            let q = SphereView::query(n, toward, camera);
            let got = px.query().unwrap();
            assert!((got.l - q.l).length() < 2e-3 && (got.v - q.v).length() < 2e-3, "({i}, {j}): {got:?} vs {q:?}");
            assert_eq!(px.falloff, 1.0);
            // Eye-space depth: the camera sits at 3·camera looking at the origin.
            assert!((px.depth as f64 - (3.0 - n.dot(camera))).abs() < 2e-3);
            assert!(px.face_normal.as_dvec3().angle_between(n) < 0.05);
            n_px += 1;
        }
    }
    eprintln!("G-buffer: {n_px} pixels, worst normal error {worst_normal:.2e} rad");
    assert!(n_px > 4000);
}

/// The analytic GGX shader against `brdf::Analytic::Ggx` at the G-buffer's samples.
#[test]
fn ggx_shader_matches_the_cpu_model() {
    let (ctx, mut r) = setup();
    let model = Ggx { diffuse: Vec3::new(0.45, 0.25, 0.12), f0: Vec3::new(0.9, 0.5, 0.04), roughness: 0.4 };
    let cpu = Analytic::Ggx { diffuse: [0.45, 0.25, 0.12], f0: [0.9, 0.5, 0.04], roughness: 0.4 };
    let scene = perspective_sphere(DVec3::new(0.5, 0.8, 3.5), 0.7, sun(DVec3::new(0.5, 0.3, 1.0), [1.0, 2.0, 3.0]));
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let image = r.ggx(&gpu, &model, RES, RES).unwrap();
    let g = r.gbuffer(&gpu, RES, RES).unwrap();
    let (mut n_px, mut worst) = (0, 0.0f64);
    for j in 0..RES {
        for i in 0..RES {
            let Some(q) = g.at(i, j).query() else { continue };
            let s = cpu.shading(&q);
            let want = [s[0], 2.0 * s[1], 3.0 * s[2]];
            let scale = want.iter().fold(0.1f64, |m, x| m.max(x.abs()));
            let e = rel_err(image.at(i, j), want, scale);
            assert!(e < 1e-4, "({i}, {j}): GL {:?} vs CPU {want:?}", image.at(i, j));
            worst = worst.max(e);
            n_px += 1;
        }
    }
    eprintln!("GGX: {n_px} pixels, worst relative error {worst:.2e}");
    assert!(n_px > 3000);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let (ctx, mut r) = setup();
    let gl = ctx.gl();
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::Z, [1.0; 3]));
    let gpu = GpuScene::upload(gl, &scene).unwrap();
    let good = uniform(Term { base: None,
        factors: vec![random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 8), 1)],
        map: LogMap::Identity { floor: [1e-3; 3] },
        coefficients: None,
    });
    let sh = r.upload(&good).unwrap();
    for (w, h) in [(0, 0), (0, 16), (100_000, 100_000), (16, 100_000)] {
        assert!(r.factored(&gpu, &sh, w, h).is_err(), "{w}x{h}");
        assert!(r.gbuffer(&gpu, w, h).is_err(), "{w}x{h}");
        assert!(r.outline(&gpu, &OutlineStyle::default(), w, h).is_err(), "{w}x{h}");
    }
    // After errors the renderer still works.
    assert_eq!(r.factored(&gpu, &sh, 8, 8).unwrap().pixels.len(), 64);

    // Broken meshes.
    let mut m = uv_sphere(Vec3::ZERO, 1.0, 8, 4);
    m.indices.extend([0, 1, 9999]);
    assert!(matches!(Mesh::upload(gl, &m), Err(brdfpaint::Error::Input(_))));
    let m = CpuMesh {
        positions: vec![Vec3::ZERO; 3],
        normals: vec![Vec3::Z; 2],
        indices: vec![0, 1, 2],
        ..Default::default()
    };
    assert!(Mesh::upload(gl, &m).is_err());

    // Materials the renderer cannot draw.
    let custom = CustomInput { name: "mine".into(), project: std::sync::Arc::new(|_| [0.0, 0.0]) };
    let mut bad = good.clone();
    bad.terms[0].factors[0].spec.input = Input::Custom(custom);
    assert!(r.upload(&bad).unwrap_err().to_string().contains("custom"));
    let too_many = map_of(vec![good.terms[0].clone(); MAX_TERMS + 1]);
    assert!(r.upload(&too_many).is_err());
    let mut nan = good.clone();
    nan.terms[0].factors[0].texels[3][1] = f32::NAN;
    assert!(r.upload(&nan).is_err());
    let short = uniform(Term { base: None,
        factors: vec![Factor {
            spec: spec(Input::Half, Param::Parabolic, Domain::Hemisphere, 8),
            texels: vec![[1.0; 3]; 8],
        }],
        ..good.terms[0].clone()
    });
    assert!(r.upload(&short).unwrap_err().to_string().contains("64 expected"));

    // Bad cameras and lights.
    let mut s = scene.clone();
    s.camera.world_from_camera = Mat4::ZERO;
    let g2 = GpuScene::upload(gl, &s).unwrap();
    assert!(r.factored(&g2, &sh, 8, 8).is_err());
    let mut s = scene.clone();
    s.light = Light::Directional { direction: Vec3::ZERO, color: Vec3::ONE, intensity: 1.0 };
    let g3 = GpuScene::upload(gl, &s).unwrap();
    assert!(r.reference(&g3, &ReferenceStyle::default(), 8, 8).is_err());

    // A shader that does not compile reports the stage, the log and the line.
    let vs = format!("{}void main() {{ gl_Position = vec4(0.0); }}\n", header(gl, &[]));
    let fs =
        format!("{}out vec4 o;\nvoid main() {{\n    o = texture(no_such_sampler, vec2(0.0));\n}}\n", header(gl, &[]));
    let e = Program::new(gl, "bad", &vs, &fs).err().expect("compile error").to_string();
    assert!(e.contains("fragment shader 'bad'") && e.contains("no_such_sampler"), "{e}");
}

/// A sheet drawn in bands (the scissored G-buffer and reference passes, the row-by-row line
/// tracer) is the sheet of the whole-image passes: the mask and lines of one full
/// `Renderer::gbuffer`, the reference of one full `Renderer::reference`, for bands of 1, 7
/// and 13 rows of a model with creases and occlusion contours, and a size that no band
/// height divides.
#[test]
fn a_sheet_drawn_in_bands_is_the_sheet_of_the_whole_image() {
    use brdfpaint::render::Sheet;
    let (ctx, mut r) = setup();
    let (w, h) = (90, 76);
    let scene = Scene::from_preset("suzanne", "front-left").unwrap();
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let g = r.gbuffer(&gpu, w, h).unwrap();
    let style = ReferenceStyle { exposure: brdfpaint::render::reference_exposure(&g, &scene.light), ..ReferenceStyle::default() };
    let reference: Vec<u8> = r
        .reference(&gpu, &style, w, h)
        .unwrap()
        .pixels
        .iter()
        .flat_map(|p| [p[0], p[1], p[2]].map(brdfpaint::images::encode_srgb8))
        .collect();
    let hit: Vec<bool> = g.pixels.iter().map(|p| p.hit).collect();
    let lines = g.lines(&OutlineStyle::default());
    assert!(lines.iter().filter(|&&l| l).count() > 100 && g.coverage() > 1000, "a picture with lines");
    for rows in [1, 7, 13, h] {
        let sheet = Sheet::render_in_bands(&mut r, &scene, w, h, rows).unwrap();
        assert_eq!((sheet.width, sheet.height, sheet.coverage), (w, h, g.coverage()), "bands of {rows}");
        assert!(sheet.hit == hit, "mask, bands of {rows}");
        assert!(sheet.lines == lines, "lines, bands of {rows}");
        assert!(sheet.reference == reference, "reference, bands of {rows}");
        // Code that clears and draws a target itself (the viewer, the stroke timing) must
        // not be clipped to the last band.
        // SAFETY: a state query on the current context.
        assert!(!unsafe { glow::HasContext::is_enabled(&**ctx.gl(), glow::SCISSOR_TEST) }, "scissor left on");
    }
}
