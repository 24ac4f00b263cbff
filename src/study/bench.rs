//! `brdfpaint bench`: the thesis's timing tables reproduced on this machine, with the
//! thesis's seconds beside ours (DESIGN.md, Command line).
//!
//! - Table 5.1: three 1D factors, M ∈ {32, 64, 96, 128}, 7.9k samples, and the same with a
//!   fourth 32×32 uv factor.
//! - Table 5.2: three 2D factors, M ∈ {16, 32}, at 317, 10k and 100k samples; and the
//!   thesis's 4-factor column (three 1D factors of 32 and a uv factor of M², 317 samples).
//!
//! Samples are pixels of a painted sphere view (`SphereView`), so the patterns are those of a
//! real painting. `prepare_s` assembles and factors the system; `solve_s` maps RGB values to
//! log space, solves, and returns linear-space tables for one mapping: the work of one refit
//! during painting. The thesis's "fast factorization" column measured the same step.

use std::time::Instant;

use serde::Serialize;

use glow::HasContext;

use super::median;
use crate::brdf::{Analytic, Reflectance, SphereView, Striped};
use crate::error::{Error, Result};
use crate::factor::{prepare, Channels, LogMap, Pattern, Settings};
use crate::render::{Ggx, GpuScene, GpuShading, Renderer};

/// One measured case: the fields of DESIGN.md's `bench --json` that apply.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Case {
    pub case: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub res: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unknowns: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub terms: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub prepare_s: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solve_s: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_s: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// Errors on the fitted samples (thesis Table 5.4: RMS and max, values in [0, 1]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// Relative RMS on views nobody painted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_out: Option<f64>,
    /// The thesis's figure for the step we time as `solve_s` (or `time_s`), where it has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thesis_s: Option<f64>,
    /// The thesis's pre-inversion (SVD) time, beside our `prepare_s`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thesis_prepare_s: Option<f64>,
}

/// The median of repeated timings of `f`: at least `min_runs`, and more until `budget_s`
/// seconds have passed (at most 1000).
pub fn median_time(min_runs: usize, budget_s: f64, mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    let mut times = Vec::new();
    while times.len() < min_runs || (start.elapsed().as_secs_f64() < budget_s && times.len() < 1000) {
        let t = Instant::now();
        f();
        times.push(t.elapsed().as_secs_f64());
    }
    super::median(&times)
}

/// Frame times of the factored and the analytic shader on the same mesh and image size.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FrameTimes {
    /// Median milliseconds per factored frame (all terms), clear to `glFinish`.
    pub factored_ms: f64,
    /// Median milliseconds per analytic GGX frame.
    pub analytic_ms: f64,
    /// `factored_ms / analytic_ms`.
    pub ratio: f64,
    pub frames: usize,
    pub width: usize,
    pub height: usize,
    pub triangles: usize,
}

/// Median frame times of `shading` (all its terms) and the analytic GGX shader and the analytic GGX shader, interleaved
/// frame by frame, each frame a clear, the draw and `glFinish` (after `frames / 10 + 1`
/// untimed warm-up frames of each).
pub fn frame_times(
    renderer: &mut Renderer,
    scene: &GpuScene,
    shading: &GpuShading,
    model: &Ggx,
    width: usize,
    height: usize,
    frames: usize,
) -> Result<FrameTimes> {
    if frames == 0 {
        return Err(Error::input("frame timing needs at least one frame"));
    }
    let (mut factored, mut analytic) = (Vec::with_capacity(frames), Vec::with_capacity(frames));
    let warm = frames / 10 + 1;
    for k in 0..warm + frames {
        let start = Instant::now();
        renderer.begin(width, height)?;
        renderer.draw_factored(scene, shading, width, height)?;
        // SAFETY: waits for the GPU on the current context.
        unsafe { renderer.gl().finish() };
        let t_factored = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        renderer.begin(width, height)?;
        renderer.draw_ggx(scene, model, width, height)?;
        // SAFETY: as above.
        unsafe { renderer.gl().finish() };
        let t_analytic = start.elapsed().as_secs_f64() * 1e3;
        if k >= warm {
            factored.push(t_factored);
            analytic.push(t_analytic);
        }
    }
    let (f, a) = (median(&factored), median(&analytic));
    Ok(FrameTimes {
        factored_ms: f,
        analytic_ms: a,
        ratio: f / a,
        frames,
        width,
        height,
        triangles: scene.triangles(),
    })
}

