//! The real window under Xvfb: `brdfpaint view MAT --model sphere --frames 5 --screenshot`
//! shows the object shaded as `Material::eval` predicts under the camera and light the viewer
//! reports, draws its egui panel, and the X server's own screenshot (xwd) shows the same
//! window. Skipped, with a message, where `xvfb-run` is missing (CI installs it: .ci/run).
#![cfg(feature = "viewer")]

use brdfpaint::brdf::Reflectance;
use std::path::{Path, PathBuf};
use std::process::Command;

use brdfpaint::factor::{Mapping, Settings};
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::linear_to_srgb;
use brdfpaint::render::{GpuScene, Renderer};
use brdfpaint::scene::{builtin_model, Camera, Light, Projection, Scene};
use brdfpaint::live::{PaintSession, PaintView};
use glam::{Mat4, Vec3};

fn have(tool: &str) -> bool {
    Command::new("sh").arg("-c").arg(format!("command -v {tool}")).output().is_ok_and(|o| o.status.success())
}

/// A material fitted to the example painting of a sphere, saved in `dir`.
fn fitted_material(dir: &Path) -> PathBuf {
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let mut session = PaintSession::new(Settings::default(), Mapping::Auto);
    let k = session.add_view(PaintView::standard(&mut renderer, "sphere", "front-left", 128).unwrap());
    let p = brdfpaint::live::example_painting(&session.views[k]);
    session.views[k].canvas.set_painting(&p).unwrap();
    session.settle().unwrap();
    let path = dir.join("mat");
    session.material().unwrap().save(&path).unwrap();
    path
}

#[derive(serde::Deserialize)]
struct Rect {
    x: i32,
    y: i32,
    width: i32,
    height: i32,
}

#[derive(serde::Deserialize)]
struct Info {
    window: [u32; 2],
    view_rect: Rect,
    panel_rect: Rect,
    world_from_camera: [f32; 16],
    yfov: f32,
    znear: f32,
    zfar: f32,
    light_direction: [f32; 3],
    light_color: [f32; 3],
    light_intensity: f32,
    model: String,
    background: [u8; 3],
    render_scale: f32,
}

/// Runs a shell script under a fresh Xvfb screen (1280×800), software GL, scale factor 1.
fn xvfb(script: &str) -> std::process::Output {
    Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24", "sh", "-c", script])
        .env("WINIT_X11_SCALE_FACTOR", "1")
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .output()
        .unwrap()
}

/// An XWD file (X Window Dump, ZPixmap, 24/32 bits per pixel) as RGB rows.
fn read_xwd(bytes: &[u8]) -> (usize, usize, Vec<[u8; 3]>) {
    let u = |k: usize| u32::from_be_bytes(bytes[4 * k..4 * k + 4].try_into().unwrap());
    let (header, format, width, height) = (u(0) as usize, u(2), u(4) as usize, u(5) as usize);
    let (byte_order, bpp, bytes_per_line) = (u(7), u(11) as usize, u(12) as usize);
    let masks = [u(14), u(15), u(16)];
    let ncolors = u(19) as usize;
    assert_eq!(format, 2, "ZPixmap");
    assert!(bpp == 32 || bpp == 24, "{bpp} bits per pixel");
    let data = &bytes[header + 12 * ncolors..];
    let step = bpp / 8;
    let mut out = Vec::with_capacity(width * height);
    for j in 0..height {
        for i in 0..width {
            let at = j * bytes_per_line + i * step;
            let mut raw = [0u8; 4];
            raw[..step].copy_from_slice(&data[at..at + step]);
            let p = if byte_order == 0 { u32::from_le_bytes(raw) } else { u32::from_be_bytes(raw) >> (8 * (4 - step)) };
            out.push(masks.map(|m| ((p & m) >> m.trailing_zeros()) as u8));
        }
    }
    (width, height, out)
}

