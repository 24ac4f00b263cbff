//! Exposure and tone mapping: from linear HDR radiance to the [0, 1] display range of a PNG.
//! EXR output stays linear: only the exposure (a linear scale) applies to it.

use crate::error::{Error, Result};

/// A tone-mapping operator, applied to linear RGB after the exposure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tonemap {
    /// Khronos PBR Neutral (Khronos 3D Commerce, 2024): identity up to 0.76 apart from a
    /// small toe, then a smooth roll-off to 1 with a little desaturation. Base colours
    /// stay true, which is why it is the default for materials.
    Neutral,
    /// ACES filmic, Stephen Hill's fit of the RRT and sRGB ODT, after the 1/0.6 exposure
    /// boost the glTF Sample Viewer and three.js apply.
    Aces,
    /// Clamp to [0, 1].
    None,
}

impl Tonemap {
    /// The names the command line uses.
    pub const NAMES: [&'static str; 3] = ["neutral", "aces", "none"];

    /// Parses `neutral`, `aces` or `none`.
    pub fn parse(name: &str) -> Result<Tonemap> {
        match name {
            "neutral" => Ok(Tonemap::Neutral),
            "aces" => Ok(Tonemap::Aces),
            "none" => Ok(Tonemap::None),
            _ => Err(Error::input(format!("unknown tone mapping '{name}' (neutral, aces or none)"))),
        }
    }

    /// Maps one linear colour (already exposed) into [0, 1].
    pub fn map(self, c: [f32; 3]) -> [f32; 3] {
        let c = c.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
        match self {
            Tonemap::Neutral => pbr_neutral(c),
            Tonemap::Aces => aces_hill(c.map(|x| x / 0.6)),
            Tonemap::None => c.map(|x| x.min(1.0)),
        }
    }
}

/// $2^{EV}$: the linear scale of an exposure in stops.
pub fn exposure_scale(ev: f32) -> f32 {
    ev.exp2()
}

/// Khronos PBR Neutral, the reference GLSL of the specification transcribed.
fn pbr_neutral(mut c: [f32; 3]) -> [f32; 3] {
    const START: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let x = c[0].min(c[1]).min(c[2]);
    // The toe: darks lose up to 0.04, so black stays black and grey 0.18 stays near it.
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    c = c.map(|v| v - offset);
    let peak = c[0].max(c[1]).max(c[2]);
    if peak < START {
        return c;
    }
    let d = 1.0 - START;
    let new_peak = 1.0 - d * d / (peak + d - START);
    c = c.map(|v| v * new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c.map(|v| v * (1.0 - g) + new_peak * g)
}

/// ACES filmic (Stephen Hill's fit): sRGB to the RRT's space, the fitted curve, back.
fn aces_hill(c: [f32; 3]) -> [f32; 3] {
    const INPUT: [[f32; 3]; 3] = [[0.59719, 0.35458, 0.04823], [0.07600, 0.90834, 0.01566], [0.02840, 0.13383, 0.83777]];
    const OUTPUT: [[f32; 3]; 3] =
        [[1.60475, -0.53108, -0.07367], [-0.10208, 1.10813, -0.00605], [-0.00327, -0.07276, 1.07602]];
    let mul = |m: &[[f32; 3]; 3], v: [f32; 3]| m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2]);
    let v = mul(&INPUT, c).map(|v| {
        let a = v * (v + 0.024_578_6) - 0.000_090_537;
        let b = v * (0.983_729 * v + 0.432_951) + 0.238_081;
        a / b
    });
    mul(&OUTPUT, v).map(|x| x.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neutral_keeps_mid_tones_and_compresses_highlights() {
        // Above the toe, below the shoulder: only the 0.04 offset.
        let c = Tonemap::Neutral.map([0.5, 0.3, 0.2]);
        assert!((c[0] - 0.46).abs() < 1e-6 && (c[2] - 0.16).abs() < 1e-6, "{c:?}");
        assert_eq!(Tonemap::Neutral.map([0.0; 3]), [0.0; 3]);
        // Highlights approach 1 and never pass it; order is kept.
        let (a, b) = (Tonemap::Neutral.map([2.0; 3]), Tonemap::Neutral.map([50.0; 3]));
        assert!(a[0] < b[0] && b[0] < 1.0 && a[0] > 0.8, "{a:?} {b:?}");
    }

    #[test]
    fn aces_is_monotone_and_bounded_and_none_clamps() {
        let mut last = -1.0;
        for k in 0..100 {
            let x = k as f32 * 0.2;
            let y = Tonemap::Aces.map([x; 3])[1];
            assert!(y >= last && (0.0..=1.0).contains(&y), "{x}: {y}");
            last = y;
        }
        assert_eq!(Tonemap::None.map([2.0, 0.5, f32::NAN]), [1.0, 0.5, 0.0]);
        assert!((exposure_scale(-1.0) - 0.5).abs() < 1e-7);
        assert!(Tonemap::parse("filmic").is_err() && Tonemap::parse("aces").is_ok());
    }
}
