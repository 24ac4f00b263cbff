//! Analytic fits of measured materials: "measured-like" ground truth for demos and tests.
//!
//! The ABC model of Löw, Kronander, Ynnerman and Unger, "BRDF models for accurate and
//! efficient rendering of glossy surfaces" (ACM TOG 2012), as fitted to all 100 MERL
//! materials and tabulated in jdupuy/dj_brdf (public domain; the CSV is in
//! `../shared/data/merl-fits`). It is a microfacet model whose distribution is the paper's
//! "ABC" curve in $1 - \cos\theta_h$:
//!
//! $$ f_r(\omega_l, \omega_v) = \frac{k_d}{\pi} + \frac{F(\cos\theta_d; \eta)\, D(\cos\theta_h)\,
//! G(\omega_l, \omega_v)}{\pi \cos\theta_l \cos\theta_v}, \qquad
//! D = \frac{A}{\left(1 + B (1 - \cos\theta_h)\right)^{C}} $$
//!
//! with $\cos\theta_d = \omega_l\cdot\mathbf h$, the unpolarized dielectric Fresnel term
//! $F$ of index $\eta$ (`ior`) and the Cook-Torrance V-groove shadowing
//! $G = \min\!\left(1, \frac{2 h_z l_z}{\mathbf h\cdot\omega_l}, \frac{2 h_z v_z}{\mathbf h\cdot\omega_v}\right)$.
//! The paper writes the distribution as $S(f) = A / (1 + B f^2)^C$ with
//! $f = \sqrt{1 - \mathbf h\cdot\mathbf n}$, which is the same curve. A constant in the
//! denominator only rescales $A$; the fitted $A$ values go with the $\pi$ used by the code the
//! parameters were published in (dj_brdf's `abc::eval`), so that is the normalization here.
//! `A` is per channel, `B`, `C` and `ior` are shared.

use std::f64::consts::PI;

use glam::DVec3;

use super::Reflectance;
use crate::error::{Error, Result};
use crate::factor::Query;

/// A material of the ABC model (Löw et al. 2012). Colours are linear RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct Abc {
    /// The MERL name, e.g. `gold-paint`.
    pub name: String,
    /// Diffuse reflectance $k_d$.
    pub kd: [f64; 3],
    /// Height of the distribution, per channel.
    pub a: [f64; 3],
    /// Width of the distribution: larger is narrower.
    pub b: f64,
    /// Fall-off exponent of the distribution's tail.
    pub c: f64,
    /// Index of refraction of the Fresnel term.
    pub ior: f64,
}

/// Rows of `merl_abc_fits_low2012.csv`, copied verbatim, for the materials the product
/// ships paintings of (the test `bundled_rows_match_the_csv` checks them against the file).
const BUNDLED: &[&str] = &[
    "gold-paint,0.150463,0.080224,0.022239,1.010258,0.811582,0.504538,46.942558,1.756670,7.936110",
    "purple-paint,0.280217,0.031190,0.032274,14.006363,13.769886,13.753972,408.684143,1.776584,1.483770",
    "orange-paint,0.407889,0.131526,0.003770,0.451945,0.373510,0.347662,11.196602,1.972428,1.887030",
    "blue-rubber,0.035403,0.074082,0.154563,1.295714,1.279542,1.248921,37.265717,1.565906,1.448611",
    "nickel,0.006227,0.006663,0.007587,36.614742,32.745403,28.906111,705.733887,1.945258,5.441883",
];

/// The unpolarized Fresnel reflectance of a dielectric of index `ior` at
/// $c = \cos\theta_d$ (Cook and Torrance 1982):
/// $F = \frac{(g-c)^2}{2(g+c)^2}\left(1 + \frac{(c(g+c)-1)^2}{(c(g-c)+1)^2}\right)$,
/// $g = \sqrt{\eta^2 + c^2 - 1}$.
pub fn fresnel_dielectric(c: f64, ior: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    // $\eta \ge 1$ for every fitted material, so $g^2 \ge c^2 \ge 0$; the floor only keeps an
    // index below 1 (total internal reflection, F = 1 there) from producing a NaN.
    let g2 = ior * ior + c * c - 1.0;
    if g2 <= 0.0 {
        return 1.0;
    }
    let g = g2.sqrt();
    let (gm, gp) = (g - c, g + c);
    let t = (c * gp - 1.0) / (c * gm + 1.0);
    // At c = 0 both terms give F = 1 (grazing), and gp = g > 0.
    0.5 * (gm * gm) / (gp * gp) * (1.0 + t * t)
}

