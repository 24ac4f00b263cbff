//! Material maps and four-factor fits on the striped test object (thesis Table 5.4's
//! metrics), on the painted samples and on held-out views.
//!
//! `cargo run --release --example map_fidelity`

use brdfpaint::brdf::Reflectance;
use brdfpaint::brdf::{Striped};
use brdfpaint::study::sphere_rms;
use brdfpaint::factor::{prepare, Settings};
use brdfpaint::material::map::{self, MapOptions, Method};

fn main() -> brdfpaint::Result<()> {
    let object = Striped::wood();
    for views in [1usize, 4] {
        let painted = &Striped::painted_views(90)[..views];
        let (pattern, values, grids) = object.paint(painted);
        let held = Striped::held_out_views(90);
        let prepared = prepare(&pattern, &Settings::default())?;
        for method in [Method::Greedy, Method::Cluster] {
            for terms in 1..=5 {
                let opts = MapOptions { terms, min_gain: 0.0, method, ..Default::default() };
                let (m, report) = map::fit(&prepared, &pattern, &values, &grids, &opts)?;
                let h = sphere_rms(&held, |q| object.shading(q), |q| m.shading(q));
                println!(
                    "views {views} {method:?} J={terms} (got {}) train rms {:.4} max {:.3} rel {:.4}  held-out rel {:.4}  {:.1} ms",
                    m.terms.len(),
                    report.fitted.rms,
                    report.fitted.max,
                    report.fitted.rms_relative,
                    h,
                    report.seconds * 1e3
                );
            }
        }
    }
    Ok(())
}
