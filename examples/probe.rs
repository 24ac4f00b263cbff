use brdfpaint::brdf::Reflectance;
use brdfpaint::factor::Query;
use glam::{DVec2, DVec3};
fn main() {
    for dir in std::env::args().skip(1) {
        let m = brdfpaint::material::Material::load(std::path::Path::new(&dir)).unwrap();
        let y = |q: Query| { let s = m.shading(&q); 0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2] };
        let at = |deg: f64| DVec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        println!("{dir}");
        print!("  l=v=θ      :"); for d in [0.0, 30.0, 60.0, 80.0, 89.0] { print!(" {:6.3}", y(Query { l: at(d), v: at(d), uv: DVec2::ZERO })); } println!();
        print!("  v=n, θ_l   :"); for d in [0.0, 30.0, 60.0, 80.0, 100.0, 120.0, 150.0, 180.0] { print!(" {:6.3}", y(Query { l: at(d), v: DVec3::Z, uv: DVec2::ZERO })); } println!();
        print!("  l=n, θ_v   :"); for d in [0.0, 30.0, 60.0, 80.0, 89.0] { print!(" {:6.3}", y(Query { l: DVec3::Z, v: at(d), uv: DVec2::ZERO })); } println!();
        print!("  v=60°,l=-θ :"); for d in [0.0, 30.0, 60.0, 90.0, 120.0, 150.0] { print!(" {:6.3}", y(Query { l: at(-d), v: at(60.0), uv: DVec2::ZERO })); } println!();
    }
}
