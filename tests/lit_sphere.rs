//! Lit spheres and MatCaps (`brdfpaint fit --lit-sphere`): the disk is found and the key
//! light estimated on rendered analytic spheres (the truth known, lights behind the sphere
//! included; a sphere lit from behind relights from the front), every bundled MatCap gets a
//! material that darkens when the light goes behind, and bad pictures are refused in one
//! line.

mod sphere_common;
use sphere_common::sphere_picture;

use std::path::Path;
use std::process::Command;

use brdfpaint::brdf::{Analytic, Reflectance};
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::Painting;
use brdfpaint::litsphere::{estimate_light, find_disk, Outline};
use brdfpaint::material::Material;
use brdfpaint::render::{GpuScene, Renderer};
use brdfpaint::scene::{Light, Scene};
use glam::{DVec3, Vec3};

const MATCAPS: &str = "../shared/data/matcaps/blender_cc0/exr";

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_brdfpaint"));
    c.env("LIBGL_ALWAYS_SOFTWARE", "1").env("BRDFPAINT_CACHE", std::env::temp_dir().join("brdfpaint-test-cache"));
    c
}

#[test]
fn light_of_rendered_analytic_spheres_within_10_degrees() {
    let models = [
        Analytic::Lambert { albedo: [0.7, 0.45, 0.2] },
        Analytic::BlinnPhong { diffuse: [0.45, 0.25, 0.12], specular: [0.3, 0.35, 0.4], exponent: 32.0 },
        Analytic::Ggx { diffuse: [0.4, 0.25, 0.12], f0: [0.5, 0.42, 0.35], roughness: 0.3 },
        Analytic::Gooch { warm: [0.9, 0.6, 0.2], cool: [0.1, 0.2, 0.6] },
    ];
    // Upper left, side (76° from the view), top (73°), lower right.
    let lights = [DVec3::new(-0.5, 0.5, 1.0), DVec3::new(1.0, 0.0, 0.25), DVec3::new(0.0, 1.0, 0.3), DVec3::new(0.4, -0.3, 1.0)];
    let mut worst = 0.0f64;
    for model in &models {
        for &light in &lights {
            let picture = sphere_picture(model, light, 160, (240, 200), (50, 20));
            let (disk, outline) = find_disk(&picture, "sphere").unwrap();
            assert_eq!(outline, Outline::Background);
            assert!((disk.cx - 130.0).abs() < 1.5 && (disk.cy - 100.0).abs() < 1.5 && (disk.r - 80.0).abs() < 1.5, "{disk:?}");
            let e = estimate_light(&picture, &disk).unwrap();
            let angle = e.direction.angle_between(light.normalize()).to_degrees();
            eprintln!("{} light {light}: estimated {:.3} off by {angle:.1}° (spread {:.1}°)", model.name(), e.direction, e.spread_deg);
            assert!(angle < 10.0, "{}: light {light} estimated as {} ({angle:.1}° off)", model.name(), e.direction);
            worst = worst.max(angle);
        }
    }
    eprintln!("worst {worst:.1}°");
}

