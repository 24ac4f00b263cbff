//! Mappings between linear and log space (thesis 3.2.3).
//!
//! Homomorphic factorization fits $\log f$. Three mappings decide which samples dominate:
//! - identity, $\tilde f = \log \max(f, \epsilon)$: emphasizes dark samples (the base colour);
//!   the floor $\epsilon$ keeps zero samples (the unlit side) from becoming $-\infty$;
//! - offset, $\tilde f = \log(a + f)$ (eq. 3.13), inverted by $f = \prod p_j - a$ (eq. 3.14):
//!   all samples weigh about equally;
//! - inverted, $\tilde f = \log(a - f)$ (eq. 3.15), inverted by $f = a - \prod p_j$
//!   (eq. 3.16): emphasizes bright samples (narrow highlights).
//!
//! The mapping is applied to the values before the solve, so any mapping works with one
//! prepared system, and `auto` simply tries each.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The floor of the identity mapping, relative to the channel's largest value: zero samples
/// map to $\log(10^{-3} \max f)$, about 7 natural-log units below the brightest sample. That
/// is darker than an 8-bit sRGB step above black (~3e-4 relative is the smallest nonzero),
/// yet finite, so the unlit side cannot swamp the fit.
pub const IDENTITY_FLOOR: f64 = 1e-3;
/// Default offset constant of [`Mapping::Offset`], relative to the channel's largest value.
pub const OFFSET_DEFAULT: f64 = 0.1;
/// Default constant of [`Mapping::Inverted`], relative to the channel's largest value. It
/// must exceed 1 so the brightest sample stays finite in log space.
pub const INVERTED_DEFAULT: f64 = 1.05;

/// A mapping choice as the user states it: constants may be left to their defaults.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Mapping {
    /// Try identity, offset and inverted; keep the lowest linear-space error on the samples.
    #[default]
    Auto,
    Identity,
    /// Offset by an absolute constant `a`, or by [`OFFSET_DEFAULT`] × max when `None`.
    Offset(Option<f64>),
    /// Invert about an absolute constant `a`, or [`INVERTED_DEFAULT`] × max when `None`.
    Inverted(Option<f64>),
}

impl FromStr for Mapping {
    type Err = Error;

    /// `auto`, `identity`, `offset`, `offset:A`, `inverted`, `inverted:A`.
    fn from_str(s: &str) -> Result<Self> {
        let (name, arg) = match s.split_once(':') {
            Some((n, a)) => (n, Some(a)),
            None => (s, None),
        };
        let constant = |a: Option<&str>| -> Result<Option<f64>> {
            match a {
                None => Ok(None),
                Some(a) => match a.parse::<f64>() {
                    Ok(x) if x.is_finite() && x > 0.0 => Ok(Some(x)),
                    _ => Err(Error::input(format!("mapping constant '{a}' must be a positive number"))),
                },
            }
        };
        match (name, arg) {
            ("auto", None) => Ok(Mapping::Auto),
            ("identity", None) => Ok(Mapping::Identity),
            ("offset", a) => Ok(Mapping::Offset(constant(a)?)),
            ("inverted", a) => Ok(Mapping::Inverted(constant(a)?)),
            _ => Err(Error::input(format!(
                "unknown mapping '{s}': expected auto, identity, offset[:A] or inverted[:A]"
            ))),
        }
    }
}

impl fmt::Display for Mapping {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Mapping::Auto => write!(f, "auto"),
            Mapping::Identity => write!(f, "identity"),
            Mapping::Offset(None) => write!(f, "offset"),
            Mapping::Offset(Some(a)) => write!(f, "offset:{a}"),
            Mapping::Inverted(None) => write!(f, "inverted"),
            Mapping::Inverted(Some(a)) => write!(f, "inverted:{a}"),
        }
    }
}

/// A mapping with its per-channel constants fixed: what a material stores with each term.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum LogMap {
    /// $\tilde f = \log \max(f, \text{floor})$.
    Identity { floor: [f64; 3] },
    /// $\tilde f = \log(a + f)$, $f = \prod p - a$.
    Offset { a: [f64; 3] },
    /// $\tilde f = \log(a - f)$, $f = a - \prod p$.
    Inverted { a: [f64; 3] },
}

