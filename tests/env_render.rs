//! Materials under HDR environments (`Renderer::lit`, shaders/env.frag) against a CPU
//! Monte-Carlo estimate of the same integral, at pixel centres:
//!
//! $$ L_o = \int_{H^2} S(l, v, uv)\, L_{env}(l)\, d\omega_l, $$
//!
//! with $S$ evaluated by `gl_common::cpu_shading` (through `brdfpaint::factor`, not the
//! renderer) and the environment by `Environment::radiance` (bilinear, as the GPU's level 0).

mod gl_common;

use std::f64::consts::PI;

use brdfpaint::factor::{Domain, Input, LogMap, Param, Query};
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::env::{uv_to_direction, Environment};
use brdfpaint::material::{Coefficients, Factor, Material, Term};
use brdfpaint::render::env::DEFAULT_SAMPLES;
use brdfpaint::render::{Background, GBuffer, GpuEnvironment, GpuScene, Image, Lighting, Renderer};
use brdfpaint::scene::Scene;
use gl_common::*;
use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const RES: usize = 48;

/// Stated error of the GPU estimator against the reference, relative to the brightest
/// reference pixel of the image: (worst pixel, mean over pixels). With the default 64
/// directions the worst pixels are the highlight of the sky's bright "sun" and grazing
/// views of it (measured 5-8%, means 0.4-0.9%); with 256 the estimator has converged to
/// within the reference's own noise and the filtering blur (measured worst 1.5-2%, means
/// 0.1-0.2%).
const DEFAULT_TOL: (f64, f64) = (0.10, 0.015);
const CONVERGED_TOL: (f64, f64) = (0.03, 0.005);
/// The furnace's tolerance, absolute on a white environment: the fixed 64-direction pattern
/// is exact in expectation, and off by up to 2.3% (Lambert) and 3.1% (glossy) at grazing
/// views, where half of the mirror lobes' directions fall below the horizon.
const FURNACE_TOL: f64 = 0.04;

fn identity() -> LogMap {
    LogMap::Identity { floor: [1e-3; 3] }
}

/// A smooth sky with some structure: brighter above, a warm broad "sun" and a cool glow
/// on the other side, sampled at the pixel centres of a 64x32 map.
fn sky() -> Environment {
    let (w, h) = (64, 32);
    let sun = DVec3::new(0.6, 0.5, 0.62).normalize();
    let glow = DVec3::new(-0.7, 0.1, -0.7).normalize();
    let pixels = (0..w * h)
        .map(|k| {
            let d = uv_to_direction((k % w) as f64 / w as f64 + 0.5 / w as f64, (k / w) as f64 / h as f64 + 0.5 / h as f64);
            let a = d.dot(sun).max(0.0).powi(6);
            let b = d.dot(glow).max(0.0).powi(3);
            let base = 0.35 + 0.25 * d.y;
            [base + 3.0 * a + 0.2 * b, base + 2.0 * a + 0.4 * b, base + 1.0 * a + 0.9 * b].map(|x| x as f32)
        })
        .collect();
    Environment::new(w, h, pixels).unwrap()
}

/// World direction of local-frame direction `l` at a G-buffer pixel.
fn frame(px: &brdfpaint::render::GPixel) -> (DVec3, DVec3, DVec3) {
    let n = px.normal.as_dvec3().normalize();
    let t = px.tangent.truncate().as_dvec3().normalize();
    let b = n.cross(t) * if px.tangent.w < 0.0 { -1.0 } else { 1.0 };
    (t, b, n)
}

