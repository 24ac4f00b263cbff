//! The suite another renderer made (issue 37; `brdfpaint::study::rendered`): Mitsuba 3
//! renders committed in tests/data/mitsuba/ (tools/mitsuba/render_suite.py), so this runs
//! without Mitsuba. `cargo run --release --example mitsuba_suite` prints the table.

use brdfpaint::read::lobe::BaseChoice;
use brdfpaint::sample::SceneSampler;
use brdfpaint::study::rendered::{self, median_of_medians, worst_view, Row, Suite};

fn suite() -> Suite {
    Suite::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mitsuba"))).unwrap()
}

fn table(rows: &[Row]) -> String {
    let mut s = String::new();
    for r in rows {
        s += &format!("{:<26} {:.4} ({:.3}) {}\n", r.material, r.median(), r.worst(), r.base.as_deref().unwrap_or("-"));
    }
    s + &format!("median {:.4}, worst view {:.3}", median_of_medians(rows), worst_view(rows))
}

/// The renderers agree on camera, pixel centres, light direction and irradiance, π and
/// linear values: Mitsuba's Lambertian sphere is brdfpaint's Lambert shading up to the
/// half-float EXR's rounding (measured 1.87e-4 to 1.98e-4 per view; 2e-7 to 8e-7 from
/// float EXRs). A flipped image or a missing π would be order 1.
#[test]
fn lambert_rendered_by_mitsuba_is_brdfpaints_lambert() {
    let scenes = tempfile::tempdir().unwrap();
    rendered::write_scenes(scenes.path()).unwrap();
    let mut sampler = SceneSampler::new().unwrap();
    let errors = rendered::convention_check(&suite(), &mut sampler, scenes.path()).unwrap();
    assert_eq!(errors.len(), rendered::presets().len());
    assert!(errors.iter().all(|&e| e < 4e-4), "{errors:?}");
}

/// Today's numbers as regression bounds: each table's median over materials (of each
/// material's median over the three held-out views) and its worst view may grow by at most
/// 10% of what was measured at the commit that made the suite. Lower is better: when a
/// change improves them, lower the bounds with it (BENCHMARKS.md keeps the table).
#[test]
fn fits_of_mitsuba_materials_hold_todays_held_out_errors() {
    let suite = suite();
    assert_eq!(suite.materials.len(), 9);
    let scenes = tempfile::tempdir().unwrap();
    rendered::write_scenes(scenes.path()).unwrap();
    let mut sampler = SceneSampler::new().unwrap();
    // (painted views, base, median measured, worst view measured)
    let today = [
        (1, BaseChoice::Auto, 0.0294, 0.081),
        (3, BaseChoice::Auto, 0.0072, 0.074),
        (1, BaseChoice::None, 0.0625, 0.310),
        (3, BaseChoice::None, 0.0099, 0.079),
    ];
    for (painted, base, median, worst) in today {
        let rows = rendered::measure(&suite, &mut sampler, scenes.path(), painted, base).unwrap();
        let t = table(&rows);
        eprintln!("{painted} view(s), base {base:?}:\n{t}");
        assert!(median_of_medians(&rows) <= 1.1 * median, "{painted} view(s), base {base:?}: median over {median} + 10%\n{t}");
        assert!(worst_view(&rows) <= 1.1 * worst, "{painted} view(s), base {base:?}: worst view over {worst} + 10%\n{t}");
    }
}
