//! Stylized lit spheres (`fit --lit-sphere --style auto|stylized`, issue 36): toon spheres
//! (flat tones, a hard terminator, a hard highlight at the half vector) drawn here with known
//! lights are read as drawn, keep their edges and find their light; the thesis's cases (an
//! outline, a highlight with coloured halos) keep what was drawn; smooth rendered spheres and
//! a warm-to-cool painting are read as physical; the bunny under a moved light still shows
//! the toon's tones.

mod sphere_common;
use sphere_common::sphere_picture;

use std::path::Path;

use brdfpaint::brdf::Analytic;
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::{linear_to_srgb, srgb_to_linear};
use brdfpaint::litsphere::{self, Ask, LitSphere, Style};
use brdfpaint::material::Material;
use brdfpaint::pipeline::Options;
use brdfpaint::render::{GpuScene, Renderer};
use brdfpaint::scene::{Light, Scene};
use glam::{DVec3, Vec3};

/// A sphere drawn by `shade` (sRGB from the normal, the unit light and the half vector), on
/// a white page, 256² with a radius of 110; 4×4 supersampled (the edges anti-aliased as a
/// drawing program does), 8-bit PNG.
fn drawn_png(path: &Path, light: DVec3, shade: impl Fn(DVec3, DVec3, DVec3) -> [f64; 3]) {
    const SIZE: u32 = 256;
    const SUB: u32 = 4;
    let (c, r) = (128.0, 110.0);
    let l = light.normalize();
    let h = (l + DVec3::Z).normalize();
    let image = image::RgbImage::from_fn(SIZE, SIZE, |i, j| {
        let mut sum = [0.0f64; 3];
        for sj in 0..SUB {
            for si in 0..SUB {
                let x = (i as f64 + (si as f64 + 0.5) / SUB as f64 - c) / r;
                let y = -(j as f64 + (sj as f64 + 0.5) / SUB as f64 - c) / r;
                let d = x * x + y * y;
                let srgb = if d >= 1.0 { [1.0; 3] } else { shade(DVec3::new(x, y, (1.0 - d).sqrt()), l, h) };
                for k in 0..3 {
                    sum[k] += srgb_to_linear(srgb[k] as f32) as f64;
                }
            }
        }
        image::Rgb(sum.map(|s| (linear_to_srgb((s / (SUB * SUB) as f64) as f32) * 255.0).round() as u8))
    });
    image.save(path).unwrap();
}

/// A toon sphere: `tones` (sRGB, darkest first) above the thresholds `steps` of $n \cdot l$,
/// white where $n \cdot h > 0.985$ (a highlight 10° in radius).
fn toon_png(path: &Path, light: DVec3, tones: &[[f64; 3]], steps: &[f64]) {
    drawn_png(path, light, |n, l, h| {
        let tone = steps.iter().filter(|&&s| n.dot(l) > s).count();
        if n.dot(h) > 0.985 { [1.0; 3] } else { tones[tone] }
    });
}

/// sRGB luminance of linear RGB.
fn display_luminance(c: [f64; 3]) -> f64 {
    linear_to_srgb((0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]) as f32) as f64
}

/// The 99th percentile of the luminance gradient's magnitude (forward differences) over the
/// pixels of `image` (None: not on the sphere) at least `inset` pixels inside the disk.
fn strongest_edges(image: &[Option<f64>], w: usize, h: usize, disk: &litsphere::Disk, inset: f64) -> f64 {
    let mut g = Vec::new();
    for j in 0..h - 1 {
        for i in 0..w - 1 {
            let (x, y) = (i as f64 + 0.5 - disk.cx, j as f64 + 0.5 - disk.cy);
            if (x * x + y * y).sqrt() > disk.r - inset {
                continue;
            }
            if let (Some(a), Some(b), Some(c)) = (image[j * w + i], image[j * w + i + 1], image[(j + 1) * w + i]) {
                g.push(((b - a).powi(2) + (c - a).powi(2)).sqrt());
            }
        }
    }
    g.sort_by(f64::total_cmp);
    g[g.len() * 99 / 100]
}

