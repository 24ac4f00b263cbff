use brdfpaint::gl::HeadlessContext;
use brdfpaint::material::Material;
use brdfpaint::render::{GpuScene, Renderer};
use brdfpaint::scene::{Light, Scene};
use glam::Vec3;

fn sweep(renderer: &mut Renderer, gpu: &mut GpuScene, view: Vec3, m: &Material) -> f64 {
    let shading = renderer.upload(m).unwrap();
    let mut frames = Vec::new();
    for k in 0..8 {
        let a = std::f32::consts::TAU * k as f32 / 8.0;
        let towards = glam::Quat::from_rotation_y(a) * -view;
        gpu.light = Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 };
        let image = renderer.factored(gpu, &shading, 128, 128).unwrap();
        let (mut sum, mut n) = (0.0, 0);
        for j in 0..128 { for i in 0..128 { let p = image.at(i, j); if p[3] == 1.0 { sum += 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64; n += 1; } } }
        frames.push(sum / n as f64);
    }
    let (lo, hi) = frames.iter().fold((f64::MAX, 0.0f64), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    lo / hi
}

fn main() {
    let opts = brdfpaint::pipeline::Options::default();
    for name in std::env::args().skip(1) {
        let path = format!("../shared/data/matcaps/blender_cc0/exr/{name}.exr");
        let lit = brdfpaint::litsphere::fit(std::path::Path::new(&path), None, &opts, None).unwrap();
        let ctx = HeadlessContext::new().unwrap();
        let mut renderer = Renderer::new(ctx.gl()).unwrap();
        let scene = Scene::from_preset("bunny", "front").unwrap();
        let mut gpu = GpuScene::upload(ctx.gl(), &scene).unwrap();
        let view = scene.camera.forward();
        let base = sweep(&mut renderer, &mut gpu, view, &lit.fitted.material);
        let mut line = format!("{name:28} plain {base:.3} (rel {:.4})", lit.fitted.errors().rms_relative);
        for damp in [1e-4, 1e-3] {
            let mut o = opts.clone();
            o.settings.factors[1].damp = damp;
            let lit = brdfpaint::litsphere::fit(std::path::Path::new(&path), None, &o, None).unwrap();
            ctx.make_current().unwrap();
            line += &format!("; damp q {damp:e}: {:.3} (rel {:.4})", sweep(&mut renderer, &mut gpu, view, &lit.fitted.material), lit.fitted.errors().rms_relative);
        }
        println!("{line}");
    }
}
