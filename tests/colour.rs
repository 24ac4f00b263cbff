//! The painter's colours under every light (issue 35): a lit-sphere material rendered on the
//! bunny under its key light and a white light swept around it keeps its lit pixels within
//! the picture's own chromaticities (`study::colour`: 0.05 in rg, pixels above 2% of the
//! frame's brightest, at most 5% of them off), unless the picture itself shows the colour.

use std::path::{Path, PathBuf};

use brdfpaint::brdf::{Analytic, Reflectance, SphereView};
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::Painting;
use brdfpaint::litsphere::{self, LitSphere, Picture};
use brdfpaint::pipeline::Options;
use brdfpaint::render::{GpuScene, Renderer};
use brdfpaint::scene::Scene;
use brdfpaint::study::colour::{self, chromaticity, Palette, Sweep, INVENTED};
use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng};

const MATCAPS: &str = "../shared/data/matcaps/blender_cc0/exr";

/// Bunny renders: a headless renderer and the bunny's front scene.
struct Bunny {
    renderer: Renderer,
    gpu: GpuScene,
    ctx: HeadlessContext,
}

impl Bunny {
    fn new() -> Bunny {
        let ctx = HeadlessContext::new().unwrap();
        let renderer = Renderer::new(ctx.gl()).unwrap();
        let gpu = GpuScene::upload(ctx.gl(), &Scene::from_preset("bunny", "front").unwrap()).unwrap();
        Bunny { renderer, gpu, ctx }
    }

    /// Fit the picture at `path` as `fit --lit-sphere` does (`Fit::Default`), or as the thesis
    /// does (`Fit::Thesis`: channels one by one, the mapping of least error, never
    /// refitted), and sweep the light around the bunny.
    fn sweep(&mut self, path: &Path, how: Fit) -> (LitSphere, Sweep) {
        let opts = Options { keep_colours: how == Fit::Default, ..Options::default() };
        let fit = litsphere::fit(path, None, &opts, None).unwrap();
        // The fit sampled the picture with a context of its own.
        self.ctx.make_current().unwrap();
        let palette = Palette::of_painting(&Picture::read(path, litsphere::MAX_SIDE).unwrap().painting);
        let key = self.gpu.camera.world_from_camera.transform_vector3(fit.light.as_vec3());
        let shading = self.renderer.upload(&fit.fitted.material).unwrap();
        let s = colour::sweep(&mut self.renderer, &mut self.gpu, &shading, &palette, key, 128).unwrap();
        (fit, s)
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Fit {
    Default,
    Thesis,
}

/// `model` on a black background, a `res`-pixel sphere lit from `light`, with `noise`
/// (relative, per channel, seeded: brush grain) on every pixel.
fn sphere(dir: &Path, name: &str, model: &Analytic, light: DVec3, noise: f64) -> PathBuf {
    let res = 200;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(35);
    let mut p = Painting::opaque(res, res, vec![[0.0; 3]; res * res]).unwrap();
    for px in SphereView::new(light, res).pixels() {
        let s = model.shading(&px.query);
        p.pixels[px.pixel[1] * res + px.pixel[0]] = s.map(|x| (x * (1.0 + noise * rng.random_range(-1.0..1.0))) as f32);
    }
    let path = dir.join(format!("{name}.exr"));
    std::fs::write(&path, p.encode_exr().unwrap()).unwrap();
    path
}

#[test]
fn no_blender_matcap_invents_colours_on_the_bunny() {
    let mut bunny = Bunny::new();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(MATCAPS).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|e| e == "exr")).collect();
    paths.sort();
    assert_eq!(paths.len(), 23, "{paths:?}");
    let (mut failures, mut thesis) = (Vec::new(), 0);
    for path in &paths {
        let (_, s) = bunny.sweep(path, Fit::Default);
        let name = path.file_stem().unwrap().to_string_lossy();
        eprintln!("{name}: invented key {:.3} darkest {:.3}; darkest/brightest {:.2}", s.key, s.darkest, s.darkest_over_brightest);
        if s.worst() > INVENTED {
            failures.push(format!("{name}: {s:?}"));
        }
        assert!(s.darkest_over_brightest <= 0.5, "{name} does not darken: {s:?}");
        thesis += (bunny.sweep(path, Fit::Thesis).1.worst() > INVENTED) as usize;
    }
    // Measured: none of the 23 invents; fitted as the thesis does, 9 do (BENCHMARKS.md,
    // "Colours under every light").
    assert!(failures.is_empty(), "{failures:#?}");
    assert!(thesis >= 8, "the thesis's fit invents colours in {thesis} of 23: this test no longer tells the fits apart");
}

