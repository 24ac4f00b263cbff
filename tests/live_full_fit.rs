//! Live painting settles on the material `brdfpaint fit` writes for the same painting
//! (issue 34, item 6): once the strokes pause, the session runs the full reading and fit on a
//! worker and shows it; a stroke during that fit discards it.
#![cfg(feature = "viewer")]

use std::path::{Path, PathBuf};
use std::time::Instant;

use brdfpaint::brdf::Reflectance;
use brdfpaint::factor::{Mapping, Query, Settings};
use brdfpaint::gl::HeadlessContext;
use brdfpaint::images::Painting;
use brdfpaint::live::full::PAUSE;
use brdfpaint::live::{Brush, PaintSession, PaintView};
use brdfpaint::material::{Kind, Material};
use brdfpaint::note::Note;
use brdfpaint::pipeline::{self, Options};
use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::read::Reading;
use brdfpaint::render::Renderer;
use brdfpaint::sample::{Erosion, SceneSampler};
use brdfpaint::scene::Scene;
use glam::{DVec2, DVec3, Vec2};

const SIZE: usize = 128;

/// Identical inputs through the same code give the same numbers; the one freedom left is the
/// order of parallel sums, $n\,\varepsilon\,\kappa \approx 10^4 \cdot 10^{-16} \cdot 10^3$.
const SAME: f64 = 1e-9;

/// A glossy orange sphere painted over the reference shading, with two strokes the shading
/// does not explain (what the reading repaints), as a file `fit` reads: the canvas is set to
/// the file's own pixels, so the window and `fit` start from the same values.
fn painted_session(renderer: &mut Renderer, dir: &Path) -> (PaintSession, PathBuf, PathBuf) {
    let scene_path = dir.join("scene.gltf");
    Scene::from_preset("sphere", "front-left").unwrap().write_gltf(&scene_path).unwrap();
    let painting_path = dir.join("painting.png");
    let name = painting_path.display().to_string();
    let mut view = PaintView::new(renderer, &name, Scene::load(&scene_path).unwrap(), SIZE, SIZE).unwrap();
    let mut p = view.reference_painting();
    for px in &mut p.pixels {
        *px = [px[0] * 0.9, px[1] * 0.45, px[2] * 0.2];
    }
    view.canvas.set_painting(&p).unwrap();
    let s = SIZE as f32;
    let brush = Brush { color: [0.05, 0.3, 0.6], radius: 3.0, hardness: 0.5, opacity: 1.0, erase: false };
    view.canvas.stroke(brush, &[Vec2::new(0.35 * s, 0.6 * s), Vec2::new(0.5 * s, 0.65 * s)]);
    view.canvas.stroke(brush, &[Vec2::new(0.6 * s, 0.3 * s), Vec2::new(0.62 * s, 0.42 * s)]);
    view.canvas.painting().write(&painting_path).unwrap();
    view.canvas.set_painting(&Painting::read(&painting_path).unwrap()).unwrap();
    let mut session = PaintSession::new(Settings::default(), Mapping::Auto);
    session.add_view(view);
    (session, scene_path, painting_path)
}

/// `brdfpaint fit --scene S --image P` with no other flags, step by step as `cli/fit.rs`
/// runs it: load, read, fit with `--base auto`, the load's and the reading's notes first.
fn fit_command(scene: &Path, painting: &Path) -> (Material, Vec<Note>) {
    let mut sampler = SceneSampler::new().unwrap();
    let mut loaded = pipeline::load_views(&mut sampler, &[(scene.to_path_buf(), painting.to_path_buf())], Erosion::default()).unwrap();
    loaded.read(&Reading::default(), Kind::Uniform).unwrap();
    let opts = Options { base: BaseChoice::Auto, ..Options::new(Kind::Uniform, 1, None, None, None).unwrap() };
    let mut fitted = pipeline::fit(&loaded.views, &opts, None).unwrap();
    fitted.prepend_notes(&loaded.notes);
    (fitted.material, fitted.notes)
}

/// Queries over the hemisphere: light and view on a grid of directions, uv on a grid.
fn queries() -> Vec<Query> {
    let dir = |t: f64, p: f64| DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
    let mut out = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            for k in 0..4 {
                let l = dir(0.25 * i as f64, 1.1 * k as f64);
                let v = dir(0.25 * j as f64, 0.4 + 0.9 * k as f64);
                out.push(Query { l, v, uv: DVec2::new(i as f64 / 6.0, j as f64 / 6.0) });
            }
        }
    }
    out
}