/// A key light with a size: an environment-lit MatCap's terminator is soft, and its fit
/// keeps it so. Before, the light prior's shape was a point light's $\max(\cos\theta_l, 0)$,
/// whose corner the light table took, and the re-render showed a dark crease along
/// $n \cdot l = 0$ that the picture does not have (the crease depth across it, 4° either
/// side, was 0.17 on ceramic_dark, 0.15 on jade and 0.30 on clay_muddy, the pictures'
/// 0.0005, 0.007 and 0.023). A sphere rendered under a point light keeps the point.
#[test]
fn an_environment_lit_matcap_has_no_crease_at_its_terminator() {
    use brdfpaint::brdf::SphereView;
    use brdfpaint::litsphere::{light_size, unlit_floor, Picture, ENVIRONMENT_KEY_DEG, LIGHT_FLOOR};
    let lum = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let dir = tempfile::tempdir().unwrap();
    for (stem, picture_crease) in [("ceramic_dark", 0.0005), ("jade", 0.0068), ("clay_muddy", 0.0229)] {
        let path = Path::new(MATCAPS).join(format!("{stem}.exr"));
        let out = dir.path().join(stem);
        let run = bin().args(["fit", "--lit-sphere"]).arg(&path).arg("--out").arg(&out).output().unwrap();
        assert!(run.status.success(), "{stem}: {}", String::from_utf8_lossy(&run.stderr));
        let picture = Picture::read(&path, 512).unwrap();
        let l = estimate_light(&picture.painting, &picture.disk).unwrap().direction;
        assert_eq!(light_size(unlit_floor(&picture.painting, &picture.disk, l).unwrap(), LIGHT_FLOOR), ENVIRONMENT_KEY_DEG, "{stem}");
        let material = Material::load(&out).unwrap();
        let s = |n: DVec3| lum(material.shading(&SphereView::query(n, l, DVec3::Z)));
        // The terminator's great circle, and the points 4° to either side of it.
        let t = l.cross(if l.z.abs() < 0.9 { DVec3::Z } else { DVec3::X }).normalize();
        let b = l.cross(t);
        let delta = 4f64.to_radians();
        let mut crease: Vec<f64> = (0..720)
            .filter_map(|k| {
                let phi = k as f64 / 720.0 * std::f64::consts::TAU;
                let n0 = t * phi.cos() + b * phi.sin();
                let side = |sign: f64| (n0 * delta.cos() + l * (sign * delta.sin())).normalize();
                let (np, nm) = (side(1.0), side(-1.0));
                (n0.z.min(np.z).min(nm.z) >= 0.3).then(|| 1.0 - s(n0) / (0.5 * (s(np) + s(nm))))
            })
            .collect();
        assert!(crease.len() > 100, "{stem}: the terminator is in view");
        crease.sort_by(f64::total_cmp);
        let median = crease[crease.len() / 2];
        eprintln!("{stem}: crease {median:.4} (the picture's {picture_crease})");
        assert!(median < picture_crease + 0.02, "{stem}: a crease of {median:.4} along the terminator, the picture's {picture_crease}");
    }
    // A Lambertian sphere rendered under a point light: its unlit side is black.
    let light = DVec3::new(1.0, 0.3, 0.4);
    let picture = sphere_picture(&Analytic::Lambert { albedo: [0.6, 0.5, 0.4] }, light, 160, (240, 200), (50, 20));
    let (disk, _) = find_disk(&picture, "sphere").unwrap();
    assert_eq!(light_size(unlit_floor(&picture, &disk, light.normalize()).unwrap(), LIGHT_FLOOR), 0.0);
}

/// The search reaches behind the sphere (all but 25° about straight behind, `MIN_LIGHT_Z`).
/// A Lambertian sphere rendered with a known light behind it (left, above right, below, and
/// 58° behind) is read as lit from there, and one in front near grazing as it is; the truths
/// are known independently of the estimator, so this fails if the search stops at the
/// hemisphere's edge or loses the light's side; and the estimate says which lights were behind.
#[test]
fn a_light_behind_the_sphere_is_found_behind_it() {
    use brdfpaint::litsphere::MIN_LIGHT_Z;
    let model = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
    let lights = [DVec3::new(-1.0, 0.2, -0.3), DVec3::new(0.8, 0.6, -0.4), DVec3::new(0.1, -1.0, -0.2), DVec3::new(0.9, 0.3, 0.2), DVec3::new(0.3, 0.4, -0.8)];
    let mut worst = 0.0f64;
    for light in lights {
        let picture = sphere_picture(&model, light, 160, (240, 200), (50, 20));
        let (disk, _) = find_disk(&picture, "sphere").unwrap();
        let e = estimate_light(&picture, &disk).unwrap();
        let angle = e.direction.angle_between(light.normalize()).to_degrees();
        eprintln!("light {light}: estimated {:.3}, off by {angle:.1}°", e.direction);
        assert!(e.direction.z >= MIN_LIGHT_Z - 1e-9, "light {light} estimated out of reach: {}", e.direction);
        assert_eq!(e.behind, light.z < 0.0, "light {light}: estimate {e:?}");
        assert!(!e.undecided && angle < 10.0, "light {light}: estimated {e:?}, {angle:.1}° off");
        worst = worst.max(angle);
    }
    eprintln!("worst {worst:.1}°");
}