/// The strongest inner edges of the fit re-rendered in its own scene over the picture's
/// (issue 36: 6 pixels in from the rim).
fn edge_ratio(lit: &LitSphere) -> f64 {
    let p = &lit.view.painting;
    let (w, h) = (p.width, p.height);
    let picture: Vec<Option<f64>> = p.pixels.iter().map(|c| Some(display_luminance(c.map(f64::from)))).collect();
    let solved = &lit.fitted.solved;
    let predicted = solved.prepared.predict(&solved.fit.tables, &solved.fit.map);
    let mut fit = vec![None; w * h];
    for (s, &(_, px)) in lit.fitted.samples.origin.iter().enumerate() {
        fit[px] = Some(display_luminance(predicted[s]));
    }
    strongest_edges(&fit, w, h, &lit.disk, 6.0) / strongest_edges(&picture, w, h, &lit.disk, 6.0)
}

/// The lean of `lit`'s half-vector factor (1: the mirror direction).
fn lean(lit: &LitSphere) -> f64 {
    let factors = &lit.fitted.material.terms[0].factors;
    factors.iter().find(|f| f.spec.input == brdfpaint::factor::Input::Half).map_or(1.0, |f| f.spec.lean)
}

/// Two-tone spheres whose white highlight (5° in radius) is drawn about the leaned half
/// vector $h_k \propto l + k v$, nearer the light than the mirror direction ($k < 1$), at it
/// and nearer the eye: the lean read back within 10%, and 1 for the mirror direction (the
/// information criterion keeps the thesis's $q(h)$ when nothing asks for more).
#[test]
fn a_highlight_drawn_off_the_mirror_direction_is_read_with_its_lean() {
    let dir = tempfile::tempdir().unwrap();
    let light = DVec3::new(-0.45, 0.5, 0.74).normalize();
    for (k, truth) in [0.35, 0.6, 1.0, 1.8].into_iter().enumerate() {
        let path = dir.path().join(format!("lean{k}.png"));
        let hk = brdfpaint::factor::leaned_half(light, DVec3::Z, truth);
        drawn_png(&path, light, |n, l, _| match n.dot(hk) > 5f64.to_radians().cos() {
            true => [1.0; 3],
            false => if n.dot(l) > 0.3 { [0.75, 0.6, 0.5] } else { [0.3, 0.22, 0.25] },
        });
        let lit = litsphere::fit_in(&path, &Ask::default(), &Options::default(), None).unwrap();
        let read = lean(&lit);
        eprintln!("lean {truth}: read {read:.3}; light {:.2}° off", lit.light.angle_between(light).to_degrees());
        assert!(lit.stylization.stylized, "lean {truth}: read as physical");
        match truth == 1.0 {
            true => assert_eq!(read, 1.0, "a highlight at h read with lean {read}"),
            false => assert!((read / truth).ln().abs() < 0.1, "lean {truth} read as {read}"),
        }
    }
}

/// Toon spheres of two and three tones under lights from the front to the side: read as
/// drawn by `auto`, the light within 3° of the one they were drawn with, the re-render's
/// strongest inner edges at least 0.6 of the picture's (issue 36; before the stylized
/// reading, 0.15 on the Blender toon MatCap) and its error small.
#[test]
fn toon_spheres_are_read_as_drawn_with_their_edges_and_light() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(DVec3, &[[f64; 3]], &[f64]); 4] = [
        (DVec3::new(0.3, 0.6, 0.74), &[[0.35, 0.2, 0.15], [0.85, 0.55, 0.4]], &[0.25]),
        (DVec3::new(-0.7, 0.2, 0.68), &[[0.15, 0.2, 0.35], [0.4, 0.55, 0.8], [0.7, 0.8, 0.95]], &[0.1, 0.7]),
        (DVec3::new(0.5, -0.3, 0.81), &[[0.3, 0.3, 0.3], [0.75, 0.75, 0.7]], &[0.0]),
        (DVec3::new(-0.2, 0.9, 0.4), &[[0.2, 0.35, 0.15], [0.5, 0.75, 0.35]], &[0.3]),
    ];
    for (k, (light, tones, steps)) in cases.into_iter().enumerate() {
        let path = dir.path().join(format!("toon{k}.png"));
        toon_png(&path, light, tones, steps);
        let lit = litsphere::fit_in(&path, &Ask::default(), &Options::default(), None).unwrap();
        assert!(lit.stylization.stylized, "toon{k}: read as physical ({:?})", lit.stylization.tones);
        let off = lit.light.angle_between(light.normalize()).to_degrees();
        let ratio = edge_ratio(&lit);
        let rms = lit.fitted.errors().rms;
        eprintln!("toon{k}: light {off:.2}° off; strongest edges {ratio:.2} of the picture's; RMS {rms:.4}");
        assert!(off < 3.0, "toon{k}: light {:?} is {off:.1}° from {light:?}", lit.light);
        assert!(ratio >= 0.6, "toon{k}: the fit's strongest edges are {ratio:.2} of the picture's");
        assert!(rms < 0.03, "toon{k}: RMS {rms}");
    }
}