/// The reference: stratified Monte Carlo over the hemisphere, `side`² jittered strata of
/// uniform density $1/2\pi$, seeded.
fn reference(material: &Material, env: &Environment, rotate_deg: f64, q: &Query, tbn: (DVec3, DVec3, DVec3), side: usize, seed: u64) -> [f64; 3] {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (t, b, n) = tbn;
    let mut sum = [0.0; 3];
    for i in 0..side {
        for j in 0..side {
            let (x1, x2) = ((i as f64 + rng.random::<f64>()) / side as f64, (j as f64 + rng.random::<f64>()) / side as f64);
            let z = x1;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * x2;
            let l = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            let s = cpu_shading(material, &Query { l, v: q.v, uv: q.uv });
            let radiance = env.radiance(t * l.x + b * l.y + n * l.z, rotate_deg);
            for c in 0..3 {
                sum[c] += s[c] * radiance[c];
            }
        }
    }
    let weight = 2.0 * PI / (side * side) as f64;
    sum.map(|x| x * weight)
}

/// The environment alone, shown behind the object (`Lighting::new` with a lifetime the
/// closures of `render` accept).
fn plain(e: &GpuEnvironment) -> Lighting<'_> {
    Lighting::new(e)
}

fn render(r: &mut Renderer, scene: &Scene, material: &Material, env: &Environment, lighting: impl Fn(&GpuEnvironment) -> Lighting) -> (Image, GBuffer) {
    let gpu = GpuScene::upload(r.gl(), scene).unwrap();
    let shading = r.upload(material).unwrap();
    let genv = GpuEnvironment::upload(r.gl(), env).unwrap();
    let image = r.lit(&gpu, &shading, &lighting(&genv), RES, RES).unwrap();
    let g = r.gbuffer(&gpu, RES, RES).unwrap();
    (image, g)
}

/// Compares every 3rd covered pixel with the reference; returns (worst, mean) errors
/// relative to the brightest reference pixel.
fn compare(material: &Material, camera: DVec3, rotate_deg: f32, samples: usize, tol: (f64, f64), what: &str) -> (f64, f64) {
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let env = sky();
    let scene = ortho_sphere(camera, sun(DVec3::Y, [1.0; 3]));
    let (image, g) = render(&mut r, &scene, material, &env, |e| Lighting {
        rotate_deg,
        background: Background::Color(Vec3::ZERO),
        samples,
        ..Lighting::new(e)
    });
    let mut cases = Vec::new();
    for j in (1..RES).step_by(3) {
        for i in (1..RES).step_by(3) {
            let px = g.at(i, j);
            // Pixels whose shading normal turns from the camera (silhouette) are skipped:
            // there the hemisphere is mostly behind the surface and both estimates are ~0.
            let Some(q) = px.query().filter(|q| q.v.z > 0.05) else { continue };
            let want = reference(material, &env, rotate_deg as f64, &q, frame(px), 96, (j * RES + i) as u64);
            cases.push(((i, j), image.at(i, j), want, q));
        }
    }
    let scale = cases.iter().flat_map(|c| c.2).fold(0.0f64, f64::max);
    assert!(scale > 0.05, "{what}: the reference is black");
    let (mut worst, mut total, mut count) = (0.0f64, 0.0, 0);
    for ((i, j), got, want, q) in &cases {
        let e = rel_err(*got, *want, scale);
        assert!(
            e < tol.0,
            "{what}: pixel ({i}, {j}): GL {got:?} vs Monte Carlo {want:?} (error {e:.3} of {scale:.3}); v {:?} uv {:?}",
            q.v,
            q.uv
        );
        worst = worst.max(e);
        total += (0..3).map(|c| (got[c] as f64 - want[c]).abs()).sum::<f64>() / 3.0;
        count += 1;
    }
    let mean = total / count as f64 / scale;
    eprintln!("{what}: {count} pixels, worst {worst:.4}, mean {mean:.4} of the brightest");
    assert!(mean < tol.1, "{what}: mean error {mean:.4} of the brightest pixel");
    assert!(count > 100, "{what}: only {count} pixels compared");
    (worst, mean)
}

/// A glossy 1D table over the radius of h: a floor plus a peak at the normal.
fn lobe(res: usize, floor: f32, peak: f32, width: f64) -> Factor {
    let texels = (0..res)
        .map(|k| {
            let t = k as f64 / (res - 1) as f64;
            [floor + peak * (-(t / width).powi(2)).exp() as f32; 3]
        })
        .collect();
    Factor { spec: spec(Input::Half, Param::Radius, Domain::Sphere, res), texels }
}