/// A sphere view with about `target` samples.
fn sphere_pattern(target: usize) -> Pattern {
    // The eroded disc of a res² view holds about π (res/2 − 1)² pixels.
    let res = (2.0 * ((target as f64 / std::f64::consts::PI).sqrt() + 1.0)).round() as usize;
    SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), res.max(4)).pattern()
}

/// The painting every timed case solves: the suite's third model on the case's pattern.
fn case_values(pattern: &Pattern) -> Vec<[f64; 3]> {
    let model = Analytic::suite()[2].clone();
    pattern.shade(|q| model.shading(q))
}

/// The log mapping every timed solve uses.
const CASE_OFFSET: f64 = 0.05;

/// Time prepare and solve for one case.
fn measure(spec: &CaseSpec, quick: bool) -> Result<Case> {
    let (pattern, settings) = (&spec.pattern, &spec.settings);
    let values = case_values(pattern);
    let mut prepared = None;
    let runs = if quick { 1 } else { 3 };
    let mut failure = None;
    let prepare_s = median_time(runs, 0.0, || match prepare(pattern, settings) {
        Ok(p) => prepared = Some(p),
        Err(e) => failure = Some(e),
    });
    if let Some(e) = failure {
        return Err(e);
    }
    let prepared = prepared.expect("prepare ran at least once");
    let map = LogMap::Offset { a: [CASE_OFFSET; 3] };
    let budget = if quick { 0.05 } else { 0.5 };
    let mut result = Ok(());
    let solve_s = median_time(5, budget, || {
        if let Err(e) = prepared.solve_tables(&values, &map) {
            result = Err(e);
        }
    });
    result?;
    Ok(Case {
        case: spec.name.clone(),
        samples: Some(pattern.len()),
        res: Some(spec.res),
        unknowns: Some(prepared.unknowns()),
        prepare_s: Some(prepare_s),
        solve_s: Some(solve_s),
        thesis_s: spec.thesis.map(|t| t.1),
        thesis_prepare_s: spec.thesis.map(|t| t.0),
        ..Default::default()
    })
}

/// One timed factorization case.
struct CaseSpec {
    name: String,
    pattern: Pattern,
    settings: Settings,
    res: usize,
    /// The thesis's (SVD pre-inversion, fast factorization) seconds, where it has the case.
    thesis: Option<(f64, f64)>,
    /// A case of the thesis's tables 5.1 and 5.2 (the reference implementation times those).
    table: bool,
}

/// The cases of thesis Tables 5.1 and 5.2, and the 256² four-factor product beyond them.
fn case_specs() -> Vec<CaseSpec> {
    let mut out = Vec::new();
    let p7884 = sphere_pattern(7884);
    let spec = |name: String, pattern: &Pattern, settings: Settings, res: usize, thesis: Option<(f64, f64)>| CaseSpec {
        name,
        pattern: pattern.clone(),
        settings,
        res,
        thesis,
        table: true,
    };
    // Table 5.1: (res, SVD 3-factor, SVD 4-factor, fast 3-factor, fast 4-factor).
    let t51 = [
        (32, 4.26, 247.36, 0.1834, 1.2649),
        (64, 11.08, 330.04, 0.2868, 1.3207),
        (96, 21.58, 397.37, 0.3842, 1.5919),
        (128, 38.06, 506.11, 0.4375, 1.6877),
    ];
    for (res, svd3, svd4, fast3, fast4) in t51 {
        out.push(spec(format!("table5.1 3x1D M={res}"), &p7884, Settings::uniform(1, res), res, Some((svd3, fast3))));
        out.push(spec(format!("table5.1 4-factor M={res} uv=32"), &p7884, Settings::four_factor(1, res, 32), res, Some((svd4, fast4))));
    }
    // Table 5.2, 3-factor column: (res, SVD, fast) at 317 samples; 100m 12s = 6072 s.
    let t52 = [(16, 103.0, 0.0308), (32, 6072.0, 0.1048)];
    for target in [317, 10_000, 100_000] {
        let pattern = sphere_pattern(target);
        let size = if target < 1000 { target.to_string() } else { format!("{}k", target / 1000) };
        for (res, svd, fast) in t52 {
            let thesis = (target == 317).then_some((svd, fast));
            out.push(spec(format!("table5.2 3x2D M={res} {size} samples"), &pattern, Settings::uniform(2, res), res, thesis));
        }
    }
    // Table 5.2, 4-factor column: 1D factors of 32, a uv factor of res², 317 samples.
    let p317 = sphere_pattern(317);
    for (res, svd, fast) in [(16, 3.77, 0.0160), (32, 13.76, 0.0418), (48, 44.88, 0.0853), (64, 121.55, 0.1409)] {
        out.push(spec(format!("table5.2 4-factor uv={res} 317 samples"), &p317, Settings::four_factor(1, 32, res), res, Some((svd, fast))));
    }
    // Beyond the thesis's 64²: the four-factor product with a 256² uv table (issue targets:
    // prepare ≤ 2 s, solve ≤ 20 ms), at 7.9k samples and at a 512² painting's ~200k.
    for target in [7884, 200_000] {
        let pattern = if target == 7884 { p7884.clone() } else { sphere_pattern(target) };
        let name = format!("4-factor M=128 uv=256 {}k samples", (target + 500) / 1000);
        out.push(CaseSpec { table: false, ..spec(name, &pattern, Settings::four_factor(1, 128, 256), 256, None) });
    }
    out
}

