//! The factored-BRDF program against the CPU evaluation of the same tables
//! (`brdfpaint::factor`), pixel by pixel at pixel centres.

mod gl_common;

use brdfpaint::brdf::SphereView;
use brdfpaint::factor::{Domain, Input, LogMap, Param};
use brdfpaint::gl::{ApiPreference, DevicePreference, HeadlessContext};
use brdfpaint::material::{Coefficients, Factor, Material, Term};
use brdfpaint::render::{Ggx, GpuScene, Renderer};
use brdfpaint::scene::{Light, Scene};
use gl_common::*;
use glam::{DVec3, Vec3};

const RES: usize = 96;

fn identity() -> LogMap {
    LogMap::Identity { floor: [1e-3; 3] }
}

/// Renders `shading` and the G-buffer of `scene`; for every covered pixel compares the GL
/// value with `cpu_shading` at the G-buffer's (l, v, uv), times the light's colour ×
/// intensity and a falloff computed here from the G-buffer's world position. Returns the
/// worst error relative to max(|expected|, 1) and the number of pixels compared.
fn compare_at_gbuffer(scene: &Scene, shading: &Material, w: usize, h: usize) -> (f64, usize) {
    compare_with(&HeadlessContext::new().unwrap(), scene, shading, w, h)
}

fn compare_with(ctx: &HeadlessContext, scene: &Scene, shading: &Material, w: usize, h: usize) -> (f64, usize) {
    let mut r = Renderer::new(ctx.gl()).unwrap();
    compare_gl(&mut r, scene, shading, w, h, TABLE_TOL, "CPU", |q| cpu_shading(shading, q))
}

/// Scenes covering both camera kinds, both light kinds, lights below the horizon of part
/// of the sphere and grazing views.
fn scenes() -> Vec<(String, Scene, usize, usize)> {
    let point = Light::Point { position: Vec3::new(2.0, 1.5, 2.5), color: Vec3::new(1.0, 0.8, 0.6), intensity: 9.0 };
    vec![
        ("ortho, upper-left light".into(), ortho_sphere(DVec3::Z, sun(DVec3::new(-0.5, 0.5, 1.0), [1.0; 3])), RES, RES),
        (
            "ortho from the side, back light".into(),
            ortho_sphere(DVec3::new(0.6, 0.3, 0.75), sun(DVec3::new(0.2, -0.4, -1.0), [0.9, 1.1, 1.3])),
            RES,
            RES,
        ),
        ("perspective, point light".into(), perspective_sphere(DVec3::new(0.5, 0.8, 3.5), 0.7, point), RES + 32, RES),
    ]
}

/// Agreement of GL's float-texture filtering and f32 parameterizations with the f64 tables,
/// relative to max(|expected|, 1), on random tables whose neighbouring nodes differ by up
/// to 1. llvmpipe filters float textures with float weights; measured worst 1e-5 (f32
/// rounding of coordinates times the node step). Hardware with 8-bit filter fractions would
/// need ~4e-3 (1/256 of a node step).
const TABLE_TOL: f64 = 1e-4;

/// Render one identity-mapped product of `factors` in every test scene and compare it with
/// the CPU tables at the G-buffer's queries.
fn assert_tables_match(label: &str, factors: Vec<Factor>) {
    let shading = uniform(Term { base: None, factors, map: identity(), coefficients: None });
    for (name, scene, w, h) in scenes() {
        let (worst, n) = compare_at_gbuffer(&scene, &shading, w, h);
        eprintln!("{label} {name}: {n} pixels, worst relative error {worst:.2e}");
        assert!(n > 2000, "{label} {name}: {n} pixels, worst {worst:.2e}");
    }
}

#[test]
fn one_d_factors_match_the_cpu_tables_in_both_domains() {
    assert_tables_match("1D", vec![
            random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 33), 1),
            random_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 64), 2),
            random_factor(spec(Input::View, Param::Radius, Domain::Hemisphere, 17), 3),
        ]);
}

/// The half/difference factors (Rusinkiewicz 1998): a factor of $\theta_d$ and a 2D table of
/// $(\theta_h, \theta_d)$, beside a light factor, in every scene (back light and grazing views
/// included, where $\theta_d$ approaches 90°).
#[test]
fn half_difference_factors_match_the_cpu_tables() {
    assert_tables_match("half/difference", vec![
            random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 33), 41),
            random_factor(spec(Input::Difference, Param::Radius, Domain::Hemisphere, 29), 42),
            random_factor(spec(Input::HalfDifference, Param::Radii, Domain::Sphere, 24), 43),
        ]);
    assert_tables_match("half/difference, hemisphere", vec![
            random_factor(spec(Input::HalfDifference, Param::Radii, Domain::Hemisphere, 17), 44),
            random_factor(spec(Input::View, Param::Radius, Domain::Hemisphere, 9), 45),
        ]);
}

