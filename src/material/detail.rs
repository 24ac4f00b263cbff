//! A painting's detail over its fitted material (issue 36, `fit --texture keep`): the brush
//! strokes and paper grain the factored BRDF cannot hold, kept as a multiplier looked up by
//! the surface normal in view space, as a MatCap is, so it travels to any model while the
//! relit material still moves with the light.
//!
//! The texture is square with the unit disk inscribed (pixel $(i, j)$ of $N$ at
//! $x = 2(i + 1/2)/N - 1$, $y = 1 - 2(j + 1/2)/N$, row 0 at the top: the frame of
//! [`crate::export::matcap`] and of the lit-sphere picture); a normal $n$ in view space
//! (x right, y up, z toward the camera) reads it bilinearly at $(n_x, n_y)$, clamped to the
//! disk. `shaders/term.glsl` (`term_detail`) is the same lookup.

use glam::DVec2;

/// Largest detail texture read or written: a 1024² picture's disk at one texel per pixel.
pub const MAX_DETAIL_RES: usize = 1024;

/// Most a stroke multiplies the surface it lies on: paint over paint changes reflectance by a
/// layer's worth, not more. A larger ratio in the picture is paint over shadow (paper through
/// charcoal, a light stroke on black), which adds light rather than multiplying it.
pub const GAIN: f32 = 2.0;

/// The ratio $d(n_x, n_y)$ of the painting over its fit, linear RGB per texel, row 0 at the
/// top, and the floor $\epsilon$ it was measured above: a shading $f$ becomes
/// $f \min(d, G) + \epsilon (d - 1)$ ([`GAIN`]), which in the picture's own scene is the picture
/// ($d = (p + \epsilon)/(f + \epsilon)$) wherever $d \le G$, and keeps the strokes painted over
/// black without multiplying them into sparks where a moved light makes the surface bright.
#[derive(Clone, Debug, PartialEq)]
pub struct Detail {
    pub res: usize,
    pub floor: f32,
    pub texels: Vec<[f32; 3]>,
}

impl Detail {
    /// The detail at a view-space normal's $(x, y)$, as the shader samples it: clamped to the
    /// unit disk, bilinear between texel centres, clamped at the texture's edge.
    pub fn lookup(&self, n: DVec2) -> [f64; 3] {
        let n = if n.length() > 1.0 { n.normalize() } else { n };
        let res = self.res as f64;
        let x = ((0.5 + 0.5 * n.x) * res - 0.5).clamp(0.0, res - 1.0);
        let y = ((0.5 - 0.5 * n.y) * res - 0.5).clamp(0.0, res - 1.0);
        let (i0, j0) = (x.floor() as usize, y.floor() as usize);
        let (i1, j1) = ((i0 + 1).min(self.res - 1), (j0 + 1).min(self.res - 1));
        let (fx, fy) = (x - i0 as f64, y - j0 as f64);
        let at = |i: usize, j: usize| self.texels[j * self.res + i];
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            let top = at(i0, j0)[c] as f64 * (1.0 - fx) + at(i1, j0)[c] as f64 * fx;
            let bottom = at(i0, j1)[c] as f64 * (1.0 - fx) + at(i1, j1)[c] as f64 * fx;
            *o = top * (1.0 - fy) + bottom * fy;
        }
        out
    }

    /// `value` (a shading times its light) with the detail at view-space normal `n`, as
    /// `shaders/term.glsl` applies it to a one-term material, clamped at 0.
    pub fn apply(&self, value: [f64; 3], n: DVec2) -> [f64; 3] {
        let d = self.lookup(n);
        let e = self.floor as f64;
        [0, 1, 2].map(|c| (value[c] * d[c].min(GAIN as f64) + e * (d[c] - 1.0)).max(0.0))
    }

    /// Why the texture cannot be drawn, if it cannot: its size, or a negative or non-finite
    /// texel.
    pub fn validate(&self) -> std::result::Result<(), String> {
        if !(2..=MAX_DETAIL_RES).contains(&self.res) {
            return Err(format!("detail resolution {} is outside 2..={MAX_DETAIL_RES}", self.res));
        }
        if self.texels.len() != self.res * self.res {
            return Err(format!("detail texture of {} texels at resolution {}", self.texels.len(), self.res));
        }
        if !(self.floor.is_finite() && self.floor >= 0.0) {
            return Err(format!("detail floor {} is not a non-negative number", self.floor));
        }
        if !self.texels.iter().all(|t| t.iter().all(|x| x.is_finite() && *x >= 0.0)) {
            return Err("detail texture has negative or non-finite values".into());
        }
        Ok(())
    }

    /// The unit normal's $(x, y)$ at the centre of texel $(i, j)$.
    pub fn texel_normal(res: usize, i: usize, j: usize) -> DVec2 {
        let r = res as f64;
        DVec2::new(2.0 * (i as f64 + 0.5) / r - 1.0, 1.0 - 2.0 * (j as f64 + 0.5) / r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_reads_texel_centres_and_interpolates_between_them() {
        let res = 4;
        let texels = (0..res * res).map(|k| [k as f32, 1.0, 2.0]).collect();
        let d = Detail { res, floor: 0.0, texels };
        for (i, j) in [(1, 1), (2, 1), (1, 2), (2, 2)] {
            let n = Detail::texel_normal(res, i, j);
            assert!((d.lookup(n)[0] - (j * res + i) as f64).abs() < 1e-9, "texel ({i}, {j})");
        }
        // Halfway between texels (1, 1) and (2, 1): the mean of 5 and 6.
        assert!((d.lookup(DVec2::new(0.0, 0.25))[0] - 5.5).abs() < 1e-9);
        // Outside the disk: the rim in that direction, not the corner.
        assert_eq!(d.lookup(DVec2::new(3.0, 0.0)), d.lookup(DVec2::new(1.0, 0.0)));
        assert!(d.validate().is_ok());
        assert!(Detail { res, floor: 0.0, texels: vec![[-1.0; 3]; 16] }.validate().is_err());
        assert!(Detail { res, floor: 0.0, texels: vec![[1.0; 3]; 15] }.validate().is_err());
    }
}