/// The factorization cases of thesis Tables 5.1 and 5.2 (and the 256² product beyond
/// them). `quick` shortens the timing loops (for tests and a first look), not the cases.
pub fn factor_cases(quick: bool) -> Result<Vec<Case>> {
    case_specs().iter().map(|s| measure(s, quick)).collect()
}

/// Writes the systems of Tables 5.1 and 5.2 into `dir` for the reference implementation
/// ([`super::systems`]).
pub fn write_systems(dir: &std::path::Path) -> Result<()> {
    let specs: Vec<CaseSpec> = case_specs().into_iter().filter(|s| s.table).collect();
    let values: Vec<Vec<[f64; 3]>> = specs.iter().map(|s| case_values(&s.pattern)).collect();
    let systems: Vec<super::systems::System<'_>> = specs
        .iter()
        .zip(&values)
        .map(|(s, v)| super::systems::System { name: &s.name, pattern: &s.pattern, settings: &s.settings, values: v, offset: CASE_OFFSET })
        .collect();
    super::systems::write(dir, &systems)
}

/// A human-readable table of cases.
pub fn table(cases: &[Case]) -> String {
    let ms = |x: Option<f64>| x.map_or("-".to_string(), |s| format!("{:.3}", s * 1e3));
    let sec = |x: Option<f64>| x.map_or("-".to_string(), |s| format!("{s:.4}"));
    let mut out = format!(
        "{:<38} {:>8} {:>9} {:>12} {:>11} | {:>12} {:>11}\n",
        "case", "samples", "unknowns", "prepare ms", "solve ms", "thesis SVD s", "thesis fast s"
    );
    for c in cases {
        out += &format!(
            "{:<38} {:>8} {:>9} {:>12} {:>11} | {:>12} {:>11}\n",
            c.case,
            c.samples.map_or("-".into(), |x| x.to_string()),
            c.unknowns.map_or("-".into(), |x| x.to_string()),
            ms(c.prepare_s),
            ms(c.solve_s.or(c.time_s)),
            c.thesis_prepare_s.map_or("-".into(), |s| format!("{s:.2}")),
            sec(c.thesis_s),
        );
    }
    out
}

/// Frame sizes of the GL cases.
const GL_SIZES: [usize; 2] = [512, 1024];

/// The GL cases' material source: the analytic GGX shader's own material (`Ggx::default`)
/// as the CPU model, shaded at 7,884 sphere samples (a painting's worth).
fn ggx_painting() -> (crate::factor::Pattern, Vec<[f64; 3]>) {
    let ggx = Ggx::default();
    let model = Analytic::Ggx {
        diffuse: ggx.diffuse.as_dvec3().to_array(),
        f0: ggx.f0.as_dvec3().to_array(),
        roughness: ggx.roughness as f64,
    };
    let pattern = sphere_pattern(7884);
    let values = pattern.shade(|q| model.shading(q));
    (pattern, values)
}