impl Abc {
    /// One of the materials whose fit is compiled in (`gold-paint`, `purple-paint`,
    /// `orange-paint`, `blue-rubber`, `nickel`).
    pub fn bundled(name: &str) -> Option<Abc> {
        BUNDLED.iter().filter_map(|row| Abc::parse_row(row).ok()).find(|m| m.name == name)
    }

    /// Names of [`Abc::bundled`] materials.
    pub fn bundled_names() -> Vec<String> {
        BUNDLED.iter().filter_map(|row| row.split(',').next()).map(String::from).collect()
    }

    /// One CSV row: `merl_name,kD_r,kD_g,kD_b,A_r,A_g,A_b,B,C,ior`.
    pub fn parse_row(row: &str) -> Result<Abc> {
        let cells: Vec<&str> = row.trim().split(',').collect();
        if cells.len() != 10 {
            return Err(Error::input(format!(
                "ABC row '{row}': expected 10 comma-separated fields, found {}",
                cells.len()
            )));
        }
        let mut x = [0.0; 9];
        for (k, cell) in cells[1..].iter().enumerate() {
            x[k] = cell.trim().parse::<f64>().ok().filter(|v| v.is_finite() && *v >= 0.0).ok_or_else(|| {
                Error::input(format!("ABC row '{row}': field {} is not a non-negative number", k + 2))
            })?;
        }
        Ok(Abc {
            name: cells[0].trim().to_string(),
            kd: [x[0], x[1], x[2]],
            a: [x[3], x[4], x[5]],
            b: x[6],
            c: x[7],
            ior: x[8],
        })
    }

    /// Every material of a CSV file in the layout of `merl_abc_fits_low2012.csv` (a header
    /// line, then one row per material).
    pub fn parse_csv(text: &str) -> Result<Vec<Abc>> {
        text.lines().skip(1).filter(|l| !l.trim().is_empty()).map(Abc::parse_row).collect()
    }

    /// The distribution $D(\cos\theta_h)$, per channel.
    pub fn ndf(&self, cos_h: f64) -> [f64; 3] {
        // $1 - \cos\theta_h \in [0, 2]$; clamping keeps the base of the power positive.
        let base = 1.0 + self.b * (1.0 - cos_h).clamp(0.0, 2.0);
        let s = base.powf(-self.c);
        self.a.map(|a| a * s)
    }

    /// The BRDF $f_r(\omega_l, \omega_v)$ in the local frame (z = normal); zero when either
    /// direction is at or below the horizon.
    pub fn brdf(&self, l: DVec3, v: DVec3) -> [f64; 3] {
        let (cos_l, cos_v) = (l.z, v.z);
        if cos_l <= 0.0 || cos_v <= 0.0 {
            return [0.0; 3];
        }
        // Both above the horizon: l + v != 0.
        let h = (l + v).normalize();
        let cos_d = l.dot(h).clamp(0.0, 1.0);
        // $\mathbf h\cdot\omega \ge \cos\theta_d > 0$ for both directions (h bisects them), so
        // the shadowing ratios are finite.
        let g = (2.0 * h.z * cos_l / l.dot(h)).min(2.0 * h.z * cos_v / v.dot(h)).min(1.0);
        let f = fresnel_dielectric(cos_d, self.ior);
        let d = self.ndf(h.z);
        let spec = f * g / (PI * cos_l * cos_v);
        [0, 1, 2].map(|c| self.kd[c] / PI + d[c] * spec)
    }

}