/// $\cos\theta_l$ over the light's radius (hemisphere domain: $t = \tan(\theta/2)$,
/// so $\cos\theta = (1 - t^2)/(1 + t^2)$), times `k`.
fn cosine(res: usize, k: [f32; 3]) -> Factor {
    let texels = (0..res)
        .map(|i| {
            let t = i as f32 / (res - 1) as f32;
            let c = (1.0 - t * t) / (1.0 + t * t);
            k.map(|x| x * c)
        })
        .collect();
    Factor { spec: spec(Input::Light, Param::Radius, Domain::Hemisphere, res), texels }
}

#[test]
fn one_d_factors_match_monte_carlo() {
    // p(l) q(h) r(v): a diffuse cosine, a glossy lobe on h, a smooth view factor.
    let material = uniform(Term { base: None,
        factors: vec![
            cosine(32, [0.25, 0.2, 0.15]),
            lobe(32, 0.6, 3.0, 0.12),
            smooth_factor(spec(Input::View, Param::Radius, Domain::Sphere, 16)),
        ],
        map: identity(),
        coefficients: None,
    });
    let camera = DVec3::new(0.2, 0.3, 1.0);
    compare(&material, camera, 0.0, DEFAULT_SAMPLES, DEFAULT_TOL, "1D p(l) q(h) r(v)");
    compare(&material, camera, 0.0, 256, CONVERGED_TOL, "1D p(l) q(h) r(v), 256 directions");
}

/// A term over an analytic GGX base (issue 15): the environment pass evaluates the base
/// through the same `term_product` as the key-light pass, so its estimate of a glossy GGX
/// lobe under the sky must meet the same stated tolerances against Monte Carlo (measured
/// worst 5.2%, mean 0.65% with 64 directions; 1.4%, 0.17% with 256).
#[test]
fn a_term_over_an_analytic_base_matches_monte_carlo() {
    use brdfpaint::brdf::lobe::{Base, Lobe};
    let base = Base { ambient: [0.0; 3], diffuse: [0.2, 0.15, 0.1], specular: [0.3, 0.3, 0.35], fresnel: [0.5, 0.5, 0.45], alpha: 0.3, lobe: Lobe::Ggx };
    let material = uniform(Term {
        base: Some(base),
        factors: vec![smooth_factor(spec(Input::View, Param::Radius, Domain::Sphere, 16))],
        map: identity(),
        coefficients: None,
    });
    let camera = DVec3::new(0.2, 0.3, 1.0);
    compare(&material, camera, 0.0, DEFAULT_SAMPLES, DEFAULT_TOL, "GGX base times r(v)");
    compare(&material, camera, 0.0, 256, CONVERGED_TOL, "GGX base times r(v), 256 directions");
}

#[test]
fn two_d_factors_match_monte_carlo_and_rotation() {
    // Parabolic 2D factors of l and h (anisotropic: they see the tangent frame).
    let material = uniform(Term { base: None,
        factors: vec![
            cosine(32, [0.3, 0.25, 0.2]),
            smooth_factor(spec(Input::Light, Param::Parabolic, Domain::Sphere, 12)),
            smooth_factor(spec(Input::Half, Param::Parabolic, Domain::Hemisphere, 12)),
        ],
        map: identity(),
        coefficients: None,
    });
    let camera = DVec3::new(-0.4, 0.2, 1.0);
    compare(&material, camera, 0.0, DEFAULT_SAMPLES, DEFAULT_TOL, "2D factors");
    compare(&material, camera, 70.0, DEFAULT_SAMPLES, DEFAULT_TOL, "2D factors, environment turned 70 degrees");
    compare(&material, camera, 0.0, 256, CONVERGED_TOL, "2D factors, 256 directions");
}