/// The GL cases: frame time of the factored shader against the analytic GGX shader, the
/// same mesh (the bunny, front-left preset) and image size, measured side by side in one
/// run by [`frame_times`] (frames interleaved, medians, `glFinish` per
/// frame). The factored materials are real fits of the GGX model the analytic shader
/// draws, painted on a sphere view: three 1D factors (M = 128) and three 2D factors
/// (M = 32), the defaults. `time_s` is the factored frame, `ratio` factored / analytic;
/// `res` is the factor resolution, `samples` the fitted samples. Also returns the GL
/// renderer's name. `quick` takes a few frames per case instead of dozens.
pub fn gl_cases(quick: bool) -> Result<(Vec<Case>, String)> {
    use crate::factor::Mapping;
    use crate::gl::HeadlessContext;
    use crate::material::Material;
    use crate::scene::Scene;

    let ggx = Ggx::default();
    let (pattern, values) = ggx_painting();
    let ctx = HeadlessContext::new()?;
    let mut renderer = Renderer::new(ctx.gl())?;
    let scene = GpuScene::upload(ctx.gl(), &Scene::from_preset("bunny", "front-left")?)?;
    let mut out = Vec::new();
    for (name, dim, res) in [("3x1D", 1, crate::factor::defaults::RES_1D), ("3x2D", 2, crate::factor::defaults::RES_2D)] {
        let settings = Settings::uniform(dim, res);
        let fit = prepare(&pattern, &settings)?.solve(&values, Mapping::Auto)?;
        let shading = renderer.upload(&Material::from_fit(&settings, &fit, Default::default())?)?;
        for size in GL_SIZES {
            let frames = match (quick, size) {
                (true, 512) => 6,
                (true, _) => 3,
                (false, 512) => 60,
                (false, _) => 30,
            };
            let t = frame_times(&mut renderer, &scene, &shading, &ggx, size, size, frames)?;
            out.push(Case {
                case: format!("gl factored {name} M={res} vs GGX, bunny {size}x{size}"),
                samples: Some(pattern.len()),
                res: Some(res),
                terms: Some(1),
                time_s: Some(t.factored_ms * 1e-3),
                ratio: Some(t.ratio),
                ..Default::default()
            });
        }
    }
    Ok((out, ctx.renderer().to_string()))
}