/// Warped radius tables (FactorSpec::warp): the shader's `pow` against the CPU's, on random
/// tables where a coordinate error shows as a jump between independent nodes.
#[test]
fn warped_radius_tables_match_the_cpu_tables() {
    let warped = |mut f: Factor, warp: f64| {
        f.spec.warp = warp;
        f
    };
    assert_tables_match("warped", vec![
            warped(random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 33), 51), 1.5),
            warped(random_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 128), 52), 3.0),
            warped(random_factor(spec(Input::HalfDifference, Param::Radii, Domain::Sphere, 24), 53), 2.0),
        ]);
}

/// Leaned half-vector tables (FactorSpec::lean): the shader's $h_k$ against the CPU's, nearer
/// the light, nearer the eye, and warped as well, on random tables where a wrong half vector
/// shows as a jump between independent nodes.
#[test]
fn leaned_half_tables_match_the_cpu_tables() {
    let leaned = |mut f: Factor, lean: f64, warp: f64| {
        f.spec.lean = lean;
        f.spec.warp = warp;
        f
    };
    assert_tables_match("leaned", vec![
            random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 33), 61),
            leaned(random_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 128), 62), 0.45, 3.0),
            leaned(random_factor(spec(Input::Half, Param::Parabolic, Domain::Hemisphere, 16), 63), 2.5, 1.0),
        ]);
}

#[test]
fn two_d_factors_match_the_cpu_tables() {
    assert_tables_match("2D", vec![
            random_factor(spec(Input::Light, Param::Parabolic, Domain::Sphere, 16), 4),
            random_factor(spec(Input::Half, Param::Hemispherical, Domain::Hemisphere, 24), 5),
            random_factor(spec(Input::View, Param::Parabolic, Domain::Hemisphere, 8), 6),
            random_factor(spec(Input::Uv, Param::Uv, Domain::Hemisphere, 32), 7),
        ]);
}

#[test]
fn sphere_domain_two_d_factors_and_hemispherical_light_match() {
    let shading = uniform(Term { base: None,
        factors: vec![
            random_factor(spec(Input::Light, Param::Hemispherical, Domain::Sphere, 20), 8),
            random_factor(spec(Input::Half, Param::Parabolic, Domain::Sphere, 12), 9),
            random_factor(spec(Input::View, Param::Radius, Domain::Sphere, 40), 10),
        ],
        map: identity(),
        coefficients: None,
    });
    let (_, scene, w, h) = scenes().remove(1);
    let (worst, n) = compare_at_gbuffer(&scene, &shading, w, h);
    assert!(n > 2000, "{n} pixels, worst {worst:.2e}");
}

/// The same comparison at the analytic sphere's geometry instead of the G-buffer's: what
/// the fit and the render of a sphere scene see independently. Smooth tables; the error is
/// the tessellation's (normals of a 256 x 128 sphere, ~1e-4 rad) times the tables' slope;
/// measured worst 1.8e-4, asserted 1e-3.
#[test]
fn factored_sphere_matches_the_analytic_sphere_at_pixel_centres() {
    let shading = uniform(Term { base: None,
        factors: vec![
            smooth_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 64)),
            smooth_factor(spec(Input::Half, Param::Parabolic, Domain::Hemisphere, 24)),
            smooth_factor(spec(Input::View, Param::Radius, Domain::Hemisphere, 32)),
            smooth_factor(spec(Input::Uv, Param::Uv, Domain::Hemisphere, 16)),
        ],
        map: identity(),
        coefficients: None,
    });
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let gpu_shading = r.upload(&shading).unwrap();
    for (camera, light) in
        [(DVec3::Z, DVec3::new(-0.5, 0.5, 1.0)), (DVec3::new(-0.3, 0.5, 0.8), DVec3::new(1.0, 0.2, -0.4))]
    {
        let scene = ortho_sphere(camera, sun(light, [1.0; 3]));
        let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
        let image = r.factored(&gpu, &gpu_shading, RES, RES).unwrap();
        let (mut worst, mut n) = (0.0f64, 0);
        for j in 0..RES {
            for i in 0..RES {
                let Some(normal) = sphere_normal(camera, RES, i, j) else { continue };
                // Stay 2 px inside the silhouette (interpolation there is steep) and off the
                // uv seam and poles, where u or the tangent jump.
                let rim = normal.dot(camera.normalize());
                let uv = SphereView::uv(normal);
                if rim < 0.3 || uv.x < 0.02 || uv.x > 0.98 || normal.y.abs() > 0.98 {
                    continue;
                }
                let q = SphereView::query(normal, light.normalize(), camera.normalize());
                let want = cpu_shading(&shading, &q);
                let e = rel_err(image.at(i, j), want, 1.0);
                assert!(e < 1e-3, "({i}, {j}): GL {:?} vs analytic {want:?}", image.at(i, j));
                worst = worst.max(e);
                n += 1;
            }
        }
        eprintln!("analytic sphere from {camera}: {n} pixels, worst error {worst:.2e}");
        assert!(n > 3000);
    }
}