impl Reflectance for Abc {
    /// The shading function $S = f_r \cos\theta_l$ a painting shows.
    fn shading(&self, q: &Query) -> [f64; 3] {
        let f = self.brdf(q.l, q.v);
        let c = q.l.z.max(0.0);
        f.map(|x| x * c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(theta: f64, phi: f64) -> DVec3 {
        DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
    }

    #[test]
    fn fresnel_matches_hand_values() {
        // Normal incidence: $((\eta - 1)/(\eta + 1))^2$; grazing: 1.
        for ior in [1.33f64, 1.5, 2.4, 7.9] {
            let f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
            assert!((fresnel_dielectric(1.0, ior) - f0).abs() < 1e-12, "ior {ior}");
            assert!((fresnel_dielectric(0.0, ior) - 1.0).abs() < 1e-12, "ior {ior}");
        }
        // Glass at 60 degrees: Rs = 0.1773, Rp = 0.00177, mean 0.0895 (textbook values).
        let f = fresnel_dielectric(60f64.to_radians().cos(), 1.5);
        assert!((f - 0.0895).abs() < 5e-4, "{f}");
    }

    #[test]
    fn reciprocal_non_negative_and_energy_bounded() {
        for name in Abc::bundled_names() {
            let m = Abc::bundled(&name).unwrap();
            for (tl, pl, tv, pv) in [(0.3, 0.0, 0.5, 2.0), (1.2, 1.0, 0.2, -0.5), (0.7, 0.4, 0.7, 0.4 + PI)] {
                let (l, v) = (dir(tl, pl), dir(tv, pv));
                let (a, b) = (m.brdf(l, v), m.brdf(v, l));
                for c in 0..3 {
                    assert!(a[c] >= 0.0 && (a[c] - b[c]).abs() <= 1e-12 * a[c].max(1.0), "{name} {a:?} {b:?}");
                }
            }
            // Directional albedo at normal incidence by midpoint quadrature over the
            // hemisphere: positive and at most 1 (every fitted material is physical).
            let n = 256;
            let mut albedo = [0.0; 3];
            for i in 0..n {
                let t = (i as f64 + 0.5) / n as f64 * PI / 2.0;
                for j in 0..n {
                    let p = (j as f64 + 0.5) / n as f64 * 2.0 * PI;
                    let v = dir(t, p);
                    let s = m.shading(&Query::at(v, DVec3::Z));
                    let w = t.sin() * (PI / 2.0 / n as f64) * (2.0 * PI / n as f64);
                    for c in 0..3 {
                        albedo[c] += s[c] * w;
                    }
                }
            }
            for c in 0..3 {
                assert!(albedo[c] > m.kd[c] * 0.99 && albedo[c] < 1.0, "{name}: albedo {albedo:?}");
            }
            assert_eq!(m.brdf(dir(1.7, 0.0), DVec3::Z), [0.0; 3]);
        }
    }

    #[test]
    fn peak_follows_the_formula() {
        // Light and view both along the normal: h = n, cos_d = 1, G = 1, D = A.
        let m = Abc::bundled("gold-paint").unwrap();
        let f = m.brdf(DVec3::Z, DVec3::Z);
        let f0 = ((m.ior - 1.0) / (m.ior + 1.0)).powi(2);
        for c in 0..3 {
            let want = m.kd[c] / PI + f0 * m.a[c] / PI;
            assert!((f[c] - want).abs() < 1e-12, "{f:?} {want}");
        }
    }

    #[test]
    fn bundled_rows_match_the_csv() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/merl-fits/merl_abc_fits_low2012.csv");
        let Ok(text) = std::fs::read_to_string(&path) else {
            eprintln!("skipped: {} is not here", path.display());
            return;
        };
        let all = Abc::parse_csv(&text).unwrap();
        assert_eq!(all.len(), 100);
        for name in Abc::bundled_names() {
            let ours = Abc::bundled(&name).unwrap();
            assert_eq!(all.iter().find(|m| m.name == name), Some(&ours), "{name}");
        }
        assert!(Abc::parse_row("x,1,2").is_err() && Abc::parse_row("x,1,2,3,4,5,6,7,8,-9").is_err());
    }
}