/// Environment lighting (`render::env`): for each bundled environment its preparation
/// (`prepare_s`: upload and mip chain, the prefiltering, to `glFinish`; `time_s`: decoding
/// the file), then the frame time of a material under an environment beside its frame under
/// the point light alone, on the same mesh and size, interleaved (`time_s` the environment
/// frame with the key light and the background, `ratio` environment / point light; `samples`
/// the directions per pixel). The material is the 3×1D fit of the GGX model of
/// [`gl_cases`], on the bunny. `quick` times one frame of each.
pub fn env_cases(quick: bool) -> Result<Vec<Case>> {
    use crate::factor::Mapping;
    use crate::gl::HeadlessContext;
    use crate::images::env::{Environment, BUNDLED};
    use crate::material::Material;
    use crate::render::env::DEFAULT_SAMPLES;
    use crate::render::{GpuEnvironment, Lighting};
    use crate::scene::Scene;

    let ctx = HeadlessContext::new()?;
    let mut renderer = Renderer::new(ctx.gl())?;
    let mut out = Vec::new();
    let mut prepared = Vec::new();
    for (name, bytes) in BUNDLED {
        let t = Instant::now();
        let env = Environment::decode(std::path::Path::new(name), bytes)?;
        let decode_s = t.elapsed().as_secs_f64();
        let runs = if quick { 1 } else { 5 };
        let mut times = Vec::new();
        let mut gpu = None;
        for _ in 0..runs {
            let t = Instant::now();
            gpu = Some(GpuEnvironment::upload(ctx.gl(), &env)?);
            // SAFETY: waits for the GPU on the current context.
            unsafe { ctx.gl().finish() };
            times.push(t.elapsed().as_secs_f64());
        }
        out.push(Case {
            case: format!("env prepare {name} {}x{} (upload + mip chain)", env.width, env.height),
            prepare_s: Some(median(&times)),
            time_s: Some(decode_s),
            ..Default::default()
        });
        prepared.push(gpu.expect("at least one run"));
    }

    let (pattern, values) = ggx_painting();
    let res = crate::factor::defaults::RES_1D;
    let settings = Settings::uniform(1, res);
    let fit = prepare(&pattern, &settings)?.solve(&values, Mapping::Auto)?;
    let shading = renderer.upload(&Material::from_fit(&settings, &fit, Default::default())?)?;
    let scene = GpuScene::upload(ctx.gl(), &Scene::from_preset("bunny", "front-left")?)?;
    for (size, samples) in [(512, DEFAULT_SAMPLES), (1024, DEFAULT_SAMPLES), (512, 16)] {
        let lighting = Lighting { key_light: true, samples, ..Lighting::new(&prepared[0]) };
        let frames = if quick { 1 } else if size == 512 { 8 } else { 4 };
        let (mut env_ms, mut point_ms) = (Vec::new(), Vec::new());
        // One untimed frame of each compiles the programs.
        for k in 0..frames + 1 {
            let start = Instant::now();
            renderer.begin(size, size)?;
            renderer.draw_lit(&scene, &shading, &lighting, size, size)?;
            // SAFETY: waits for the GPU on the current context.
            unsafe { renderer.gl().finish() };
            let t_env = start.elapsed().as_secs_f64() * 1e3;
            let start = Instant::now();
            renderer.begin(size, size)?;
            renderer.draw_factored(&scene, &shading, size, size)?;
            // SAFETY: as above.
            unsafe { renderer.gl().finish() };
            let t_point = start.elapsed().as_secs_f64() * 1e3;
            if k > 0 {
                env_ms.push(t_env);
                point_ms.push(t_point);
            }
        }
        let (e, p) = (median(&env_ms), median(&point_ms));
        out.push(Case {
            case: format!("gl env {} 3x1D M={res} vs point light, bunny {size}x{size}", BUNDLED[0].0),
            samples: Some(samples),
            res: Some(res),
            terms: Some(1),
            time_s: Some(e * 1e-3),
            ratio: Some(e / p),
            ..Default::default()
        });
    }
    Ok(out)
}

/// A human-readable table of the environment cases: preparation, then frame times.
pub fn env_table(cases: &[Case]) -> String {
    let mut out = String::new();
    for c in cases.iter().filter(|c| c.prepare_s.is_some()) {
        out += &format!(
            "{:<58} prepare {:>7.2} ms, decode {:>7.2} ms\n",
            c.case,
            c.prepare_s.unwrap_or(f64::NAN) * 1e3,
            c.time_s.unwrap_or(f64::NAN) * 1e3
        );
    }
    out += &format!("{:<58} {:>5} {:>10} {:>10} {:>7}\n", "case", "dirs", "env ms", "point ms", "ratio");
    for c in cases.iter().filter(|c| c.prepare_s.is_none()) {
        let (t, r) = (c.time_s.unwrap_or(f64::NAN), c.ratio.unwrap_or(f64::NAN));
        out += &format!("{:<58} {:>5} {:>10.1} {:>10.1} {:>7.1}\n", c.case, c.samples.unwrap_or(0), t * 1e3, t / r * 1e3, r);
    }
    out
}

/// A human-readable table of GL cases: factored and analytic frame times and their ratio.
pub fn gl_table(cases: &[Case]) -> String {
    let mut out = format!("{:<46} {:>12} {:>12} {:>7}\n", "case", "factored ms", "analytic ms", "ratio");
    for c in cases {
        let (t, r) = (c.time_s.unwrap_or(f64::NAN), c.ratio.unwrap_or(f64::NAN));
        out += &format!("{:<46} {:>12.2} {:>12.2} {:>7.2}\n", c.case, t * 1e3, t / r * 1e3, r);
    }
    out
}

