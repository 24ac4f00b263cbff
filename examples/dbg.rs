use brdfpaint::brdf::{Analytic, SphereView};
use brdfpaint::factor::{prepare, LogMap, Settings};
fn main() -> brdfpaint::Result<()> {
    let pattern = SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), 102).pattern();
    let model = Analytic::suite()[2].clone();
    let values = pattern.shade(|l, v| model.shading(l, v));
    let prepared = prepare(&pattern, &Settings::four_factor(1, 128, 256))?;
    let map = LogMap::Offset { a: [0.05; 3] };
    for _ in 0..3 {
        let t = std::time::Instant::now();
        let b = prepared.rhs(&values, &map);
        let t1 = t.elapsed().as_secs_f64();
        let y = prepared.apply(&b);
        let t2 = t.elapsed().as_secs_f64();
        let _tables = prepared.split(&y);
        let t3 = t.elapsed().as_secs_f64();
        let _ = prepared.solve_tables(&values, &map)?;
        let t4 = t.elapsed().as_secs_f64();
        println!("rhs {:.2} apply {:.2} split {:.2} | solve_tables {:.2} ms", t1*1e3, (t2-t1)*1e3, (t3-t2)*1e3, (t4-t3)*1e3);
    }
    Ok(())
}
