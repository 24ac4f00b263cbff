//! Materials on the GPU: the GL image of a saved-then-loaded material equals
//! `Material::eval` (the CPU reference) at the G-buffer's queries, times the light's colour ×
//! intensity and a $1/d^2$ falloff computed here, under several lights and views.

mod gl_common;

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{Analytic, SphereView};
use brdfpaint::factor::{prepare, Domain, Input, LogMap, Mapping, Param, Settings};
use brdfpaint::gl::HeadlessContext;
use brdfpaint::material::{Coefficients, Factor, Kind, Material, Provenance, Term};
use brdfpaint::render::Renderer;
use brdfpaint::scene::{Light, Scene};
use gl_common::*;
use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Agreement of GL float-texture filtering in f32 with `Material::eval` in f64, relative
/// to max(|expected|, 1); the same bound as tests/gl_factored.rs (llvmpipe measured ~1e-5).
const TOL: f64 = 1e-4;

/// A material fitted to an analytic model painted on one sphere view.
fn fitted(dim: usize, res: usize, model: &Analytic) -> Material {
    let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 48).pattern();
    let settings = Settings::uniform(dim, res);
    let prepared = prepare(&pattern, &settings).unwrap();
    let values = pattern.shade(|q| model.shading(q));
    let fit = prepared.solve(&values, Mapping::Auto).unwrap();
    Material::from_fit(&settings, &fit, Provenance::default()).unwrap()
}

fn random_table(input: Input, param: Param, domain: Domain, res: usize, rng: &mut ChaCha8Rng) -> Factor {
    let spec = spec(input, param, domain, res);
    let texels = (0..spec.len()).map(|_| [0; 3].map(|_| rng.random_range(0.3f32..1.3))).collect();
    Factor { spec, texels }
}

/// A material map built by hand: two terms with different factor layouts and mappings,
/// blended by random coefficient textures of different resolutions.
fn two_terms() -> Material {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let c0: Vec<f32> = (0..8 * 8).map(|_| rng.random_range(0.0f32..1.0)).collect();
    let c1: Vec<f32> = (0..5 * 5).map(|_| rng.random_range(0.0f32..1.5)).collect();
    Material {
        kind: Kind::Hybrid,
        terms: vec![
            Term { base: None,
                factors: vec![
                    random_table(Input::Light, Param::Radius, Domain::Sphere, 33, &mut rng),
                    random_table(Input::Half, Param::Parabolic, Domain::Hemisphere, 12, &mut rng),
                ],
                map: LogMap::Offset { a: [0.05, 0.1, 0.02] },
                coefficients: Some(Coefficients::grey(8, &c0)),
            },
            Term { base: None,
                factors: vec![
                    random_table(Input::View, Param::Hemispherical, Domain::Hemisphere, 9, &mut rng),
                    random_table(Input::Uv, Param::Uv, Domain::Hemisphere, 16, &mut rng),
                ],
                map: LogMap::Inverted { a: [2.0, 2.5, 3.0] },
                coefficients: Some(Coefficients::grey(5, &c1)),
            },
        ],
        detail: None,
        provenance: Provenance::default(),
    }
}

/// Saves, loads (checking the round trip is exact), and converts.
fn through_disk(material: &Material) -> (Material, Material) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mat");
    material.save(&path).unwrap();
    let loaded = Material::load(&path).unwrap();
    assert_eq!(&loaded, material, "save/load round trip");
    brdfpaint::render::check(&loaded).unwrap();
    (loaded.clone(), loaded)
}

/// Scenes: both camera kinds, both light kinds (coloured, intensity ≠ 1), lights below
/// part of the sphere's horizon.
fn scenes() -> Vec<(&'static str, Scene, usize, usize)> {
    let point = Light::Point { position: Vec3::new(2.0, 1.5, 2.5), color: Vec3::new(1.0, 0.8, 0.6), intensity: 9.0 };
    let warm_sun = Light::Directional {
        direction: -Vec3::new(0.2, -0.4, -1.0).normalize(),
        color: Vec3::new(0.9, 1.1, 1.3),
        intensity: 1.5,
    };
    vec![
        ("ortho front, upper-left sun", ortho_sphere(DVec3::Z, sun(DVec3::new(-0.5, 0.5, 1.0), [1.0; 3])), 80, 80),
        ("ortho from the side, back light", ortho_sphere(DVec3::new(0.6, 0.3, 0.75), warm_sun), 80, 80),
        ("perspective, point light", perspective_sphere(DVec3::new(0.5, 0.8, 3.5), 0.7, point), 96, 72),
    ]
}

/// Worst error over covered pixels of the GL image against `material.eval`; pixel count.
fn compare(r: &mut Renderer, material: &Material, shading: &Material, scene: &Scene, w: usize, h: usize) -> (f64, usize) {
    compare_gl(r, scene, shading, w, h, TOL, "Material::eval", |q| material.shading(q))
}

fn check(name: &str, material: &Material) {
    let (loaded, shading) = through_disk(material);
    assert_eq!(shading.terms.len(), loaded.terms.len());
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    for (scene_name, scene, w, h) in scenes() {
        let (worst, n) = compare(&mut r, &loaded, &shading, &scene, w, h);
        eprintln!("{name} / {scene_name}: {n} pixels, worst relative error {worst:.2e}");
        assert!(n > 2000, "{name} / {scene_name}: only {n} pixels");
    }
}

#[test]
fn fitted_uniform_1d_material_renders_as_it_evaluates() {
    let model = Analytic::BlinnPhong { diffuse: [0.45, 0.25, 0.12], specular: [0.3, 0.35, 0.4], exponent: 32.0 };
    check("fitted 3x1D", &fitted(1, 64, &model));
}

#[test]
fn fitted_uniform_2d_material_renders_as_it_evaluates() {
    let model = Analytic::Ggx { diffuse: [0.4, 0.25, 0.12], f0: [0.5, 0.42, 0.35], roughness: 0.4 };
    check("fitted 3x2D", &fitted(2, 16, &model));
}

#[test]
fn two_term_material_with_coefficient_textures_renders_as_it_evaluates() {
    let m = two_terms();
    // Both coefficient textures matter: they are not constant over the visible uvs.
    assert!(m.needs_uv());
    check("two terms + coefficients", &m);
}
