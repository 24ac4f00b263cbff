use brdfpaint::bench::median_time;
use brdfpaint::brdf::{Analytic, SphereView};
use brdfpaint::factor::{prepare, LogMap, Settings};
fn main() {
    if std::env::var("SEQ").is_ok() { faer::set_global_parallelism(faer::Par::Seq); }
    let args: Vec<String> = std::env::args().collect();
    let (dim, res, img): (usize, usize, usize) = (args[1].parse().unwrap(), args[2].parse().unwrap(), args[3].parse().unwrap());
    let pattern = SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), img).pattern();
    let settings = if args.len() > 4 { Settings::four_factor(dim, res, args[4].parse().unwrap()) } else { Settings::uniform(dim, res) };
    let t = std::time::Instant::now();
    let p = prepare(&pattern, &settings).unwrap();
    println!("samples {} unknowns {} kind {} prepare {:.1} ms", pattern.len(), p.unknowns(), p.solver_kind(), t.elapsed().as_secs_f64() * 1e3);
    let m = Analytic::suite()[2].clone();
    let values = pattern.shade(|l, v| m.shading(l, v));
    let map = LogMap::Offset { a: [0.05; 3] };
    let rhs = median_time(20, 0.3, || { std::hint::black_box(p.rhs(&values, &map)); });
    let b = p.rhs(&values, &map);
    let apply = median_time(20, 0.3, || { std::hint::black_box(p.apply(&b)); });
    let all = median_time(20, 0.3, || { std::hint::black_box(p.solve_tables(&values, &map).unwrap()); });
    dump(&p, &values, &map);
    println!("rhs {:.3} ms apply {:.3} ms total {:.3} ms", rhs * 1e3, apply * 1e3, all * 1e3);
}
#[allow(dead_code)]
fn dump(p: &brdfpaint::factor::Prepared, values: &[[f64; 3]], map: &LogMap) {
    let y = p.apply(&p.rhs(values, map));
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for c in 0..3 { for r in 0..y.nrows() { lo = lo.min(y[(r, c)]); hi = hi.max(y[(r, c)]); } }
    println!("log table range {lo} .. {hi}");
    let t = std::time::Instant::now();
    let mut s = 0.0;
    for _ in 0..100 { for c in 0..3 { for r in 0..y.nrows() { s += std::hint::black_box(y[(r, c)]).exp(); } } }
    println!("exp: {:.1} ns each ({s})", t.elapsed().as_secs_f64() * 1e9 / (100.0 * 3.0 * y.nrows() as f64));
}