/// Smooth rendered spheres (the analytic suite, 16-bit PNG) and a warm-to-cool painting are
/// read as physical by `auto`; a picture asked `stylized` is read as drawn.
#[test]
fn smooth_spheres_are_read_as_physical() {
    let dir = tempfile::tempdir().unwrap();
    for (k, model) in Analytic::suite().iter().enumerate() {
        let picture = sphere_picture(model, DVec3::new(-0.4, 0.5, 0.8), 200, (240, 240), (20, 20));
        let path = dir.path().join(format!("smooth{k}.png"));
        std::fs::write(&path, picture.encode_png16().unwrap()).unwrap();
        let tones = litsphere::Picture::read(&path, 512).map(|p| litsphere::style::tones(&p.painting, &p.disk)).unwrap();
        assert!(!tones.stylized(), "{}: {tones:?}", model.name());
    }
    // The thesis's warm-to-cool (Gooch) shading: smooth, so physical too.
    let gooch = dir.path().join("gooch.png");
    drawn_png(&gooch, DVec3::new(-0.5, 0.5, 0.7), |n, l, _| {
        let t = 0.5 * (1.0 + n.dot(l));
        [0.2 + 0.7 * t, 0.25 + 0.45 * t, 0.75 - 0.45 * t]
    });
    let tones = litsphere::Picture::read(&gooch, 512).map(|p| litsphere::style::tones(&p.painting, &p.disk)).unwrap();
    assert!(!tones.stylized(), "gooch: {tones:?}");
    let path = dir.path().join("smooth0.png");
    let asked = Ask { style: Style::Stylized, ..Ask::default() };
    let lit = litsphere::fit_in(&path, &asked, &Options::default(), None).unwrap();
    assert!(lit.stylization.stylized);
}

/// Counts the flat tones of the bunny's pixels: peaks of the sRGB luminance histogram that
/// hold 3% or more of them within ±4 codes, and the share they hold.
fn bunny_tones(image: &brdfpaint::render::Image, w: usize, h: usize) -> (usize, f64, f64) {
    let mut histogram = [0usize; 256];
    let mut total = 0;
    let mut brightest = 0.0f64;
    for j in 0..h {
        for i in 0..w {
            let p = image.at(i, j);
            if p[3] == 1.0 {
                let y = display_luminance([p[0] as f64, p[1] as f64, p[2] as f64]);
                histogram[(y * 255.0).round().clamp(0.0, 255.0) as usize] += 1;
                brightest = brightest.max(y);
                total += 1;
            }
        }
    }
    let (mut count, mut held) = (0, 0);
    loop {
        let (peak, _) = histogram.iter().enumerate().max_by_key(|&(_, &n)| n).unwrap();
        let window = peak.saturating_sub(4)..=(peak + 4).min(255);
        let mass: usize = histogram[window.clone()].iter().sum();
        if (mass as f64) < 0.03 * total as f64 {
            break;
        }
        count += 1;
        held += mass;
        histogram[window].iter_mut().for_each(|n| *n = 0);
    }
    (count, held as f64 / total as f64, brightest)
}