/// The largest relative difference of `a` from `b` over [`queries`], and where.
fn largest_difference(a: &Material, b: &Material) -> (f64, Query) {
    let mut worst = (0.0, queries()[0]);
    for q in queries() {
        let (x, y) = (a.shading(&q), b.shading(&q));
        for c in 0..3 {
            let d = (x[c] - y[c]).abs() / (1e-6 + y[c].abs());
            if d > worst.0 {
                worst = (d, q);
            }
        }
    }
    worst
}

/// Lets the strokes pause: the first poll sees the paintings, the one a pause later starts
/// the full fit, and the wait takes it.
fn pause_and_settle(session: &mut PaintSession) -> bool {
    let t0 = Instant::now();
    assert!(!session.poll_full(t0).unwrap(), "nothing landed yet");
    assert!(session.full_owed());
    assert!(!session.poll_full(t0 + PAUSE / 2).unwrap(), "no fit before the pause");
    session.poll_full(t0 + PAUSE).unwrap();
    session.wait_full().unwrap()
}

#[test]
fn the_window_settles_on_the_material_fit_writes() {
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let (mut session, scene, painting) = painted_session(&mut renderer, dir.path());
    session.settle().unwrap();
    let live = session.material().unwrap().clone();
    assert!(session.full_fit().is_none());

    assert!(pause_and_settle(&mut session), "the full fit of the paintings as they are lands");
    assert!(!session.full_owed(), "nothing more to fit");
    let full = session.full_fit().unwrap().clone();
    let shown = session.material().unwrap();
    assert!(std::ptr::eq(shown, &session.full_fit().unwrap().material), "the window shows the full fit");

    let (fit, notes) = fit_command(&scene, &painting);
    // The same reading and choice of base.
    assert_eq!(full.notes, notes, "the same notes");
    assert!(notes.iter().any(|n| matches!(n, Note::Strays { .. })), "the reading repainted the strokes: {notes:?}");
    let (base, fit_base) = (full.material.terms[0].base, fit.terms[0].base);
    assert_eq!(base.map(|b| b.lobe.name()), fit_base.map(|b| b.lobe.name()), "the same base");
    assert!(fit_base.is_some(), "a glossy painting gets a lobe under the product");
    // The same material.
    let (d, q) = largest_difference(&full.material, &fit);
    assert!(d <= SAME, "window vs fit: relative difference {d:e} at {q:?}");
    assert_eq!(full.material.terms[0].map, fit.terms[0].map, "the same mapping");
    // And the comparison can tell: the plain product shown while painting is another material.
    let (d, q) = largest_difference(&live, &fit);
    assert!(d > 1e3 * SAME, "the live refit differs from fit's material (only {d:e} at {q:?})");
}

#[test]
fn a_stroke_during_the_full_fit_discards_it() {
    let ctx = HeadlessContext::new().unwrap();
    let mut renderer = Renderer::new(ctx.gl()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let (mut session, _, _) = painted_session(&mut renderer, dir.path());
    session.settle().unwrap();
    session.start_full();
    // A stroke while the worker reads: the paintings it read are gone.
    let brush = Brush { color: [0.9, 0.9, 0.9], radius: 4.0, hardness: 0.5, opacity: 1.0, erase: false };
    session.views[0].canvas.stroke(brush, &[Vec2::new(50.0, 50.0)]);
    let r = session.refit().unwrap().unwrap();
    assert!(!session.wait_full().unwrap(), "a fit of paintings changed since is dropped");
    assert!(session.full_fit().is_none());
    let live = session.live_material().unwrap();
    assert!(std::ptr::eq(session.material().unwrap(), live), "the window keeps the live refit ({r:?})");
    assert!(session.full_owed(), "the paintings as they are still owe a full fit");
    // The next pause fits the paintings as they are, and that one is shown.
    assert!(pause_and_settle(&mut session));
    assert!(std::ptr::eq(session.material().unwrap(), &session.full_fit().unwrap().material));
    // A session dropped while its worker runs: the result is dropped with it, no panic.
    session.views[0].canvas.stroke(brush, &[Vec2::new(60.0, 60.0)]);
    session.start_full();
    drop(session);
}