impl LogMap {
    /// Log-space value of linear sample value `f` in channel `c`.
    #[inline]
    pub fn forward(&self, c: usize, f: f64) -> f64 {
        match self {
            LogMap::Identity { floor } => fast_ln(f.max(floor[c])),
            LogMap::Offset { a } => fast_ln(a[c] + f),
            // Values at or above `a` would be -inf or NaN; they cannot occur for the default
            // constant, and a user constant below the data is rejected by `resolve`.
            LogMap::Inverted { a } => fast_ln((a[c] - f).max(a[c] * 1e-9)),
        }
    }

    /// [`LogMap::forward`] over a slice of one channel's values, in place. Written as two
    /// flat loops so the logarithm vectorizes.
    pub fn forward_all(&self, c: usize, x: &mut [f64]) {
        match *self {
            LogMap::Identity { floor } => x.iter_mut().for_each(|v| *v = v.max(floor[c])),
            LogMap::Offset { a } => x.iter_mut().for_each(|v| *v += a[c]),
            LogMap::Inverted { a } => x.iter_mut().for_each(|v| *v = (a[c] - *v).max(a[c] * 1e-9)),
        }
        ln_all(x);
    }

    /// Linear value from the product of the factors, clamped at zero (eq. 3.14, 3.16).
    #[inline]
    pub fn inverse(&self, c: usize, product: f64) -> f64 {
        match self {
            LogMap::Identity { .. } => product,
            LogMap::Offset { a } => (product - a[c]).max(0.0),
            LogMap::Inverted { a } => (a[c] - product).max(0.0),
        }
    }

    /// Short name, as on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            LogMap::Identity { .. } => "identity",
            LogMap::Offset { .. } => "offset",
            LogMap::Inverted { .. } => "inverted",
        }
    }

    /// The constant `a` (offset, inverted) or the floor (identity), per channel.
    pub fn constant(&self) -> [f64; 3] {
        match *self {
            LogMap::Identity { floor } => floor,
            LogMap::Offset { a } | LogMap::Inverted { a } => a,
        }
    }
}

impl Mapping {
    /// The concrete mappings to try for these values: one, or three for `Auto`.
    /// `max` is the per-channel largest sample value.
    pub fn candidates(&self, max: [f64; 3]) -> Result<Vec<LogMap>> {
        let rel = |k: f64| max.map(|m| (k * m).max(1e-12));
        let identity = LogMap::Identity { floor: rel(IDENTITY_FLOOR) };
        let offset = |a: Option<f64>| LogMap::Offset { a: a.map_or(rel(OFFSET_DEFAULT), |a| [a; 3]) };
        let inverted = |a: Option<f64>| -> Result<LogMap> {
            match a {
                None => Ok(LogMap::Inverted { a: rel(INVERTED_DEFAULT) }),
                Some(a) => {
                    let top = max.iter().cloned().fold(0.0, f64::max);
                    if a <= top {
                        return Err(Error::input(format!(
                            "inverted mapping constant {a} must exceed the largest sample value {top}"
                        )));
                    }
                    Ok(LogMap::Inverted { a: [a; 3] })
                }
            }
        };
        Ok(match self {
            Mapping::Auto => vec![identity, offset(None), inverted(None)?],
            Mapping::Identity => vec![identity],
            Mapping::Offset(a) => vec![offset(*a)],
            Mapping::Inverted(a) => vec![inverted(*a)?],
        })
    }
}

impl Mapping {
    /// [`Mapping::candidates`] with every constant along one colour, `tint` (largest
    /// channel 1): the identity floor and the offset at their defaults times the largest
    /// value over the channels, the inverted constant its default times the least scale that
    /// keeps it above every channel's largest value. A constant the user gave is grey.
    pub fn candidates_tinted(&self, max: [f64; 3], tint: [f64; 3]) -> Result<Vec<LogMap>> {
        let top = max.iter().cloned().fold(0.0, f64::max).max(1e-12);
        let reach = (0..3).map(|c| max[c] / tint[c]).fold(top, f64::max);
        let identity = LogMap::Identity { floor: tint.map(|t| IDENTITY_FLOOR * top * t) };
        let offset = LogMap::Offset { a: tint.map(|t| OFFSET_DEFAULT * top * t) };
        let inverted = LogMap::Inverted { a: tint.map(|t| INVERTED_DEFAULT * reach * t) };
        Ok(match self {
            Mapping::Auto => vec![identity, offset, inverted],
            Mapping::Identity => vec![identity],
            Mapping::Offset(None) => vec![offset],
            Mapping::Inverted(None) => vec![inverted],
            Mapping::Offset(Some(_)) | Mapping::Inverted(Some(_)) => self.candidates(max)?,
        })
    }
}

