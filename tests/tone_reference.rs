//! Tone mapping against published references, not against its own formula: Khronos PBR
//! Neutral through the analytical inverse Khronos publishes beside it
//! (KhronosGroup/ToneMapping, `PBR_Neutral/lut-writer.mjs`, `inverseNeutral`, transcribed
//! below in f64), and the properties its specification states (identity below the
//! compression start apart from the 0.04 offset; the toe x − 6.25x² for the darkest channel
//! under 0.08; highlights compressed towards 1, never past it). The forward map is
//! `brdfpaint::images::tone`'s, in f32.

use brdfpaint::images::tone::Tonemap;

/// Khronos' published inverse of PBR Neutral (lut-writer.mjs), in f64.
fn inverse_neutral(c: [f64; 3]) -> [f64; 3] {
    const START: f64 = 0.8 - 0.04;
    const DESATURATION: f64 = 0.15;
    let mut c = c;
    let peak = c[0].max(c[1]).max(c[2]);
    if peak > START {
        let d = 1.0 - START;
        let old_peak = d * d / (1.0 - peak) - d + START;
        let f_inv = DESATURATION * (old_peak - peak) + 1.0;
        let f = 1.0 / f_inv;
        c = c.map(|v| (v + (f - 1.0) * peak) * f_inv * old_peak / peak);
    }
    // (Clamped at 0: the f32 forward map can leave the darkest channel of a strongly
    // desaturated highlight a rounding step below it, where the toe's root has no value.)
    let y = c[0].min(c[1]).min(c[2]).max(0.0);
    let offset = if y < 0.04 {
        let x = (y / 6.25).sqrt();
        x - 6.25 * x * x
    } else {
        0.04
    };
    c.map(|v| v + offset)
}

/// Relative error as Khronos' script measures it: |Δ| / |rgb|.
fn relative(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    d / (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt().max(1e-20)
}

#[test]
fn pbr_neutral_is_inverted_by_khronos_published_inverse() {
    // Khronos' LUT grid is 2^-9 to 2^10 per channel, log spaced; here 2^-9 to 2^3 in 20
    // steps: further up, highlights are compressed to within a few f32 steps of 1 and
    // desaturated towards white, where no inverse of an f32 output recovers the input.
    let n = 20;
    let level = |i: usize| 2f64.powf(-9.0 + 12.0 * i as f64 / (n - 1) as f64);
    let (mut worst, mut checked) = (0.0f64, 0);
    for r in 0..n {
        for g in 0..n {
            for b in 0..n {
                let x = [level(r), level(g), level(b)];
                let y = Tonemap::Neutral.map(x.map(|v| v as f32)).map(f64::from);
                assert!(y.iter().all(|v| (0.0..=1.0).contains(v)), "{x:?} -> {y:?}");
                let back = inverse_neutral(y);
                let e = relative(x, back);
                worst = worst.max(e);
                checked += 1;
                // f32 forward: relative error grows as the roll-off flattens (dy/dx ~ d²/x²).
                let peak = x[0].max(x[1]).max(x[2]);
                let tol = 1e-5 * (1.0 + peak * peak);
                assert!(e <= tol, "{x:?} -> {y:?} -> {back:?}: relative error {e:.2e} > {tol:.1e}");
            }
        }
    }
    eprintln!("{checked} colours, worst relative error of the round trip {worst:.2e}");
    assert!(checked > 5000);
}

#[test]
fn pbr_neutral_meets_its_specifications_stated_values() {
    // Mid tones: every channel at least 0.08 and the peak under 0.8 pass as x − 0.04.
    for c in [[0.18f32; 3], [0.5, 0.3, 0.2], [0.79, 0.1, 0.5]] {
        let y = Tonemap::Neutral.map(c);
        for k in 0..3 {
            assert!((y[k] - (c[k] - 0.04)).abs() < 1e-6, "{c:?} -> {y:?}");
        }
    }
    // The toe: the darkest channel x < 0.08 loses x − 6.25x² (every channel does): black
    // stays black, 0.04 loses 0.03 (to 0.01), and the toe meets the constant 0.04 offset at
    // 0.08.
    assert_eq!(Tonemap::Neutral.map([0.0; 3]), [0.0; 3]);
    let y = Tonemap::Neutral.map([0.04, 0.5, 0.5]);
    assert!((y[0] - 0.01).abs() < 1e-6 && (y[1] - 0.47).abs() < 1e-6, "{y:?}");
    let (a, b) = (Tonemap::Neutral.map([0.08 - 1e-4; 3])[0], Tonemap::Neutral.map([0.08; 3])[0]);
    assert!((a - b).abs() < 2e-4 && (b - 0.04).abs() < 1e-6, "{a} {b}");
    // Compression: a grey of peak p ≥ 0.76 + 0.04 maps to 1 − d²/(p − 0.04 + d − 0.76),
    // d = 0.24 (a grey stays grey, so the desaturation does nothing).
    for x in [1.0f64, 2.0, 10.0] {
        let p = x - 0.04;
        let want = 1.0 - 0.24 * 0.24 / (p + 0.24 - 0.76);
        let y = Tonemap::Neutral.map([x as f32; 3]);
        assert!(y.iter().all(|&v| (v as f64 - want).abs() < 1e-6), "{x}: {y:?}, want {want}");
    }
}

/// sRGB's encoding (IEC 61966-2-1), for comparing with code values.
fn srgb(x: f64) -> f64 {
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// ACES (`aces`) is Stephen Hill's fit of the ACES 1.0 RRT and sRGB ODT, applied after the
/// 1/0.6 boost that three.js and the glTF Sample Viewer apply, so Tonemap::Aces at 0.6 is
/// the fit at scene value 1. Published values of the transform it fits (the Academy's
/// reference transform, as quoted on ACES Central, "Understanding the sRGB RRT/ODT"):
/// ACEScg [1, 1, 1] → RRT → sRGB ODT → sRGB code value 0.812, and sRGB 1.0 is reached at a
/// scene value of about 16.29. A neutral stays neutral. The fit is a fit: measured 0.809
/// against 0.812, and 0.996 at 16.29 (it reaches 1 at about 26), so the tolerances are
/// those of the fit, not of float rounding.
#[test]
fn aces_meets_the_published_values_of_the_transform_it_fits() {
    let at = |scene: f64| Tonemap::Aces.map([(0.6 * scene) as f32; 3]).map(f64::from);
    let white = at(1.0);
    // (The published matrices' rows sum to 1 within 1e-5.)
    assert!((white[0] - white[1]).abs() < 2e-5 && (white[1] - white[2]).abs() < 2e-5, "{white:?}");
    let code = srgb(white[0]);
    eprintln!("ACES: scene 1.0 -> sRGB {code:.4} (published 0.812); scene 16.29 -> {:.4} (published 1.0)", srgb(at(16.29)[0]));
    assert!((code - 0.812).abs() < 0.005, "scene 1.0 -> sRGB code value {code:.4}, published 0.812");
    let top = srgb(at(16.29)[0]);
    assert!((top - 1.0).abs() < 0.01, "scene 16.29 -> sRGB code value {top:.4}, published 1.0");
    assert_eq!(at(1e4), [1.0; 3]);
}