/// A two-tone toon sphere's material on the bunny, lit from the front-left and from the
/// right: two flat tones hold most of the bunny in both, the darker one grows as the light
/// moves to the side (the terminator follows it), and the highlight's white appears.
#[test]
fn the_toon_material_keeps_its_tones_on_the_bunny_under_a_moved_light() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("toon.png");
    toon_png(&path, DVec3::new(-0.3, 0.4, 0.87), &[[0.3, 0.22, 0.5], [0.8, 0.6, 0.95]], &[0.2]);
    let lit = litsphere::fit_in(&path, &Ask::default(), &Options::default(), None).unwrap();
    let out = dir.path().join("mat");
    lit.save(&path, &out).unwrap();
    let material = Material::load(&out).unwrap();
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let scene = Scene::from_preset("bunny", "front").unwrap();
    let mut gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let shading = renderer.upload(&material).unwrap();
    let view = scene.camera.forward();
    let mut dark_share = Vec::new();
    for (name, angle) in [("front-left", -0.4f32), ("right", 1.3)] {
        let towards = (glam::Quat::from_rotation_y(angle) * -view + Vec3::Y * 0.4).normalize();
        gpu.light = Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 };
        let image = renderer.factored(&gpu, &shading, 192, 192).unwrap();
        let (count, held, brightest) = bunny_tones(&image, 192, 192);
        let dark = (0..192 * 192).filter(|&k| {
            let p = image.at(k % 192, k / 192);
            p[3] == 1.0 && display_luminance([p[0] as f64, p[1] as f64, p[2] as f64]) < 0.45
        });
        let object = (0..192 * 192).filter(|&k| image.at(k % 192, k / 192)[3] == 1.0).count();
        dark_share.push(dark.count() as f64 / object as f64);
        eprintln!("{name}: {count} tones hold {held:.2} of the bunny; brightest {brightest:.2}; dark share {:.2}", dark_share.last().unwrap());
        assert!((2..=4).contains(&count) && held >= 0.75, "{name}: {count} tones hold {held:.2} of the bunny");
        assert!(brightest > 0.97, "{name}: no white highlight (brightest {brightest:.2})");
    }
    assert!(dark_share[1] > dark_share[0] + 0.1, "the shadow tone did not follow the light: {dark_share:?}");
}

/// The picture's colours: the sRGB of the disk's pixels, rounded to 1/64.
fn palette(lit: &LitSphere) -> Vec<[f64; 3]> {
    let p = &lit.view.painting;
    let mut colours: Vec<[i64; 3]> =
        p.pixels.iter().zip(&p.alpha).filter(|(_, &a)| a > 0.0).map(|(c, _)| c.map(|x| (f64::from(linear_to_srgb(x)) * 64.0).round() as i64)).collect();
    colours.sort_unstable();
    colours.dedup();
    colours.into_iter().map(|c| c.map(|x| x as f64 / 64.0)).collect()
}

/// The sRGB distance from `c` to the nearest colour of `palette`.
fn off_palette(c: [f64; 3], palette: &[[f64; 3]]) -> f64 {
    palette.iter().map(|p| (0..3).map(|k| (c[k] - p[k]).powi(2)).sum::<f64>().sqrt()).fold(f64::MAX, f64::min)
}

/// Toon materials on the bunny under a rim light (150° round from the camera, behind the
/// bunny): no pixel takes a colour the picture does not have (98% within 0.08 in sRGB of one
/// of its colours), for a two-tone sphere drawn here and Blender's toon MatCap (CC0). The
/// pictures show no light that far behind, so the tables' unreached nodes hold their nearest
/// reached value (`Robust::hold_unseen`); run on in log space by the Laplacian instead, they
/// put 7.6% of the Blender toon's bunny off its colours (blue fringes).
#[test]
fn toon_materials_under_a_rim_light_keep_their_palette() {
    let dir = tempfile::tempdir().unwrap();
    let drawn = dir.path().join("toon.png");
    toon_png(&drawn, DVec3::new(-0.3, 0.4, 0.87), &[[0.3, 0.22, 0.5], [0.8, 0.6, 0.95]], &[0.2]);
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let scene = Scene::from_preset("bunny", "front").unwrap();
    let mut gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let towards = (glam::Quat::from_rotation_y(2.6) * -scene.camera.forward() + Vec3::Y * 0.4).normalize();
    gpu.light = Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 };
    for path in [drawn.as_path(), Path::new("../shared/data/matcaps/blender_cc0/exr/toon.exr")] {
        let lit = litsphere::fit_in(path, &Ask::default(), &Options::default(), None).unwrap();
        ctx.make_current().unwrap();
        let palette = palette(&lit);
        let shading = renderer.upload(&lit.fitted.material).unwrap();
        let image = renderer.factored(&gpu, &shading, 192, 192).unwrap();
        let (mut object, mut on) = (0usize, 0usize);
        for k in 0..192 * 192 {
            let p = image.at(k % 192, k / 192);
            if p[3] == 1.0 {
                object += 1;
                on += usize::from(off_palette([0, 1, 2].map(|i| f64::from(linear_to_srgb(p[i]))), &palette) < 0.08);
            }
        }
        let on = on as f64 / object as f64;
        eprintln!("{}: {on:.3} of the bunny within 0.08 of the picture's colours", path.display());
        assert!(on >= 0.98, "{}: {:.1}% of the bunny off the picture's colours", path.display(), 100.0 * (1.0 - on));
    }
}