/// Constant tables make the mapping inverses exact: product 0.8 per channel.
#[test]
fn mapping_inverses_offset_inverted_identity() {
    let constant = |value: f32| Factor {
        spec: spec(Input::Light, Param::Radius, Domain::Sphere, 4),
        texels: vec![[value; 3]; 4],
    };
    let cases = [
        (identity(), [0.8, 0.8, 0.8]),
        (LogMap::Offset { a: [0.1, 0.3, 1.0] }, [0.7, 0.5, 0.0]),
        (LogMap::Inverted { a: [1.0, 2.0, 0.5] }, [0.2, 1.2, 0.0]),
    ];
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::Z, [1.0, 2.0, 4.0]));
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    for (map, want) in cases {
        // Two factors whose product is 0.8: 2.0 x 0.4.
        let shading = uniform(Term { base: None, factors: vec![constant(2.0), constant(0.4)], map, coefficients: None });
        let image = r.factored(&gpu, &r.upload(&shading).unwrap(), 32, 32).unwrap();
        let centre = image.at(16, 16);
        for c in 0..3 {
            let expect = want[c] * [1.0, 2.0, 4.0][c];
            assert!((centre[c] as f64 - expect).abs() < 1e-5, "{map:?} channel {c}: {} vs {expect}", centre[c]);
            // And the CPU inverse agrees.
            assert!((map.inverse(c, 0.8).max(0.0) - want[c]).abs() < 1e-12);
        }
    }
}

/// Material map (thesis 4.2): two terms, coefficients split at u = 0.5.
#[test]
fn material_map_blends_two_terms_by_their_coefficients() {
    let constant = |rgb: [f32; 3]| Factor {
        spec: spec(Input::Light, Param::Radius, Domain::Sphere, 2),
        texels: vec![rgb; 2],
    };
    let n = 64;
    let left: Vec<f32> = (0..n * n).map(|k| if k % n < n / 2 { 1.0 } else { 0.0 }).collect();
    let right: Vec<f32> = left.iter().map(|c| 1.0 - c).collect();
    let red = [0.9, 0.1, 0.1];
    let blue = [0.1, 0.2, 0.8];
    let shading = map_of(vec![
            Term { base: None,
                factors: vec![constant(red)],
                map: identity(),
                coefficients: Some(Coefficients::grey(n, &left)),
            },
            Term { base: None,
                factors: vec![
                    constant(blue),
                    random_factor(spec(Input::View, Param::Radius, Domain::Hemisphere, 9), 11),
                ],
                map: LogMap::Offset { a: [0.01, 0.02, 0.03] },
                coefficients: Some(Coefficients::grey(n, &right)),
            },
    ]);
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::new(0.3, 0.2, 1.0), [1.0; 3]));
    let (worst, count) = compare_at_gbuffer(&scene, &shading, RES, RES);
    assert!(count > 5000, "{count} pixels, worst {worst:.2e}");

    // Away from the split each side is one term alone.
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let image = r.factored(&gpu, &r.upload(&shading).unwrap(), RES, RES).unwrap();
    let g = r.gbuffer(&gpu, RES, RES).unwrap();
    let (mut reds, mut blues) = (0, 0);
    for j in 0..RES {
        for i in 0..RES {
            let px = g.at(i, j);
            if !px.hit {
                continue;
            }
            let c = image.at(i, j);
            if px.uv.x < 0.45 {
                assert!(c.iter().take(3).zip(red).all(|(a, b)| (a - b).abs() < 1e-4), "red side ({i}, {j}): {c:?}");
                reds += 1;
            } else if px.uv.x > 0.55 {
                assert!(c[0] < 0.3 && c[2] > c[0], "blue side ({i}, {j}): {c:?}");
                blues += 1;
            }
        }
    }
    assert!(reds > 1000 && blues > 1000, "{reds} {blues}");
}