/// Thesis Table 5.3: material maps with J ∈ {5, 10, 15, 20} terms at factor resolution 32
/// and 128, ~7.9k samples, by both fits: `greedy` (the thesis's, eqs. 4.2–4.4) and
/// `cluster` (brdfpaint's default). The painting is a sphere with a glossy and a matte BRDF
/// in stripes of u; the system is prepared once. Fitting runs all J terms (no early stop).
/// `time_s` is the whole fit after the prepare; the thesis's seconds are beside it.
pub fn material_map_cases(quick: bool) -> Result<Vec<Case>> {
    use crate::material::map::{self, MapOptions, Method};
    let (pattern, values, grids) = Striped::wood().paint(&[SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), 102)]);
    let thesis = [(32, [2.44, 5.73, 8.91, 12.09]), (128, [3.96, 8.66, 12.64, 17.79])];
    let mut out = Vec::new();
    for (factor_res, seconds) in thesis {
        let prepared = prepare(&pattern, &Settings::uniform(1, factor_res))?;
        for method in [Method::Greedy, Method::Cluster] {
            for (terms, thesis_s) in [5, 10, 15, 20].into_iter().zip(seconds) {
                let opts = MapOptions { terms, min_gain: 0.0, method, ..Default::default() };
                let mut result = Ok(());
                let time_s = median_time(if quick { 1 } else { 3 }, 0.0, || {
                    if let Err(e) = map::fit(&prepared, &pattern, &values, &grids, &opts) {
                        result = Err(e);
                    }
                });
                result?;
                out.push(Case {
                    case: format!("table5.3 map {} J={terms} M={factor_res}", method_name(method)),
                    samples: Some(pattern.len()),
                    res: Some(factor_res),
                    terms: Some(terms),
                    time_s: Some(time_s),
                    thesis_s: Some(thesis_s),
                    ..Default::default()
                });
            }
        }
    }
    Ok(out)
}

fn method_name(m: crate::material::map::Method) -> &'static str {
    match m {
        crate::material::map::Method::Greedy => "greedy",
        crate::material::map::Method::Cluster => "cluster",
    }
}

/// Thesis Table 5.4's error metrics (RMS, max, on sample values in [0, 1]) on a spatially
/// varying test object: the striped sphere of [`Striped::wood`] painted from four views
/// that together see all of it (90² each), fitted as a material map with 1–5 terms by
/// both fits and as a four-factor product (uv 64²). `rms`, `max`: on the painted samples;
/// `held_out`: relative RMS on four views under new lights.
pub fn fidelity_cases() -> Result<Vec<Case>> {
    use crate::material::map::{self, MapOptions, Method};
    use crate::material::Material;
    let object = Striped::wood();
    let (pattern, values, grids) = object.paint(&Striped::painted_views(90));
    let held = Striped::held_out_views(90);
    let judge = |m: &Material| super::sphere_rms(&held, |q| object.shading(q), |q| m.shading(q));
    let prepared = prepare(&pattern, &Settings::default())?;
    let mut out = Vec::new();
    for method in [Method::Greedy, Method::Cluster] {
        for terms in 1..=5 {
            let opts = MapOptions { terms, min_gain: 0.0, method, ..Default::default() };
            let (material, report) = map::fit(&prepared, &pattern, &values, &grids, &opts)?;
            out.push(Case {
                case: format!("table5.4 map {} J={terms}", method_name(method)),
                samples: Some(pattern.len()),
                terms: Some(material.terms.len()),
                rms: Some(report.fitted.rms),
                max: Some(report.fitted.max),
                held_out: Some(judge(&material)),
                time_s: Some(report.seconds),
                ..Default::default()
            });
        }
    }
    let settings = Settings::four_factor(1, crate::factor::defaults::RES_1D, 64);
    let four = prepare(&pattern, &settings)?;
    let fit = four.solve(&values, crate::factor::Mapping::Auto)?;
    let material = Material::from_fit(&settings, &fit, Default::default())?;
    out.push(Case {
        case: "table5.4 four-factor uv=64".into(),
        samples: Some(pattern.len()),
        rms: Some(fit.errors.rms),
        max: Some(fit.errors.max),
        held_out: Some(judge(&material)),
        ..Default::default()
    });
    Ok(out)
}

/// Table 5.4's rows as text.
pub fn fidelity_table(cases: &[Case]) -> String {
    let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.4}"));
    let mut out = format!("{:<30} {:>6} {:>8} {:>8} {:>9} {:>9}\n", "case", "terms", "RMS", "max", "held-out", "fit ms");
    for c in cases {
        out += &format!(
            "{:<30} {:>6} {:>8} {:>8} {:>9} {:>9}\n",
            c.case,
            c.terms.map_or("-".into(), |x| x.to_string()),
            f(c.rms),
            f(c.max),
            f(c.held_out),
            c.time_s.map_or("-".into(), |s| format!("{:.1}", s * 1e3)),
        );
    }
    out
}

