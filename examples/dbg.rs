use brdfpaint::brdf::Striped;
use brdfpaint::factor::{prepare, Settings};
use brdfpaint::material::map::{self, MapOptions};
fn main() -> brdfpaint::Result<()> {
    let object = Striped::wood();
    let (pattern, values, grids) = object.paint(&Striped::painted_views(90));
    let prepared = prepare(&pattern, &Settings::default())?;
    let (m, r) = map::fit(&prepared, &pattern, &values, &grids, &MapOptions::default())?;
    println!("{} terms {:?}", m.terms.len(), r.errors.iter().map(|e| e.rms_relative).collect::<Vec<_>>());
    let c0 = m.terms[0].coefficients.as_ref().unwrap();
    let c1 = m.terms[1].coefficients.as_ref().unwrap();
    let mut img = brdfpaint::images::Rgb::new(c0.res, c0.res)?;
    for k in 0..c0.res * c0.res { let y = k / c0.res; let x = k % c0.res; img.pixels[(c0.res - 1 - y) * c0.res + x] = [c0.texels[k][0] * 0.5, c1.texels[k][0] * 0.5, 0.0]; }
    img.write_png(std::path::Path::new("/tmp/coef.png"))?;
    Ok(())
}