#[test]
fn the_window_shows_the_material_as_evaluated_on_the_cpu() {
    if !have("xvfb-run") {
        eprintln!("SKIPPED the_window_shows_the_material_as_evaluated_on_the_cpu: xvfb-run is not installed (apt-get install xvfb xauth; .ci/run does)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let material_path = fitted_material(dir.path());
    let material = brdfpaint::material::Material::load(&material_path).unwrap();
    let shot = dir.path().join("shot.png");
    let xwd = dir.path().join("screen.xwd");
    let take_xwd = have("xwd");
    // The viewer holds its window for a while after the screenshot; the X server's own
    // screenshot is taken then.
    let script = format!(
        "'{bin}' view '{mat}' --model sphere --window 1024x640 --frames 5 --screenshot '{shot}' --hold {hold} & pid=$!\n\
         for i in $(seq 600); do [ -f '{json}' ] && break; sleep 0.1; done\n\
         sleep 1\n\
         {xwd}\n\
         wait $pid",
        bin = env!("CARGO_BIN_EXE_brdfpaint"),
        mat = material_path.display(),
        shot = shot.display(),
        json = shot.with_extension("json").display(),
        hold = if take_xwd { 4 } else { 0 },
        xwd = if take_xwd { format!("xwd -root -silent > '{}'", xwd.display()) } else { String::new() },
    );
    let out = xvfb(&script);
    assert!(
        out.status.success() && shot.exists(),
        "viewer under xvfb-run failed: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let info: Info = serde_json::from_slice(&std::fs::read(shot.with_extension("json")).unwrap()).unwrap();
    let image = image::open(&shot).unwrap().into_rgb8();
    assert_eq!([image.width(), image.height()], info.window);
    assert_eq!(info.window, [1024, 640], "the window has the size asked for");
    let px = |x: i32, y: i32| image.get_pixel(x as u32, y as u32).0;
    let r = &info.view_rect;
    assert!(r.width > 200 && r.height > 200, "the 3D view has room");

    // The egui panel is drawn: its region differs from the 3D view's background and has
    // text (many distinct colours).
    let p = &info.panel_rect;
    assert!(p.width > 100 && p.height > 300, "panel {}x{}", p.width, p.height);
    let mut colours = std::collections::HashSet::new();
    let mut differs = 0;
    for y in (p.y..p.y + p.height).step_by(3) {
        for x in (p.x..p.x + p.width).step_by(3) {
            let c = px(x, y);
            colours.insert(c);
            differs += (c != info.background) as usize;
        }
    }
    assert!(colours.len() > 20, "the panel shows widgets and text: {} colours", colours.len());
    assert!(differs > 1000, "the panel is not the view's background");

    // The object: G-buffer of the same camera and light, headless, at the view's size.
    let camera = Camera {
        world_from_camera: Mat4::from_cols_array(&info.world_from_camera),
        projection: Projection::Perspective {
            yfov: info.yfov,
            aspect: None,
            znear: info.znear,
            zfar: Some(info.zfar),
        },
    };
    let light = Light::Directional {
        direction: Vec3::from_array(info.light_direction),
        color: Vec3::from_array(info.light_color),
        intensity: info.light_intensity,
    };
    assert_eq!(info.model, "sphere");
    let scene = Scene { meshes: builtin_model("sphere").unwrap(), camera, light };
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let (w, h) = (r.width as usize, r.height as usize);
    let g = renderer.gbuffer(&gpu, w, h).unwrap();
    let covered = g.coverage();
    assert!(covered > w * h / 20, "the sphere covers {covered} of {} pixels", w * h);
    let mut visible = 0;
    for j in 0..h {
        for i in 0..w {
            if g.at(i, j).hit && px(r.x + i as i32, r.y + j as i32) != info.background {
                visible += 1;
            }
        }
    }
    assert!(visible as f64 > 0.98 * covered as f64, "object pixels differ from the background: {visible} of {covered}");
    let rgb = Vec3::from_array(info.light_color) * info.light_intensity;
    let (mut checked, mut close, mut worst) = (0, 0, (0, String::new()));
    for j in (4..h - 4).step_by(7) {
        for i in (4..w - 4).step_by(7) {
            let inner = (-2..=2).all(|dj: i32| (-2..=2).all(|di: i32| g.at((i as i32 + di) as usize, (j as i32 + dj) as usize).hit));
            let Some(q) = inner.then(|| g.at(i, j).query()).flatten() else { continue };
            let s = material.shading(&q);
            let want = [0, 1, 2].map(|c| (linear_to_srgb((s[c] as f32) * rgb[c] * g.at(i, j).falloff) * 255.0 + 0.5) as i32);
            let got = px(r.x + i as i32, r.y + j as i32);
            let err = (0..3).map(|c| (want[c] - got[c] as i32).abs()).max().unwrap();
            checked += 1;
            if err <= 3 {
                close += 1;
            }
            if err > worst.0 {
                worst = (err, format!("pixel ({i}, {j}): window {got:?}, Material::eval {want:?}"));
            }
        }
    }
    assert!(checked > 200, "{checked} pixels checked");
    // The light indicator and the label are drawn over the view: a few pixels may differ.
    assert!(close as f64 >= 0.97 * checked as f64, "{close} of {checked} pixels within 3 codes; worst {}", worst.1);

    // The X server's screenshot shows the same window.
    if !take_xwd {
        eprintln!("xwd is not installed (apt-get install x11-apps): the X screenshot check was skipped");
        return;
    }
    let (sw, sh, screen) = read_xwd(&std::fs::read(&xwd).unwrap());
    let (ww, wh) = (image.width() as usize, image.height() as usize);
    assert!(sw >= ww && sh >= wh, "screen {sw}x{sh}, window {ww}x{wh}");
    // Without a window manager the window sits at the origin; look around it anyway.
    let probe: Vec<(usize, usize)> = (0..400).map(|k| ((k * 7919) % ww, (k * 104_729) % wh)).collect();
    let mut best = (0, (0, 0));
    for oy in 0..=(sh - wh).min(64) {
        for ox in 0..=(sw - ww).min(64) {
            let hits = probe
                .iter()
                .filter(|&&(x, y)| {
                    let a = screen[(oy + y) * sw + ox + x];
                    let b = image.get_pixel(x as u32, y as u32).0;
                    (0..3).all(|c| (a[c] as i32 - b[c] as i32).abs() <= 2)
                })
                .count();
            if hits > best.0 {
                best = (hits, (ox, oy));
            }
        }
    }
    assert!(best.0 >= 390, "the X screenshot shows the window's pixels: {} of 400 at {:?}", best.0, best.1);
}

/// Runs the viewer on a material under Xvfb for a few frames and returns its screenshot
/// and what it reports.
fn screenshot(material: &Path, extra: &[&str], shot: &Path) -> (image::RgbImage, Info) {
    let args: Vec<String> = extra.iter().map(|a| format!("'{a}'")).collect();
    let script = format!(
        "'{bin}' view '{mat}' --model sphere --window 1024x640 --frames 5 --screenshot '{shot}' {args}",
        bin = env!("CARGO_BIN_EXE_brdfpaint"),
        mat = material.display(),
        shot = shot.display(),
        args = args.join(" "),
    );
    let out = xvfb(&script);
    assert!(out.status.success() && shot.exists(), "viewer failed: {}", String::from_utf8_lossy(&out.stderr));
    let info: Info = serde_json::from_slice(&std::fs::read(shot.with_extension("json")).unwrap()).unwrap();
    (image::open(shot).unwrap().into_rgb8(), info)
}

#[test]
fn a_material_map_keeps_the_view_and_a_reduced_render_scale_matches_full_scale() {
    if !have("xvfb-run") {
        eprintln!("SKIPPED a_material_map_keeps_the_view...: xvfb-run is not installed (apt-get install xvfb xauth; .ci/run does)");
        return;
    }
    // A material map of four terms (the striped test sphere): its twelve factor plots
    // overflow the tables panel's width.
    use brdfpaint::brdf::Striped;
    use brdfpaint::material::map::{self, MapOptions, Method};
    let (pattern, values, grids) = Striped::wood().paint(&Striped::painted_views(60));
    let prepared = brdfpaint::factor::prepare(&pattern, &Settings::default()).unwrap();
    let opts = MapOptions { terms: 4, min_gain: 0.0, method: Method::Greedy, coef_res: 64, ..Default::default() };
    let (material, _) = map::fit(&prepared, &pattern, &values, &grids, &opts).unwrap();
    assert_eq!(material.terms.len(), 4);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("map");
    material.save(&path).unwrap();

    let (full, info) = screenshot(&path, &[], &dir.path().join("full.png"));
    assert_eq!(info.render_scale, 1.0);
    // The tables panel keeps to its size: before, captions of the plots past the panel's
    // width wrapped word by word, the panel grew to its content and the 3D view was 63
    // pixels tall.
    let r = &info.view_rect;
    assert!(r.height as f64 > 0.6 * info.window[1] as f64, "the 3D view is {}x{} in a {:?} window", r.width, r.height, info.window);

    // At half the resolution, magnified: the same picture, softer.
    let (half, info_half) = screenshot(&path, &["--render-scale", "0.5"], &dir.path().join("half.png"));
    assert_eq!(info_half.render_scale, 0.5);
    assert_eq!((info_half.view_rect.width, info_half.view_rect.height), (r.width, r.height));
    let (mut total, mut close, mut n, mut same) = (0.0, 0, 0, 0);
    for y in r.y..r.y + r.height {
        for x in r.x..r.x + r.width {
            let (a, b) = (full.get_pixel(x as u32, y as u32).0, half.get_pixel(x as u32, y as u32).0);
            let d = (0..3).map(|c| (a[c] as i32 - b[c] as i32).abs()).max().unwrap();
            total += d as f64;
            close += (d <= 12) as usize;
            same += (d == 0) as usize;
            n += 1;
        }
    }
    let mean = total / n as f64;
    // Measured: mean 0.28 codes, 99.7% within 12 (the rest on the silhouette and the light
    // indicator); a misplaced or mis-scaled image differs by tens of codes over the object.
    assert!(mean < 1.5 && close as f64 > 0.98 * n as f64, "mean difference {mean:.2} codes, {close} of {n} within 12");
    assert!(same < n, "the reduced scale changed nothing: is it applied?");
}

#[test]
fn a_render_scale_outside_its_range_is_one_clear_line() {
    for bad in ["0.1", "1.5", "nan"] {
        let out = Command::new(env!("CARGO_BIN_EXE_brdfpaint")).args(["view", "--render-scale", bad, "--frames", "1"]).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.lines().count() == 1 && err.contains("render"), "{bad}: {err}");
    }
}

/// The viewer under a bundled environment, turned and exposed, shows what `render --env`
/// writes for the same material, camera, key light, rotation and exposure: the command line's
/// own path (a glTF scene of the viewer's camera and light, the PNG development) against the
/// window's (the 3D view's target, developed in the copy shader).
#[test]
fn the_window_under_an_environment_matches_render_env() {
    if !have("xvfb-run") {
        eprintln!("SKIPPED the_window_under_an_environment_matches_render_env: xvfb-run is not installed (apt-get install xvfb xauth; .ci/run does)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let material = fitted_material(dir.path());
    let env = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/hdri/city.exr");
    let view = ["--env", "city", "--env-rotate", "30", "--exposure", "0.5", "--render-scale", "1"];
    let render = ["--env", env.to_str().unwrap(), "--env-rotate", "30", "--exposure", "0.5"];
    let (image, info) = window_against_render(dir.path(), &material, &view, &render);
    // And the environment is really there: the view is not the viewer's flat background.
    let r = &info.view_rect;
    let flat = (0..r.width).step_by(5).filter(|&i| image.get_pixel((r.x + i) as u32, (r.y + r.height - 5) as u32).0 == info.background).count();
    assert!(flat < (r.width / 5) as usize / 2, "the bottom row shows the environment, not the flat background");
}

/// A material with the painting's detail (`fit --lit-sphere --texture keep`): the window
/// draws its strokes as `render` does.
#[test]
fn the_window_draws_a_kept_brush_texture_as_render_does() {
    if !have("xvfb-run") {
        eprintln!("SKIPPED the_window_draws_a_kept_brush_texture_as_render_does: xvfb-run is not installed (apt-get install xvfb xauth; .ci/run does)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let painting = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mypaint/paintings/lambert/front-left-oil-texture-s1.png");
    let ask = brdfpaint::litsphere::Ask { keep_texture: true, ..Default::default() };
    let lit = brdfpaint::litsphere::fit_in(&painting, &ask, &Default::default(), None).unwrap();
    assert!(lit.fitted.material.detail.is_some());
    let material = dir.path().join("kept");
    lit.fitted.material.save(&material).unwrap();
    window_against_render(dir.path(), &material, &["--render-scale", "1"], &[]);
}

/// Shows `material` on the sphere in the window (with `view_args`) and renders it with
/// `render` (with `render_args`) under the camera and light the window reports: 99% of the
/// pixels within 3 levels. The window's screenshot and report.
fn window_against_render(dir: &Path, material: &Path, view_args: &[&str], render_args: &[&str]) -> (image::RgbImage, Info) {
    let shot = dir.join("window.png");
    let (image, info) = screenshot(material, view_args, &shot);
    let r = &info.view_rect;
    let camera = Camera {
        world_from_camera: Mat4::from_cols_array(&info.world_from_camera),
        projection: Projection::Perspective { yfov: info.yfov, aspect: None, znear: info.znear, zfar: Some(info.zfar) },
    };
    let light = Light::Directional {
        direction: Vec3::from_array(info.light_direction),
        color: Vec3::from_array(info.light_color),
        intensity: info.light_intensity,
    };
    let scene = Scene { meshes: builtin_model("sphere").unwrap(), camera, light };
    let gltf = dir.join("view.gltf");
    scene.write_gltf(&gltf).unwrap();
    let out = dir.join("render.png");
    let size = format!("{}x{}", r.width, r.height);
    // Without an environment the window's background is its own flat colour.
    let b = info.background;
    let background = ["--background".to_string(), format!("#{:02x}{:02x}{:02x}", b[0], b[1], b[2])];
    let background = if render_args.contains(&"--env") { &[][..] } else { &background[..] };
    let run = Command::new(env!("CARGO_BIN_EXE_brdfpaint"))
        .args(["render".as_ref(), material.as_os_str(), "--scene".as_ref(), gltf.as_os_str(), "--size".as_ref(), size.as_ref()])
        .args(render_args)
        .args(background)
        .args(["--out".as_ref(), out.as_os_str()])
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .output()
        .unwrap();
    assert!(run.status.success(), "render failed: {}", String::from_utf8_lossy(&run.stderr));
    let want = image::open(&out).unwrap().into_rgb8();
    // The egui overlays on the view (the name at the top left, the light's sun and its line)
    // are left out: the top 40 rows, and a generous band around the line to the sun.
    let (mut checked, mut close, mut worst) = (0usize, 0usize, 0i32);
    for j in (40..r.height).step_by(3) {
        for i in (0..r.width).step_by(3) {
            let got = image.get_pixel((r.x + i) as u32, (r.y + j) as u32).0;
            let w = want.get_pixel(i as u32, j as u32).0;
            let err = (0..3).map(|c| (got[c] as i32 - w[c] as i32).abs()).max().unwrap();
            checked += 1;
            close += (err <= 3) as usize;
            worst = worst.max(err);
        }
    }
    // The sun and its line cover well under 1% of the view.
    assert!(close as f64 >= 0.99 * checked as f64, "{close} of {checked} pixels within 3 levels of render (worst {worst})");
    (image, info)
}
