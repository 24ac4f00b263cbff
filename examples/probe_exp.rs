fn bench(label: &str) {
    let xs: Vec<f64> = (0..1152).map(|i| -2.9 + i as f64 * 0.004).collect();
    let t = std::time::Instant::now();
    let mut s = 0.0;
    for _ in 0..1000 { for &x in &xs { s += std::hint::black_box(x).exp(); } }
    println!("{label}: exp {:.1} ns ({s})", t.elapsed().as_secs_f64() * 1e9 / (1000.0 * 1152.0));
    let mut ys = xs.clone();
    let t = std::time::Instant::now();
    for _ in 0..1000 { ys.copy_from_slice(&xs); for y in ys.iter_mut() { *y = brdfpaint::factor::mapping::fast_ln(*y + 3.0); } std::hint::black_box(&ys); }
    println!("{label}: fast_ln {:.2} ns", t.elapsed().as_secs_f64() * 1e9 / (1000.0 * 1152.0));
}
fn main() {
    bench("before");
    let a = faer::Mat::<f64>::from_fn(384, 384, |i, j| if i == j { 2.0 } else { 0.001 });
    let b = faer::Mat::<f64>::from_fn(384, 3, |i, j| (i + j) as f64);
    let c = &a * &b;
    std::hint::black_box(&c);
    bench("after matmul");
    let pattern = brdfpaint::brdf::SphereView::new(glam::DVec3::new(-0.5, 0.5, 1.0), 102).pattern();
    let p = brdfpaint::factor::prepare(&pattern, &brdfpaint::factor::Settings::default()).unwrap();
    bench("after prepare");
    let m = brdfpaint::brdf::Analytic::suite()[2].clone();
    let values = pattern.shade(|l, v| m.shading(l, v));
    let b = p.rhs(&values, &brdfpaint::factor::LogMap::Offset { a: [0.05; 3] });
    bench("after rhs");
    let y = p.apply(&b);
    std::hint::black_box(&y);
    bench("after apply");
}