/// A sphere lit from behind and by its surroundings (a Lambertian albedo under a light 40°
/// behind it, plus an even ambient light of 0.4, the truth known in closed form) relit from
/// the viewer: the fitted material's mean over the sphere within 15% of the truth's. The
/// unlit front the picture shows is the light prior's floor (`litsphere::light_floor`); the
/// default 2% floor fights that front and fails this (BENCHMARKS.md).
#[test]
fn a_sphere_lit_from_behind_relights_from_the_front_as_its_truth() {
    use brdfpaint::brdf::SphereView;
    const AMBIENT: f64 = 0.4;
    let albedo = [0.55, 0.4, 0.3];
    let behind = DVec3::new(0.5, 0.45, -0.64).normalize();
    let truth = |n: DVec3, l: DVec3| albedo.map(|a| a * (AMBIENT + n.dot(l).max(0.0)));
    let (w, h, res) = (200, 200, 160);
    let mut picture = Painting::opaque(w, h, vec![[1.0; 3]; w * h]).unwrap();
    for px in SphereView::new(behind, res).pixels() {
        picture.pixels[(20 + px.pixel[1]) * w + 20 + px.pixel[0]] = truth(px.normal, behind).map(|x| x as f32);
    }
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("behind.png");
    std::fs::write(&png, picture.encode_png16().unwrap()).unwrap();
    let lit = brdfpaint::litsphere::fit(&png, None, &Default::default(), None).unwrap();
    let e = lit.estimate.unwrap();
    assert!(e.behind && e.direction.angle_between(behind).to_degrees() < 10.0, "{e:?}");
    let (mut fitted, mut want) = (0.0, 0.0);
    for px in SphereView::new(DVec3::Z, res).pixels() {
        fitted += brdfpaint::images::luminance(lit.fitted.material.shading(&px.query));
        want += brdfpaint::images::luminance(truth(px.normal, DVec3::Z));
    }
    eprintln!("relit from the viewer: fitted/truth {:.3}", fitted / want);
    assert!((fitted / want - 1.0).abs() < 0.15, "relit from the viewer: fitted {fitted:.1} against the truth's {want:.1}");
}

/// Mean luminance of the object's pixels (alpha 1) of a render.
fn object_luminance(image: &brdfpaint::render::Image, w: usize, h: usize) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for j in 0..h {
        for i in 0..w {
            let p = image.at(i, j);
            if p[3] == 1.0 {
                sum += 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
                n += 1;
            }
        }
    }
    sum / n.max(1) as f64
}

