use brdfpaint::brdf::{relative_rms, Striped};
use brdfpaint::factor::{prepare, Settings, Query};
use brdfpaint::material::map::{self, MapOptions};
fn main() -> brdfpaint::Result<()> {
    let object = Striped::wood();
    // Albedo rings in v on top of the bands.
    let truth = |q: &Query| { let a = if (q.uv.y * 10.0).floor() as i64 % 2 == 0 { 1.0 } else { 0.6 }; object.shading(q).map(|x| x * a) };
    let (pattern, _, grids) = object.paint(&Striped::painted_views(90));
    let values: Vec<[f64; 3]> = pattern.queries.iter().map(truth).collect();
    let held = Striped::held_out_views(90);
    for (name, settings) in [("map", Settings::default()), ("hybrid", Settings::four_factor(1, 128, 32)), ("hybrid-smooth1e-3", { let mut s = Settings::four_factor(1, 128, 32); s.factors[3].smooth = 1e-3; s }), ("hybrid-ridge1", { let mut s = Settings::four_factor(1, 128, 32); s.factors[3].ridge = 1.0; s })] {
        let prepared = prepare(&pattern, &settings)?;
        let t = std::time::Instant::now();
        let (m, r) = map::fit(&prepared, &pattern, &values, &grids, &MapOptions::default())?;
        println!("{name}: kind {:?} terms {} train rel {:.4} held {:.4} {:.0} ms", m.kind, m.terms.len(), r.fitted.rms_relative, relative_rms(&held, truth, |q| m.eval(q)), t.elapsed().as_secs_f64()*1e3);
    }
    Ok(())
}
