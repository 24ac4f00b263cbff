use brdfpaint::factor::{Mapping, Settings};
use brdfpaint::pipeline::Reading;
use brdfpaint::sample::SceneSampler;
use brdfpaint::study::faults::{self, FaultyView, Faults};
use brdfpaint::study::fidelity::{held_out_presets, painted_presets, StudyView};
use brdfpaint::study::median;
fn main() {
    let mut sampler = SceneSampler::new().unwrap();
    let size = 256;
    let held: Vec<StudyView> = held_out_presets().iter().map(|p| StudyView::new(&mut sampler, p, size).unwrap()).collect();
    let all = Faults::all();
    let cases = [
        ("all", all.clone()),
        ("no brush", Faults { brush: 0.0, ..all.clone() }),
        ("no levels", Faults { levels: 0, ..all.clone() }),
        ("no strays", Faults { strays: 0, ..all.clone() }),
        ("no light", Faults { light_off_deg: 0.0, ..all.clone() }),
        ("no noise", Faults { noise: 0.0, ..all.clone() }),
        ("brush+levels", Faults { strays: 0, light_off_deg: 0.0, noise: 0.0, ..all.clone() }),
    ];
    let only: Option<String> = std::env::args().nth(1);
    for (name, f) in cases {
        if only.as_deref().is_some_and(|o| o != name) { continue; }
        let painted = [FaultyView::new(&mut sampler, &painted_presets(1)[0], size, f.light_off_deg).unwrap()];
        let plain = |p: &brdfpaint::factor::Prepared, v: &[[f64; 3]]| p.solve(v, Mapping::Auto);
        let rows = faults::measure(&painted, &held, &faults::suite(), &Settings::default(), &f, &plain, Reading::default()).unwrap();
        let m = median(&rows.iter().map(|r| r.held_out).collect::<Vec<_>>());
        println!("{name:14} median {m:.4}  {}", rows.iter().map(|r| format!("{} {:.3}", &r.model[..r.model.len().min(8)], r.held_out)).collect::<Vec<_>>().join("  "));
    }
}