#[test]
fn every_bundled_matcap_darkens_when_the_light_goes_behind() {
    // The issue asks for 0.5; README states 0.46 for every one of the 23 MatCaps (the fits
    // are deterministic: the reflection checks' 0.453 and 0.447 are the largest, see the end).
    const DARKEST: f64 = 0.46;
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let scene = Scene::from_preset("bunny", "front").unwrap();
    let mut gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let view = scene.camera.forward();
    let dir = tempfile::tempdir().unwrap();
    let mut names: Vec<_> = std::fs::read_dir(MATCAPS).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "exr")).collect();
    names.sort();
    assert_eq!(names.len(), 23, "{names:?}");
    let mut failures = Vec::new();
    for path in &names {
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let out = dir.path().join(&stem);
        let run = bin().args(["fit", "--lit-sphere"]).arg(path).arg("--out").arg(&out).output().unwrap();
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert!(run.status.success(), "{stem}: {}", String::from_utf8_lossy(&run.stderr));
        // "light estimated at (x, y, z)": printed for the record.
        let at = stdout.split("light estimated at (").nth(1).unwrap();
        let z: f64 = at.split(')').next().unwrap().split(',').nth(2).unwrap().trim().parse().unwrap();
        // A light sweep about the vertical axis: from the camera to behind the bunny.
        let material = Material::load(&out).unwrap();
        let shading = renderer.upload(&material).unwrap();
        let mut frames = Vec::new();
        for k in 0..8 {
            let a = std::f32::consts::TAU * k as f32 / 8.0;
            let towards = glam::Quat::from_rotation_y(a) * -view;
            gpu.light = Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 };
            let image = renderer.factored(&gpu, &shading, 128, 128).unwrap();
            frames.push(object_luminance(&image, 128, 128));
        }
        let (lo, hi) = frames.iter().fold((f64::MAX, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        eprintln!("{stem}: light z {z:.2}; sweep darkest/brightest {:.3}", lo / hi);
        if lo > DARKEST * hi {
            failures.push(format!("{stem}: darkest frame {lo:.4} > {DARKEST} x brightest {hi:.4}"));
        }
    }
    // Measured (darkest/brightest): the reflection checks 0.453 (vertical) and 0.447 (lit by an
    // environment, their light is undecided and taken as the plausible upper-front key,
    // z 0.52 and 0.36), resin 0.361, every other MatCap 0.28 or less. Before the lit-sphere light prior (litsphere::settings) three did
    // not darken to 0.5 (check_rim_dark 0.53, pearl 0.68, resin 0.67; the reflection checks
    // 0.62): lit from at or near the viewer, their pictures fix little more than the product
    // p q r along θ_l = θ_h = θ_v, and the Laplacian's split of it left p(θ_l) rising towards
    // grazing light (check_rim_dark) or flat and extrapolated past the horizon.
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn the_scene_written_beside_the_material_reproduces_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let model = Analytic::BlinnPhong { diffuse: [0.45, 0.25, 0.12], specular: [0.3, 0.35, 0.4], exponent: 32.0 };
    let picture = sphere_picture(&model, DVec3::new(-0.5, 0.5, 1.0), 120, (160, 140), (10, 12));
    let png = dir.path().join("sphere.png");
    std::fs::write(&png, picture.encode_png16().unwrap()).unwrap();
    let out = dir.path().join("mat");
    let run = bin().args(["fit", "--lit-sphere"]).arg(&png).arg("--out").arg(&out).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    for f in ["material.json", "report.png", "scene.gltf"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let render = dir.path().join("again.png");
    let run = bin().arg("render").arg(&out).arg("--scene").arg(out.join("scene.gltf")).args(["--size", "160x140", "--out"]).arg(&render).output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let again = Painting::read(&render).unwrap();
    // Inside the disk (away from its rim), the render of the fit is the picture.
    let (mut num, mut den) = (0.0, 0.0);
    for j in 0..140 {
        for i in 0..160 {
            let (x, y) = (i as f64 + 0.5 - 70.0, j as f64 + 0.5 - 72.0);
            if x * x + y * y < 55.0 * 55.0 {
                let k = j * 160 + i;
                for c in 0..3 {
                    num += (again.pixels[k][c] as f64 - picture.pixels[k][c] as f64).powi(2);
                    den += (picture.pixels[k][c] as f64).powi(2);
                }
            }
        }
    }
    let rel = (num / den).sqrt();
    assert!(rel < 0.08, "relative RMS of the re-render against the picture {rel:.4}");
}

#[test]
fn bad_pictures_get_one_line_each() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, p: &Painting| {
        let path = dir.path().join(name);
        std::fs::write(&path, p.encode_png16().unwrap()).unwrap();
        path
    };
    let blank = write("blank.png", &Painting::opaque(64, 48, vec![[0.3; 3]; 64 * 48]).unwrap());
    let lambert = Analytic::Lambert { albedo: [0.7, 0.45, 0.2] };
    let mut two = sphere_picture(&lambert, DVec3::Z, 40, (120, 60), (5, 10));
    let right = sphere_picture(&lambert, DVec3::Z, 40, (120, 60), (70, 10));
    for (a, b) in two.pixels.iter_mut().zip(&right.pixels) {
        *a = [0, 1, 2].map(|c| a[c].min(b[c]));
    }
    let two = write("two.png", &two);
    let mut nan = Vec::new();
    let exr = dir.path().join("nan.exr");
    {
        let mut p = sphere_picture(&lambert, DVec3::Z, 40, (50, 50), (5, 5));
        p.pixels[25 * 50 + 25] = [f32::NAN; 3];
        std::fs::write(&exr, p.encode_exr().unwrap()).unwrap();
        nan.push(exr.clone());
    }
    for (path, want) in [(&blank, "all background"), (&two, "two shapes"), (&exr, "NaN")] {
        let out = dir.path().join("out");
        let run = bin().args(["fit", "--lit-sphere"]).arg(path).arg("--out").arg(&out).output().unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{}: {stderr}", path.display());
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
        assert!(stderr.contains(want), "{}: {stderr}", path.display());
        assert!(!out.exists(), "nothing written");
    }
    let run = bin().args(["fit", "--lit-sphere"]).arg(&blank).args(["--light", "0,0,0", "--out"]).arg(dir.path().join("o")).output().unwrap();
    assert_eq!(run.status.code(), Some(2), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(Path::new(MATCAPS).exists());
}

/// The largest difference between two fits' tables, relative to the larger value.
fn table_difference(a: &[Vec<[f64; 3]>], b: &[Vec<[f64; 3]>]) -> f64 {
    assert_eq!(a.len(), b.len(), "factor count");
    let mut worst = 0.0f64;
    for (ta, tb) in a.iter().zip(b) {
        assert_eq!(ta.len(), tb.len(), "table size");
        for (x, y) in ta.iter().zip(tb) {
            for c in 0..3 {
                worst = worst.max((x[c] - y[c]).abs() / x[c].abs().max(y[c].abs()).max(1e-12));
            }
        }
    }
    worst
}

#[test]
fn dragging_the_light_of_a_live_lit_sphere_refits_as_fit_with_that_light() {
    use brdfpaint::factor::{Mapping, Settings};
    use brdfpaint::litsphere;
    use brdfpaint::live::{PaintSession, SphereSession};
    use brdfpaint::pipeline::Options;
    let path = Path::new(MATCAPS).join("clay_studio.exr");
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();

    // Opened: the light is `fit --lit-sphere`'s estimate, and the settled fit its material.
    let t = std::time::Instant::now();
    let mut sphere = SphereSession::open(&path, None).unwrap();
    let mut session = PaintSession::new(Settings::default(), Mapping::Auto);
    let k = sphere.start(&mut renderer, &mut session).unwrap();
    let opened = session.settle().unwrap();
    eprintln!("opened and fitted in {:.2} s ({} samples)", t.elapsed().as_secs_f64(), opened.samples);
    let cli = litsphere::fit(&path, None, &Options::default(), None).unwrap();
    // (The fit renders on a context of its own.)
    ctx.make_current().unwrap();
    assert_eq!(Some(sphere.light()), cli.estimate.map(|e| e.direction));
    assert_eq!(opened.samples, cli.fitted.samples.len());
    let d = table_difference(&session.fit().unwrap().tables, &cli.fitted.solved.fit.tables);
    assert!(d < 1e-9, "estimated light: live tables differ from fit's by {d:e}");

    // A drag: the light moves every few frames; each move only asks. The views under new
    // lights are rendered on a thread and prepared on another, so no frame waits for them.
    let target = DVec3::new(0.6, 0.3, 0.74).normalize();
    let start = sphere.light();
    let (mut applied, mut slowest) = (0, 0.0f64);
    for step in 1..=6 {
        sphere.set_light(start.lerp(target, step as f64 / 6.0)).unwrap();
        for _ in 0..8 {
            let frame = std::time::Instant::now();
            applied += sphere.update(&mut renderer, &mut session, k, true).unwrap() as usize;
            session.refit().unwrap();
            slowest = slowest.max(frame.elapsed().as_secs_f64());
            std::thread::sleep(std::time::Duration::from_millis(25));
        }
    }
    eprintln!("{applied} views under new lights put in place during the drag; slowest frame {slowest:.3} s");
    assert!(applied >= 1, "the fit followed the drag");
    // No frame waits for a render or a prepare; how long the slowest took is a benchmark
    // (BENCHMARKS.md, "Lit spheres and MatCaps"), printed above, not asserted.
    let t = std::time::Instant::now();
    sphere.settle(&mut renderer, &mut session, k).unwrap();
    eprintln!("refitted for the dropped light in {:.2} s", t.elapsed().as_secs_f64());
    assert!((sphere.light() - target).length() < 1e-12 && !sphere.waiting());
    let cli = litsphere::fit(&path, Some(target), &Options::default(), None).unwrap();
    let d = table_difference(&session.fit().unwrap().tables, &cli.fitted.solved.fit.tables);
    assert!(d < 1e-9, "dragged light: live tables differ from `fit --light`'s by {d:e}");
    let live = session.material().unwrap();
    let q = brdfpaint::factor::Query { l: target, v: DVec3::Z, uv: glam::DVec2::ZERO };
    let (a, b) = (live.shading(&q), cli.fitted.material.shading(&q));
    assert!((0..3).all(|c| (a[c] - b[c]).abs() <= 1e-9 * b[c].abs().max(1e-9)), "{a:?} vs {b:?}");

    // Dropped, the session has ended its render thread (and destroyed that thread's GL
    // context): one left to end by itself raced the process's exit, and Mesa's exit
    // handlers corrupted the heap (`viewer_ui` aborted after passing, about one run in 15).
    let render_threads = || {
        std::fs::read_dir("/proc/self/task")
            .map(|tasks| tasks.filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("comm")).ok()).filter(|c| c.trim() == "lit sphere view").count())
            .unwrap_or(0)
    };
    assert_eq!(render_threads(), 1, "the drag's render thread runs");
    drop(sphere);
    assert_eq!(render_threads(), 0, "the render thread outlived its session");
}