/// MatCaps another renderer made (Mitsuba 3 spheres under HDR environments,
/// `tools/mitsuba/render_matcaps.py --seed 2`), which the colour check was not developed on:
/// a copper, an aluminium and a gold whose thesis fits invent colours on the bunny.
#[test]
fn matcaps_from_another_renderer_keep_their_colours() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/matcaps");
    let mut bunny = Bunny::new();
    for name in ["city-05-copper", "sunset-04-aluminium", "warehouse-03-gold"] {
        let path = dir.join(format!("{name}.png"));
        let (_, thesis) = bunny.sweep(&path, Fit::Thesis);
        let (_, s) = bunny.sweep(&path, Fit::Default);
        eprintln!("{name}: thesis {thesis:?}\n  default {s:?}");
        assert!(thesis.worst() > INVENTED, "{name}: the thesis's fit no longer invents colours here: {thesis:?}");
        assert!(s.worst() <= INVENTED && s.darkest_over_brightest <= 0.5, "{name}: {s:?}");
    }
}

#[test]
fn a_grainy_grey_matcap_stays_grey_under_every_light() {
    let dir = tempfile::tempdir().unwrap();
    let grey = Analytic::Ggx { diffuse: [0.35; 3], f0: [0.4; 3], roughness: 0.35 };
    let path = sphere(dir.path(), "grey", &grey, DVec3::new(-0.5, 0.5, 1.0), 0.03);
    let (_, s) = Bunny::new().sweep(&path, Fit::Default);
    eprintln!("grey: {s:?}");
    assert!(s.worst() <= INVENTED, "{s:?}");
}

#[test]
fn tinted_analytic_spheres_keep_their_colours() {
    let dir = tempfile::tempdir().unwrap();
    let mut bunny = Bunny::new();
    let models = [
        ("copper_blinn", Analytic::BlinnPhong { diffuse: [0.45, 0.25, 0.12], specular: [0.3, 0.35, 0.4], exponent: 32.0 }, DVec3::new(0.6, 0.3, 0.8)),
        ("green_oren_nayar", Analytic::OrenNayar { albedo: [0.25, 0.5, 0.3], sigma: 0.5 }, DVec3::new(-0.2, 0.7, 0.8)),
        ("blue_minnaert", Analytic::Minnaert { albedo: [0.2, 0.3, 0.7], k: 0.7 }, DVec3::new(0.0, 0.0, 1.0)),
    ];
    for (name, model, light) in &models {
        let path = sphere(dir.path(), name, model, *light, 0.02);
        let (_, s) = bunny.sweep(&path, Fit::Default);
        eprintln!("{name}: {s:?}");
        assert!(s.worst() <= INVENTED, "{name}: {s:?}");
    }
}

#[test]
#[ignore = "open (issue 35): lit from behind, the coupled fit's bunny has b-chromaticity 0.27, not the cool side's blue; the chroma ridge pulls the unpainted back toward the mean (warm) colour"]
fn a_gooch_spheres_cool_side_stays_cool_behind() {
    // Painted colour wins over the prior: the unlit side is painted blue, so a light behind
    // the bunny shows blue (the truth's cool colour has b-chromaticity 0.67, its warm 0.12).
    let dir = tempfile::tempdir().unwrap();
    let gooch = Analytic::Gooch { warm: [0.9, 0.6, 0.2], cool: [0.1, 0.2, 0.6] };
    let path = sphere(dir.path(), "gooch", &gooch, DVec3::new(-0.4, 0.4, 1.0), 0.0);
    let mut bunny = Bunny::new();
    // (Its sweep's darkest frame is not held to the palette: 0.13 of its lit pixels leave the
    // painted gradient's chromaticities there, BENCHMARKS.md "Colours under every light".)
    let (fit, s) = bunny.sweep(&path, Fit::Default);
    eprintln!("gooch: {s:?}");
    let shading = bunny.renderer.upload(&fit.fitted.material).unwrap();
    let behind = bunny.gpu.camera.forward();
    bunny.gpu.light = brdfpaint::scene::Light::Directional { direction: -behind, color: Vec3::ONE, intensity: 1.0 };
    let image = bunny.renderer.factored(&bunny.gpu, &shading, 128, 128).unwrap();
    let (mut sum, mut n) = ([0.0f64; 3], 0);
    for p in image.pixels.iter().filter(|p| p[3] >= 1.0) {
        for c in 0..3 {
            sum[c] += p[c] as f64;
        }
        n += 1;
    }
    let rg = chromaticity(sum).unwrap();
    let b = 1.0 - rg[0] - rg[1];
    eprintln!("gooch lit from behind: mean rg {rg:?}, b {b:.3} over {n} pixels");
    assert!(b > 0.5, "the cool side lost its blue: rg {rg:?}");
}