#[test]
fn material_map_matches_monte_carlo() {
    // Two terms blended by coefficient textures over uv, one with an offset mapping.
    let rough = Term { base: None,
        factors: vec![cosine(32, [0.3, 0.15, 0.1])],
        map: identity(),
        coefficients: Some(Coefficients::grey(4, &[1.0, 0.2, 0.8, 0.0, 0.5, 1.0, 0.1, 0.9, 0.3, 0.7, 1.0, 0.2, 0.0, 0.6, 0.4, 1.0])),
    };
    let shiny = Term { base: None,
        factors: vec![cosine(32, [1.0; 3]), lobe(32, 1.2, 2.0, 0.1)],
        map: LogMap::Offset { a: [0.05; 3] },
        coefficients: Some(Coefficients::grey(2, &[0.05, 0.2, 0.15, 0.0])),
    };
    let material = map_of(vec![rough, shiny]);
    compare(&material, DVec3::new(0.3, 0.5, 1.0), 0.0, DEFAULT_SAMPLES, DEFAULT_TOL, "material map");
    compare(&material, DVec3::new(0.3, 0.5, 1.0), 0.0, 256, CONVERGED_TOL, "material map, 256 directions");
}

/// The furnace: under a constant white environment a Lambertian material,
/// $S = (\rho/\pi)\cos\theta_l$, shows its albedo $\rho$ at every pixel.
#[test]
fn furnace_lambertian_shows_its_albedo() {
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let albedo = [0.8, 0.5, 0.2];
    let material = uniform(Term { base: None, factors: vec![cosine(64, albedo.map(|a| a / std::f32::consts::PI))], map: identity(), coefficients: None });
    let scene = ortho_sphere(DVec3::new(0.3, 0.2, 1.0), sun(DVec3::Y, [1.0; 3]));
    let (image, g) = render(&mut r, &scene, &material, &Environment::uniform([1.0; 3]), plain);
    let mut worst = 0.0f64;
    let mut n = 0;
    for j in 0..RES {
        for i in 0..RES {
            let Some(q) = g.at(i, j).query() else { continue };
            let got = image.at(i, j);
            let e = rel_err(got, albedo.map(f64::from), 1.0);
            assert!(e < FURNACE_TOL, "pixel ({i}, {j}): {got:?} vs albedo {albedo:?}; v {:?}", q.v);
            worst = worst.max(e);
            n += 1;
        }
    }
    eprintln!("furnace: {n} pixels, worst error {worst:.5}");
    assert!(n > 1000);
}

/// The furnace with an energy-conserving glossy factored material (its directional albedo
/// $\int S\, d\omega \le 1$ for every view, computed here on the CPU): no pixel exceeds 1,
/// and each is its albedo.
#[test]
fn furnace_energy_conserving_material_never_exceeds_one() {
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let unscaled = uniform(Term { base: None, factors: vec![cosine(32, [1.0; 3]), lobe(32, 0.3, 6.0, 0.08)], map: identity(), coefficients: None });
    let scene = ortho_sphere(DVec3::new(0.1, 0.4, 1.0), sun(DVec3::Y, [1.0; 3]));
    let white = Environment::uniform([1.0; 3]);
    // Scale the material so its largest albedo over the views seen is 0.97.
    let gpu = GpuScene::upload(r.gl(), &scene).unwrap();
    let g = r.gbuffer(&gpu, RES, RES).unwrap();
    let albedo = |m: &Material, px: &brdfpaint::render::GPixel| {
        let q = px.query().unwrap();
        reference(m, &white, 0.0, &q, frame(px), 128, 7)[0]
    };
    let seen: Vec<_> = g.pixels.iter().filter(|p| p.hit).step_by(37).collect();
    let peak = seen.iter().map(|p| albedo(&unscaled, p)).fold(0.0, f64::max);
    let k = (0.97 / peak) as f32;
    let mut material = unscaled.clone();
    for t in &mut material.terms[0].factors[0].texels {
        *t = t.map(|x| x * k);
    }
    let (image, g) = render(&mut r, &scene, &material, &white, plain);
    let (mut brightest, mut worst) = (0.0f32, 0.0f64);
    for j in 0..RES {
        for i in 0..RES {
            let px = g.at(i, j);
            if !px.hit {
                continue;
            }
            let got = image.at(i, j);
            assert!(got[0] <= 1.0, "pixel ({i}, {j}): {got:?} exceeds 1 in the furnace");
            brightest = brightest.max(got[0]);
            if (i * 7 + j) % 11 == 0 && px.v.z > 0.05 {
                let want = albedo(&material, px);
                worst = worst.max((got[0] as f64 - want).abs());
                assert!((got[0] as f64 - want).abs() < FURNACE_TOL, "pixel ({i}, {j}): {} vs albedo {want}", got[0]);
            }
        }
    }
    eprintln!("furnace, glossy: brightest pixel {brightest}, worst error against the albedo {worst:.4}");
    assert!(brightest > 0.85, "the glossy furnace peaks at {brightest}: the test would not see an excess");
}