/// A toon picture opened live (the viewer's lit-sphere session) is read as `fit` reads it by
/// default: stylized, lit from its tone edges, and the settled live fit is `fit`'s (the
/// robust solve of the stylized settings).
#[test]
fn a_live_toon_lit_sphere_is_read_as_drawn_as_fit_reads_it() {
    use brdfpaint::factor::{Mapping, Settings};
    use brdfpaint::litsphere;
    use brdfpaint::live::{PaintSession, SphereSession};
    use brdfpaint::pipeline::Options;
    let path = Path::new(MATCAPS).join("toon.exr");
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let mut sphere = SphereSession::open(&path, None).unwrap();
    assert!(sphere.stylization.stylized, "{:?}", sphere.stylization);
    let mut session = PaintSession::new(Settings::default(), Mapping::Auto);
    let k = sphere.start(&mut renderer, &mut session).unwrap();
    sphere.settle(&mut renderer, &mut session, k).unwrap();
    let cli = litsphere::fit(&path, None, &Options::default(), None).unwrap();
    ctx.make_current().unwrap();
    assert!(cli.stylization.stylized);
    assert_eq!(Some(sphere.light()), cli.estimate.map(|e| e.direction));
    let d = table_difference(&session.fit().unwrap().tables, &cli.fitted.solved.fit.tables);
    assert!(d < 1e-9, "live tables differ from fit's by {d:e}");
}