/// Each thread makes its own context; the images are identical and correct.
#[test]
fn contexts_on_parallel_threads_render_the_same_image() {
    let shading = uniform(Term { base: None,
        factors: vec![
            random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 33), 21),
            random_factor(spec(Input::Half, Param::Parabolic, Domain::Hemisphere, 16), 22),
        ],
        map: identity(),
        coefficients: None,
    });
    let images: Vec<Vec<[f32; 4]>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|_| {
                let shading = shading.clone();
                s.spawn(move || {
                    let ctx = HeadlessContext::new().unwrap();
                    let mut r = Renderer::new(ctx.gl()).unwrap();
                    let scene = ortho_sphere(DVec3::Z, sun(DVec3::new(-1.0, 1.0, 1.0), [1.0; 3]));
                    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
                    let sh = r.upload(&shading).unwrap();
                    let mut last = Vec::new();
                    for _ in 0..3 {
                        last = r.factored(&gpu, &sh, 64, 64).unwrap().pixels;
                    }
                    last
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for im in &images[1..] {
        assert_eq!(im, &images[0]);
    }
    assert!(images[0].iter().filter(|p| p[3] == 1.0).count() > 2500);
    // And one of them is right.
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::new(-1.0, 1.0, 1.0), [1.0; 3]));
    let (_, n) = compare_at_gbuffer(&scene, &shading, 64, 64);
    assert!(n > 1000, "{n} pixels");
}

/// The GLES 3.0 code path (same shaders with the `300 es` header) gives the same image as
/// desktop GL, and both match the CPU.
#[test]
fn gles_context_renders_like_desktop_gl() {
    let gles = match HeadlessContext::with_options(DevicePreference::Software, ApiPreference::Gles) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("skipped: no GLES context here ({e})");
            return;
        }
    };
    assert!(gles.is_gles(), "{gles:?}");
    let shading = map_of(vec![
            Term { base: None,
                factors: vec![
                    random_factor(spec(Input::Light, Param::Parabolic, Domain::Sphere, 16), 31),
                    random_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 40), 32),
                ],
                map: LogMap::Inverted { a: [3.0, 3.5, 4.0] },
                coefficients: Some(Coefficients::grey(2, &[0.2, 1.0, 0.5, 0.9])),
            },
            Term { base: None,
                factors: vec![random_factor(spec(Input::View, Param::Hemispherical, Domain::Hemisphere, 8), 33)],
                map: identity(),
                coefficients: None,
            },
    ]);
    let scene = perspective_sphere(DVec3::new(-0.5, 0.8, 3.0), 0.8, sun(DVec3::new(0.5, 0.5, 0.4), [1.0; 3]));
    let (worst, n) = compare_with(&gles, &scene, &shading, RES, RES);
    eprintln!("GLES ({}): {n} pixels, worst relative error {worst:.2e}", gles.version());
    assert!(n > 2000, "{n} pixels, worst {worst:.2e}");
    let image = |ctx: &HeadlessContext| {
        let mut r = Renderer::new(ctx.gl()).unwrap();
        let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
        r.factored(&gpu, &r.upload(&shading).unwrap(), RES, RES).unwrap()
    };
    let (a, b) = (image(&gles), image(&HeadlessContext::new().unwrap()));
    let diff =
        a.pixels.iter().zip(&b.pixels).flat_map(|(p, q)| (0..4).map(move |c| (p[c] - q[c]).abs())).fold(0.0, f32::max);
    assert!(diff < 1e-5, "GLES and GL differ by {diff}");
}

#[test]
fn frame_timing_reports_both_shaders() {
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::Z, [1.0; 3]));
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let shading = uniform(Term { base: None,
        factors: vec![
            random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 64), 1),
            random_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 64), 2),
            random_factor(spec(Input::View, Param::Radius, Domain::Hemisphere, 64), 3),
        ],
        map: identity(),
        coefficients: None,
    });
    let sh = r.upload(&shading).unwrap();
    let t = brdfpaint::study::bench::frame_times(&mut r, &gpu, &sh, &Ggx::default(), 64, 64, 5).unwrap();
    assert!(t.factored_ms > 0.0 && t.analytic_ms > 0.0 && t.ratio.is_finite(), "{t:?}");
    assert_eq!((t.frames, t.width, t.triangles), (5, 64, gpu.triangles()));
    assert!(brdfpaint::study::bench::frame_times(&mut r, &gpu, &sh, &Ggx::default(), 64, 64, 0).is_err());
}

