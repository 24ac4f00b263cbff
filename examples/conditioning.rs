//! The conditioning study behind the factor defaults: fit the analytic suite from painted
//! sphere views and measure relative RMS on held-out lights and views.
//!
//! `cargo run --release --example conditioning [-- sweep]`

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{held_out_views, painted_views, Analytic, SphereView};
use brdfpaint::study::sphere_rms;
use brdfpaint::factor::{defaults, prepare, Mapping, Pattern, Settings};

fn training(n: usize, res: usize) -> Vec<SphereView> {
    painted_views(n, res)
}

fn held_out(model: &Analytic, settings: &Settings, fit: &brdfpaint::factor::Fit) -> f64 {
    sphere_rms(&held_out_views(48), |q| model.shading(q), |q| fit.eval(settings, q))
}

fn study(settings: &Settings, views: usize, mapping: Mapping, verbose: bool) -> f64 {
    let patterns: Vec<Pattern> = training(views, 100).iter().map(SphereView::pattern).collect();
    let pattern = Pattern::concat(&patterns);
    let prepared = prepare(&pattern, settings).expect("prepare");
    let mut errs = Vec::new();
    for model in Analytic::suite() {
        let values = pattern.shade(|q| model.shading(q));
        let fit = prepared.solve(&values, mapping).expect("solve");
        let e = held_out(&model, settings, &fit);
        if verbose {
            println!("  {:<16} train {:.4}  held-out {:.4}  map {}", model.name(), fit.errors.rms_relative, e, fit.map.name());
        }
        errs.push(e);
    }
    errs.sort_by(f64::total_cmp);
    errs[errs.len() / 2]
}

fn main() {
    if std::env::args().any(|a| a == "probe") { return probe(); }
    let args: Vec<String> = std::env::args().collect();
    if args.len() > 2 && args[1] == "one" {
        let (dim, res, smooth, damp, views): (usize, usize, f64, f64, usize) =
            (args[2].parse().unwrap(), args[3].parse().unwrap(), args[4].parse().unwrap(), args[5].parse().unwrap(), args[6].parse().unwrap());
        let mut s = Settings::uniform(dim, res);
        for (j, f) in s.factors.iter_mut().enumerate() {
            f.smooth = smooth;
            f.damp = if j == 2 { damp } else { 0.0 };
        }
        for mapping in [Mapping::Auto, Mapping::Identity, Mapping::Offset(None), Mapping::Inverted(None)] {
            println!("{mapping}: median {:.4}", study(&s, views, mapping, args.len() > 7));
        }
        return;
    }
    let sweep = std::env::args().any(|a| a == "sweep");
    for views in [1, 3] {
        for dim in [1, 2] {
            let s = Settings::uniform(dim, if dim == 1 { defaults::RES_1D } else { defaults::RES_2D });
            println!("{views} view(s), {dim}D defaults:");
            let m = study(&s, views, Mapping::Auto, true);
            println!("  median held-out {m:.4}");
        }
    }
    if !sweep {
        return;
    }
    for views in [1, 3] {
        for dim in [1usize, 2] {
            let resolutions: &[usize] = if dim == 1 { &[64, 128, 256] } else { &[16, 24, 32] };
            for &res in resolutions {
                for smooth in [1e-6, 1e-5, 1e-4, 1e-3] {
                    for damp in [0.0, 1e-7, 1e-6, 1e-5, 1e-4] {
                        for which in ["qr", "r"] {
                            let mut s = Settings::uniform(dim, res);
                            for (j, f) in s.factors.iter_mut().enumerate() {
                                f.smooth = smooth;
                                f.damp = if j == 2 || (j == 1 && which == "qr") { damp } else { 0.0 };
                            }
                            let m = study(&s, views, Mapping::Auto, false);
                            println!("views {views} dim {dim} res {res} smooth {smooth:e} damp {damp:e} on {which}: median {m:.4}");
                        }
                    }
                }
            }
        }
    }
}

#[allow(dead_code)]
pub fn probe() {
    use brdfpaint::factor::{LogMap};
    let model = Analytic::BlinnPhong { diffuse: [0.45, 0.25, 0.12], specular: [0.30, 0.35, 0.40], exponent: 32.0 };
    for (smooth, res) in [(1e-6, 64), (1e-6, 256), (1e-3, 64)] {
        let mut s = Settings::uniform(1, res);
        for f in s.factors.iter_mut() { f.smooth = smooth; f.damp = 0.0; }
        let pattern = training(1, 100)[0].pattern();
        let prepared = prepare(&pattern, &s).unwrap();
        let values = pattern.shade(|q| model.shading(q));
        for m in [Mapping::Identity, Mapping::Offset(None)] {
            let fit = prepared.solve(&values, m).unwrap();
            println!("smooth {smooth:e} res {res} {}: train {:.4} held {:.4}", fit.map.name(), fit.errors.rms_relative, held_out(&model, &s, &fit));
        }
        let _ = LogMap::Identity { floor: [0.0;3] };
    }
}