/// Blender's toon MatCap (CC0, made by others): read as drawn, its three tones kept and its
/// highlight too: drawn nearer the light than the mirror direction of the light its tone
/// edges share (12° off $h$), it is read with a lean of about 1/2. The edges kept are at
/// least 0.6 of the picture's strongest (0.15 read physically).
#[test]
fn the_blender_toon_matcap_is_read_as_drawn() {
    let path = Path::new("../shared/data/matcaps/blender_cc0/exr/toon.exr");
    let lit = litsphere::fit_in(path, &Ask::default(), &Options::default(), None).unwrap();
    let ratio = edge_ratio(&lit);
    let rms = lit.fitted.errors().rms;
    eprintln!("toon.exr: {:?}; light {:?}; lean {:.3}; strongest edges {ratio:.2} of the picture's; RMS {rms:.4}", lit.stylization.tones, lit.light, lean(&lit));
    assert!(lit.stylization.stylized && lit.stylization.tones.count == 3, "{:?}", lit.stylization);
    assert!((0.35..0.7).contains(&lean(&lit)), "lean {}", lean(&lit));
    assert!(ratio >= 0.6, "strongest edges {ratio:.2} of the picture's");
    assert!(rms < 0.05, "RMS {rms}");
}

/// The white pixels of the bunny (sRGB luminance over 0.97), and the mean drop in luminance
/// from them to their 4-neighbours that are not white: a hard highlight falls to the tone
/// around it within a pixel, a soft one through a ramp of near-whites.
fn white_and_its_edge(image: &brdfpaint::render::Image, w: usize, h: usize) -> (usize, f64) {
    let y = |i: usize, j: usize| {
        let p = image.at(i, j);
        (p[3] == 1.0).then(|| display_luminance([p[0] as f64, p[1] as f64, p[2] as f64]))
    };
    let (mut white, mut drops) = (0usize, Vec::new());
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            if y(i, j).is_some_and(|v| v > 0.97) {
                white += 1;
                for (a, b) in [(i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)] {
                    if let Some(v) = y(a, b).filter(|&v| v <= 0.97) {
                        drops.push(0.97 - v);
                    }
                }
            }
        }
    }
    (white, drops.iter().sum::<f64>() / drops.len().max(1) as f64)
}

/// Blender's toon MatCap on the bunny under lights moved from the picture's: two or more
/// flat tones hold most of it, and its white highlight shows with a hard edge (the pixels
/// beside it at least half the picture's step from white to its lightest tone below white).
/// Before the lean was read the bunny had no white at all (brightest 0.85).
#[test]
fn the_blender_toon_keeps_two_tones_and_a_hard_highlight_on_the_bunny() {
    let path = Path::new("../shared/data/matcaps/blender_cc0/exr/toon.exr");
    let lit = litsphere::fit_in(path, &Ask::default(), &Options::default(), None).unwrap();
    // The picture's lightest tone: the brightest luminance histogram peak below white.
    let p = &lit.view.painting;
    let mut histogram = [0usize; 256];
    for (c, _) in p.pixels.iter().zip(&p.alpha).filter(|(_, &a)| a > 0.0) {
        histogram[(display_luminance(c.map(f64::from)) * 255.0).round().clamp(0.0, 255.0) as usize] += 1;
    }
    let lightest = (129..240).max_by_key(|&c| histogram[c]).unwrap() as f64 / 255.0;
    let step = 1.0 - lightest;
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let scene = Scene::from_preset("bunny", "front").unwrap();
    let mut gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
    let shading = renderer.upload(&lit.fitted.material).unwrap();
    let view = scene.camera.forward();
    for (name, angle) in [("front-left", -0.5f32), ("front-right", 0.6), ("right", 1.2)] {
        let towards = (glam::Quat::from_rotation_y(angle) * -view + Vec3::Y * 0.5).normalize();
        gpu.light = Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 };
        let image = renderer.factored(&gpu, &shading, 192, 192).unwrap();
        let (count, held, _) = bunny_tones(&image, 192, 192);
        let (white, drop) = white_and_its_edge(&image, 192, 192);
        eprintln!("{name}: {count} tones hold {held:.2}; {white} white pixels, falling {drop:.3} beside them (the picture's step {step:.3})");
        assert!((2..=4).contains(&count) && held >= 0.75, "{name}: {count} tones hold {held:.2} of the bunny");
        assert!(white >= 4, "{name}: no highlight ({white} white pixels)");
        assert!(drop >= 0.5 * step, "{name}: a soft highlight: {drop:.3} beside it, the picture's step {step:.3}");
    }
}