/// Turning the environment by 180 degrees equals rendering the image whose columns are
/// shifted by half its width; and it changes the image.
#[test]
fn rotation_by_half_a_turn_equals_the_shifted_image() {
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let env = sky();
    let shifted = Environment::new(
        env.width,
        env.height,
        (0..env.width * env.height).map(|k| env.pixels[(k / env.width) * env.width + (k % env.width + env.width / 2) % env.width]).collect(),
    )
    .unwrap();
    let material = uniform(Term { base: None, factors: vec![cosine(32, [0.3; 3]), lobe(32, 0.5, 3.0, 0.15)], map: identity(), coefficients: None });
    let scene = perspective_sphere(DVec3::new(0.5, 0.8, 3.0), 0.9, sun(DVec3::Y, [1.0; 3]));
    let (turned, _) = render(&mut r, &scene, &material, &env, |e| Lighting { rotate_deg: 180.0, ..Lighting::new(e) });
    let (shifted_image, _) = render(&mut r, &scene, &material, &shifted, plain);
    let (unturned, _) = render(&mut r, &scene, &material, &env, plain);
    let diff = |a: &Image, b: &Image| {
        a.pixels.iter().zip(&b.pixels).map(|(x, y)| (0..3).map(|c| (x[c] - y[c]).abs()).fold(0.0f32, f32::max)).fold(0.0f32, f32::max)
    };
    let same = diff(&turned, &shifted_image);
    let changed = diff(&turned, &unturned);
    eprintln!("rotation: turned vs shifted {same:.2e}, turned vs unturned {changed:.3}");
    assert!(same < 1e-3, "turning by 180 degrees differs from the shifted image by {same}");
    assert!(changed > 0.1, "turning by 180 degrees changed nothing ({changed})");
}

/// A black environment with the key light is the key-light render itself.
#[test]
fn black_environment_with_the_key_light_is_the_point_light_render() {
    let ctx = HeadlessContext::new().unwrap();
    let mut r = Renderer::new(ctx.gl()).unwrap();
    let material = uniform(Term { base: None,
        factors: vec![cosine(32, [0.3; 3]), smooth_factor(spec(Input::Half, Param::Parabolic, Domain::Sphere, 8))],
        map: identity(),
        coefficients: None,
    });
    let scene = ortho_sphere(DVec3::Z, sun(DVec3::new(0.5, 0.6, 1.0), [1.0, 0.9, 0.7]));
    let (lit, _) = render(&mut r, &scene, &material, &Environment::uniform([0.0; 3]), |e| Lighting {
        key_light: true,
        ..Lighting::new(e)
    });
    let gpu = GpuScene::upload(r.gl(), &scene).unwrap();
    let shading = r.upload(&material).unwrap();
    let point = r.factored(&gpu, &shading, RES, RES).unwrap();
    let mut brightest = 0.0f32;
    for (a, b) in lit.pixels.iter().zip(&point.pixels) {
        for c in 0..4 {
            assert!((a[c] - b[c]).abs() < 1e-6, "{a:?} vs {b:?}");
        }
        brightest = brightest.max(b[0]);
    }
    assert!(brightest > 0.1);
}