/// The live-paint loop of `brdfpaint view` (thesis 4.1), headless: strokes on a 512² painting
/// of the bunny, each followed by the viewer's own refit (painted colours → values → solve →
/// material → texture upload → a frame drawn to `glFinish`). `time_s` is the median stroke →
/// frame time; it must fit in one 60 Hz frame (16.7 ms). The second case is the same strokes
/// while the full fit the window settles on runs on its worker; the third that fit's own time.
pub fn live_paint_cases(quick: bool) -> Result<Vec<Case>> {
    let strokes = if quick { 10 } else { 60 };
    let t = super::measure_stroke_to_frame("bunny", 512, strokes, Channels::default())?;
    // Coupled channels in the same run: what coupling the colour costs a stroke.
    let coupled = super::measure_stroke_to_frame("bunny", 512, strokes, Channels::Coupled)?;
    let case = |what: &str, t: &super::StrokeTiming, total_ms: f64| Case {
        case: format!("live paint stroke -> frame{what}, bunny 512x512"),
        samples: Some(t.samples),
        res: Some(t.size),
        unknowns: Some(t.unknowns),
        time_s: Some(total_ms / 1e3),
        ..Default::default()
    };
    let settle = Case { case: "live paint full fit after the pause, bunny 512x512".into(), ..case("", &t, t.full_fit_ms) };
    Ok(vec![
        case("", &t, t.total_ms),
        case(" during the full fit", &t, t.total_during_fit_ms),
        case(", coupled channels", &coupled, coupled.total_ms),
        settle,
    ])
}

/// `brdfpaint fit --scene` of one 512² painting without its start-up and files (issue 11:
/// under 1 s): the painting read as evidence ([`crate::read::Reader`]: tones, light,
/// strays) and fitted as `fit` does by default (uniform, the analytic base `auto`). A
/// Blinn-Phong sphere painted front-left, as rendered and in 6 flat tones per channel (the
/// reading's most expensive case). `time_s` is the median of read + fit, the prepared system
/// loaded from a cache as `fit`'s is for a scene it has seen (the first, storing run is one
/// of at least three).
pub fn read_fit_cases(quick: bool) -> Result<Vec<Case>> {
    let dir = std::env::temp_dir().join(format!("brdfpaint-bench-cache-{}", std::process::id()));
    let cases = read_fit_cases_in(quick, &crate::factor::cache::Cache::new(&dir));
    let _ = std::fs::remove_dir_all(&dir);
    cases
}

fn read_fit_cases_in(quick: bool, cache: &crate::factor::cache::Cache) -> Result<Vec<Case>> {
    use super::faults::{self, FaultyView, Faults};
    const SIZE: usize = 512;
    let mut sampler = crate::sample::SceneSampler::new()?;
    let view = FaultyView::new(&mut sampler, &super::fidelity::painted_presets(1)[0], SIZE, 0.0)?;
    let model = faults::suite().into_iter().find(|m| m.name() == "blinn-phong-8").ok_or_else(|| Error::Numeric("no blinn-phong-8 in the faults suite".into()))?;
    let opts = crate::pipeline::Options { base: crate::read::lobe::BaseChoice::Auto, ..Default::default() };
    let mut cases = Vec::new();
    for (name, f) in [("as rendered", Faults::clean()), ("6 flat tones", Faults::posterized())] {
        let painted = faults::paint(&view, &model, &f)?;
        let samples = painted.geometry.sample_pixels(&painted.painting).len();
        let mut failed = None;
        let t = median_time(if quick { 3 } else { 7 }, 0.0, || {
            let gbuffers = [&view.view.gbuffer];
            let run = crate::read::Reader::new(crate::read::Reading::default(), &gbuffers)
                .read(vec![painted.clone()])
                .and_then(|read| crate::pipeline::fit(&read.views, &opts, Some(cache)));
            if let Err(e) = run {
                failed = Some(e);
            }
        });
        if let Some(e) = failed {
            return Err(e);
        }
        cases.push(Case { case: format!("read + fit {SIZE}x{SIZE} painting, {name}"), samples: Some(samples), res: Some(SIZE), time_s: Some(t), ..Default::default() });
    }
    Ok(cases)
}
