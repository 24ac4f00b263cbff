use brdfpaint::brdf::{relative_rms, Analytic, Striped};
use brdfpaint::factor::{prepare, Mapping, Settings};
use brdfpaint::material::Material;
fn main() -> brdfpaint::Result<()> {
    let model = Analytic::BlinnPhong { diffuse: [0.4, 0.3, 0.2], specular: [0.3, 0.3, 0.3], exponent: 20.0 };
    let albedo = |u: f64| if ((u * 6.0).floor() as i64) % 2 == 0 { 1.0 } else { 0.4 };
    for views in [1usize, 2, 4] {
        let vs = &Striped::painted_views(90)[..views];
        let mut queries = Vec::new();
        for v in vs { queries.extend(v.pixels().into_iter().map(|p| p.query)); }
        let pattern = brdfpaint::factor::Pattern::new(queries.clone(), true);
        let values: Vec<[f64;3]> = queries.iter().map(|q| model.shading(q.l, q.v).map(|x| x * albedo(q.uv.x))).collect();
        for (ridge, smooth) in [(1e-2, 1e-3), (1e-2, 1e-4), (1e-2, 1e-5), (1e-3, 1e-5)] {
            let mut settings = Settings::four_factor(1, 128, 32);
            settings.factors[3].ridge = ridge; settings.factors[3].smooth = smooth;
            let prepared = prepare(&pattern, &settings)?;
            let fit = prepared.solve(&values, Mapping::Auto)?;
            let m = Material::from_fit(&settings, &fit, Default::default())?;
            let s = &m.terms[0].factors[3];
            // mean of s over band interiors, v in 0.3..0.7
            let (mut hi, mut lo, mut nh, mut nl) = (0.0, 0.0, 0, 0);
            let res = s.spec.res;
            for y in (3*res/10)..(7*res/10) { for x in 0..res { let u = x as f64 / (res-1) as f64; let e = u*6.0; if (e - e.round()).abs() < 0.15 { continue; } let val = s.texels[y*res+x][1] as f64; if albedo(u) > 0.5 { hi += val.ln(); nh += 1; } else { lo += val.ln(); nl += 1; } } }
            let ratio = ((hi / nh as f64) - (lo / nl as f64)).exp();
            let held = relative_rms(&Striped::held_out_views(60)[..2], |q| model.shading(q.l, q.v).map(|x| x * albedo(q.uv.x)), |q| m.eval(q));
            println!("views {views} ridge {ridge} smooth {smooth}: train {:.4} ratio {ratio:.3} (truth 2.5) held {held:.4}", fit.errors.rms_relative);
        }
    }
    Ok(())
}