/// [`fast_ln`] over a slice, in place: with AVX2 and FMA where the CPU has them (four lanes
/// instead of SSE2's two; the log is most of a refit's time), else portable code.
pub fn ln_all(x: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the CPU has AVX-512F, checked just above.
        unsafe { ln_all_avx512(x) };
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA, checked just above.
        unsafe { ln_all_avx2(x) };
        return;
    }
    x.iter_mut().for_each(|v| *v = fast_ln(*v));
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn ln_all_avx512(x: &mut [f64]) {
    x.iter_mut().for_each(|v| *v = fast_ln(*v));
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn ln_all_avx2(x: &mut [f64]) {
    x.iter_mut().for_each(|v| *v = fast_ln(*v));
}

/// Natural logarithm for positive normal numbers, written so the compiler vectorizes it.
/// Absolute error below 2e-11 over the positive normal range (tested against `f64::ln`):
/// far below the precision of any painting, and cheaper than a full-precision log.
///
/// $x = m \cdot 2^e$ with $m \in [\sqrt{1/2}, \sqrt 2)$; then with $s = (m-1)/(m+1)$,
/// $\ln m = 2 \operatorname{artanh} s = 2(s + s^3/3 + s^5/5 + \dots)$, and $|s| < 0.172$
/// makes the series converge fast.
#[inline(always)]
pub fn fast_ln(x: f64) -> f64 {
    const SQRT_2: f64 = std::f64::consts::SQRT_2;
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    let big = m > SQRT_2;
    let m = if big { m * 0.5 } else { m };
    let e = (e + big as i64) as f64;
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    // Six terms: the first omitted one, $2 s^{13}/13$, is below $2 \cdot 10^{-11}$.
    let series = 1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 * (1.0 / 9.0 + s2 * (1.0 / 11.0)))));
    e * std::f64::consts::LN_2 + 2.0 * s * series
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_ln_matches_std() {
        let mut x = 1e-300;
        while x < 1e300 {
            for k in [1.0, 1.2345, 1.41, 1.4143, 1.7, 1.999] {
                let y = x * k;
                let err = (fast_ln(y) - y.ln()).abs();
                assert!(err < 2e-11, "ln({y}): {} vs {}", fast_ln(y), y.ln());
            }
            x *= 7.3;
        }
    }

    #[test]
    fn mappings_round_trip() {
        let max = [2.0, 1.0, 0.5];
        for map in Mapping::Auto.candidates(max).unwrap() {
            for c in 0..3 {
                for f in [0.01, 0.2, 0.49] {
                    let back = map.inverse(c, map.forward(c, f).exp());
                    // fast_ln is accurate to 2e-11 absolute, so the round trip to about 1e-10.
                    assert!((back - f).abs() < 1e-10, "{map:?} c{c} f {f}: {back}");
                }
            }
        }
    }

    #[test]
    fn identity_floor_keeps_zero_finite() {
        let map = Mapping::Identity.candidates([1.0; 3]).unwrap()[0];
        let z = map.forward(0, 0.0);
        assert!(z.is_finite());
        assert!((z - (IDENTITY_FLOOR).ln()).abs() < 1e-12);
    }

    #[test]
    fn parses_the_command_line_forms() {
        assert_eq!("auto".parse::<Mapping>().unwrap(), Mapping::Auto);
        assert_eq!("offset:0.5".parse::<Mapping>().unwrap(), Mapping::Offset(Some(0.5)));
        assert_eq!("inverted".parse::<Mapping>().unwrap(), Mapping::Inverted(None));
        assert!("offset:-1".parse::<Mapping>().is_err());
        assert!("log".parse::<Mapping>().is_err());
        for m in [Mapping::Auto, Mapping::Offset(Some(0.25)), Mapping::Inverted(None)] {
            assert_eq!(m.to_string().parse::<Mapping>().unwrap(), m);
        }
    }

    #[test]
    fn inverted_constant_below_the_data_is_an_error() {
        assert!(Mapping::Inverted(Some(0.5)).candidates([1.0; 3]).is_err());
    }
}