/// `cargo test --release --test gl_factored -- --ignored --nocapture` prints the frame
/// times of the thesis's default material (three 1D factors) against GGX at 1024².
#[test]
#[ignore]
fn frame_times_at_1024() {
    let ctx = HeadlessContext::new().unwrap();
    eprintln!("{ctx:?}");
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let mut scene = perspective_sphere(DVec3::new(0.0, 0.0, 2.6), 0.9, sun(DVec3::new(-0.5, 0.5, 1.0), [1.0; 3]));
    // BENCH_SEGMENTS=64 makes the mesh light (4k triangles) so fragment cost dominates.
    if let Some(seg) = std::env::var("BENCH_SEGMENTS").ok().and_then(|s| s.parse::<usize>().ok()) {
        scene.meshes = vec![brdfpaint::render::mesh::uv_sphere(Vec3::ZERO, 1.0, seg, seg / 2)];
    }
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let one_d = uniform(Term { base: None,
        factors: vec![
            random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 64), 1),
            random_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 64), 2),
            random_factor(spec(Input::View, Param::Radius, Domain::Hemisphere, 64), 3),
        ],
        map: identity(),
        coefficients: None,
    });
    let two_d = uniform(Term { base: None,
        factors: vec![
            random_factor(spec(Input::Light, Param::Parabolic, Domain::Sphere, 24), 1),
            random_factor(spec(Input::Half, Param::Parabolic, Domain::Hemisphere, 24), 2),
            random_factor(spec(Input::View, Param::Parabolic, Domain::Hemisphere, 24), 3),
            random_factor(spec(Input::Uv, Param::Uv, Domain::Hemisphere, 32), 4),
        ],
        map: identity(),
        coefficients: None,
    });
    for (name, shading) in [("3x1D", one_d), ("3x2D+uv", two_d)] {
        let sh = r.upload(&shading).unwrap();
        let t = brdfpaint::study::bench::frame_times(&mut r, &gpu, &sh, &Ggx::default(), 1024, 1024, 30).unwrap();
        eprintln!("{name}: {t:?}");
    }
}

/// A term over an analytic base (issue 15, `brdf::lobe`) of each lobe family: the GLSL
/// lobe of `shaders/term.glsl` against `Base::shading` in f64 times the CPU tables, in every
/// test scene (back light and grazing views included, where the lobe's Fresnel, masking
/// and grazing rise matter). The lobe is evaluated in f32 on the GPU; measured worst 1.5e-5
/// relative to max(|expected|, 1) for GGX at α = 0.15, within the tables' tolerance; the
/// Blinn-Phong, Phong and Ashikhmin-Shirley widths give exponents 87, 8 and 20, Ward's a
/// narrow Gaussian, Minnaert's k = 0.75 a brightening limb; Oren-Nayar has no width.
#[test]
fn a_term_over_an_analytic_base_matches_the_cpu() {
    use brdfpaint::brdf::lobe::{Base, Lobe};
    let ctx = HeadlessContext::new().unwrap();
    for (lobe, alpha) in Lobe::ALL.into_iter().zip([0.15, 0.15, 0.45, 0.2, 0.3, 1.0, 0.75]) {
        let base = Base { ambient: [0.02, 0.03, 0.01], diffuse: [0.5, 0.3, 0.2], specular: [0.4, 0.5, 0.6], fresnel: [0.6, 0.5, 0.3], alpha, lobe };
        let factors = vec![
            random_factor(spec(Input::Light, Param::Radius, Domain::Sphere, 33), 7),
            random_factor(spec(Input::Half, Param::Radius, Domain::Sphere, 64), 8),
        ];
        let shading = uniform(Term { base: Some(base), factors, map: identity(), coefficients: None });
        let plain = uniform(Term { base: None, ..shading.terms[0].clone() });
        for (name, scene, w, h) in scenes() {
            let mut r = Renderer::new(ctx.gl()).unwrap();
            let expected = |q: &brdfpaint::factor::Query| {
                let (b, p) = (base.shading(q), cpu_shading(&plain, q));
                [0, 1, 2].map(|c| b[c] * p[c])
            };
            let (worst, n) = compare_gl(&mut r, &scene, &shading, w, h, TABLE_TOL, "CPU with base", expected);
            eprintln!("base {} {name}: {n} pixels, worst relative error {worst:.2e}", lobe.name());
            assert!(n > 2000, "{} {name}: {n} pixels, worst {worst:.2e}", lobe.name());
        }
    }
}