/// The mean sRGB colour of the fit re-rendered in its own scene and of the picture over the
/// samples whose normal satisfies `inside`.
fn mean_colours(lit: &LitSphere, inside: impl Fn(DVec3) -> bool) -> ([f64; 3], [f64; 3]) {
    let p = &lit.view.painting;
    let solved = &lit.fitted.solved;
    let predicted = solved.prepared.predict(&solved.fit.tables, &solved.fit.map);
    let (mut fit, mut picture, mut n) = ([0.0; 3], [0.0; 3], 0.0);
    for (s, &(_, px)) in lit.fitted.samples.origin.iter().enumerate() {
        let Some(normal) = lit.disk.normal(px % p.width, px / p.width, 1.0) else { continue };
        if inside(normal) {
            for c in 0..3 {
                fit[c] += linear_to_srgb(predicted[s][c] as f32) as f64;
                picture[c] += linear_to_srgb(p.pixels[px][c]) as f64;
            }
            n += 1.0;
        }
    }
    (fit.map(|x| x / n), picture.map(|x| x / n))
}

/// The thesis's non-photorealistic cases (its figures): a toon sphere with a black outline,
/// and a highlight with coloured halos (yellow, then green, then blue rings) on a grey body.
/// Read as drawn, the rim stays dark (under 0.4 of the lit body in sRGB luminance: the
/// offset mapping the fit keeps softens a black line to a dark one) and each ring keeps its
/// colour, within 0.06 in sRGB per channel.
#[test]
fn an_outline_and_coloured_halos_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let light = DVec3::new(-0.35, 0.45, 0.82);
    let outline = dir.path().join("outline.png");
    drawn_png(&outline, light, |n, l, _| {
        if n.z < 0.3 {
            [0.02; 3]
        } else if n.dot(l) > 0.3 {
            [0.9, 0.5, 0.3]
        } else {
            [0.45, 0.2, 0.2]
        }
    });
    let halos = dir.path().join("halos.png");
    let rings = [(0.995, [1.0, 0.95, 0.2]), (0.98, [0.3, 0.85, 0.3]), (0.96, [0.25, 0.45, 0.95])];
    drawn_png(&halos, light, |n, l, h| {
        rings.iter().find(|(c, _)| n.dot(h) > *c).map_or_else(|| if n.dot(l) > 0.2 { [0.6; 3] } else { [0.3; 3] }, |(_, colour)| *colour)
    });
    let lit = litsphere::fit_in(&outline, &Ask::default(), &Options::default(), None).unwrap();
    assert!(lit.stylization.stylized, "outline: {:?}", lit.stylization.tones);
    let (rim, picture) = mean_colours(&lit, |n| n.z < 0.25);
    let (body, _) = mean_colours(&lit, |n| (0.45..0.6).contains(&n.z) && n.dot(lit.light) > 0.4);
    let y = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    eprintln!("outline at the rim: fit {rim:.3?} against the lit body's {body:.3?}; picture {picture:.3?}");
    assert!(y(rim) < 0.4 * y(body), "the outline is not kept: {rim:?} at the rim, {body:?} on the body");
    let lit = litsphere::fit_in(&halos, &Ask::default(), &Options::default(), None).unwrap();
    assert!(lit.stylization.stylized, "halos: {:?}", lit.stylization.tones);
    let h = (lit.light + DVec3::Z).normalize();
    let bounds: [f64; 4] = [1.0, 0.995, 0.98, 0.96];
    for (k, (_, colour)) in rings.iter().enumerate() {
        // The middle of each ring, off its edges by a third of its width.
        let (hi, lo) = (bounds[k].acos(), bounds[k + 1].acos());
        let (a, b) = (hi + (lo - hi) / 3.0, lo - (lo - hi) / 3.0);
        let (fit, picture) = mean_colours(&lit, |n| (a..b).contains(&n.dot(h).clamp(-1.0, 1.0).acos()));
        eprintln!("ring {k}: fit {fit:.3?}, picture {picture:.3?}, drawn {colour:?}");
        for c in 0..3 {
            assert!((fit[c] - picture[c]).abs() < 0.06, "ring {k}: fit {fit:?}, picture {picture:?}");
        }
    }
}
