//! Criterion benchmarks of the factorization engine at the thesis's sizes (Tables 5.1, 5.2).
//! `cargo bench --bench factor`. `brdfpaint bench` prints the full tables with the thesis's
//! figures beside ours.

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{Analytic, SphereView};
use brdfpaint::factor::{prepare, LogMap, Pattern, Settings};
use criterion::{criterion_group, criterion_main, Criterion};
use glam::DVec3;

fn sphere(res: usize) -> Pattern {
    SphereView::new(DVec3::new(-0.5, 0.5, 1.0), res).pattern()
}

fn cases(c: &mut Criterion) {
    let model = Analytic::suite()[2].clone();
    let map = LogMap::Offset { a: [0.05; 3] };
    let table = [
        ("3x1D M=128 7.9k", sphere(102), Settings::uniform(1, 128)),
        ("4-factor M=128 uv=32 7.9k", sphere(102), Settings::four_factor(1, 128, 32)),
        ("3x2D M=32 100k", sphere(360), Settings::uniform(2, 32)),
    ];
    for (name, pattern, settings) in &table {
        let values = pattern.shade(|q| model.shading(q));
        let prepared = prepare(pattern, settings).expect("prepare");
        let mut g = c.benchmark_group(*name);
        g.sample_size(if pattern.len() > 50_000 { 10 } else { 30 });
        g.bench_function("prepare", |b| b.iter(|| prepare(pattern, settings).expect("prepare")));
        g.bench_function("solve", |b| b.iter(|| prepared.solve_tables(&values, &map).expect("solve")));
        g.finish();
    }
}

criterion_group!(benches, cases);
criterion_main!(benches);
