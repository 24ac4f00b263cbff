//! Measured BRDFs in the MERL binary format (Matusik et al. 2003).
//!
//! Layout (../shared/data/merl-fits/README.md): three little-endian `i32` dimensions
//! (90, 90, 180), then 3 × 1,458,000 `f64` in R, G, B order, scaled by 1/1500, 1.15/1500 and
//! 1.66/1500. The table is indexed by Rusinkiewicz's half/difference angles: $\theta_h$ with
//! a square-root spacing that concentrates bins near the specular peak, $\theta_d$ and
//! $\phi_d \in [0, \pi)$ (reciprocity folds the other half) uniformly. Negative entries mark
//! missing measurements.

use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;

use glam::DVec3;

use crate::error::{Error, Result};
use crate::factor::Sample;

const THETA_H: usize = 90;
const THETA_D: usize = 90;
const PHI_D: usize = 180;
/// Entries per channel.
pub const ENTRIES: usize = THETA_H * THETA_D * PHI_D;
const HEADER: usize = 12;
/// Size of a valid file in bytes.
pub const FILE_BYTES: usize = HEADER + 3 * ENTRIES * 8;
const SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];

/// A measured isotropic BRDF table.
#[derive(Clone, PartialEq)]
pub struct Merl {
    /// Unscaled values as stored, channel-major (R block, G block, B block).
    raw: Vec<f64>,
}

impl std::fmt::Debug for Merl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Merl({} entries)", self.raw.len())
    }
}

/// Half/difference angles of a light and view direction in the local frame.
fn half_diff(l: DVec3, v: DVec3) -> (f64, f64, f64) {
    let h = (l + v).normalize();
    // atan2 rather than acos: acos loses half the digits near the normal.
    let theta_h = h.x.hypot(h.y).atan2(h.z);
    let phi_h = h.y.atan2(h.x);
    // Rotate l so that h becomes the normal: by -phi_h about z, then by -theta_h about y.
    let d = rotate(rotate(l, DVec3::Z, -phi_h), DVec3::Y, -theta_h);
    let theta_d = d.x.hypot(d.y).atan2(d.z);
    let phi_d = d.y.atan2(d.x);
    (theta_h, theta_d, phi_d)
}

/// Rodrigues' rotation of `v` about the unit `axis` by `angle`.
fn rotate(v: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis * axis.dot(v) * (1.0 - c) + axis.cross(v) * s
}

/// Table index of half/difference angles, as in MERL's reference reader.
fn index(theta_h: f64, theta_d: f64, phi_d: f64) -> usize {
    // θ_h: square-root spacing, index = sqrt(θ_h / (π/2)) · 90.
    let ih = if theta_h <= 0.0 { 0 } else { ((theta_h / FRAC_PI_2 * 8100.0).sqrt() as usize).min(THETA_H - 1) };
    let id = ((theta_d / FRAC_PI_2 * THETA_D as f64) as usize).min(THETA_D - 1);
    let phi = if phi_d < 0.0 { phi_d + PI } else { phi_d };
    let ip = ((phi / PI * PHI_D as f64) as usize).min(PHI_D - 1);
    ip + PHI_D * (id + THETA_D * ih)
}

impl Merl {
    /// Tabulate a BRDF at the centre of every bin (for tests and synthetic data).
    pub fn from_brdf(f: impl Fn(DVec3, DVec3) -> [f64; 3]) -> Merl {
        let mut raw = vec![0.0; 3 * ENTRIES];
        for ih in 0..THETA_H {
            let theta_h = ((ih as f64 + 0.5).powi(2) / 8100.0) * FRAC_PI_2;
            let h = DVec3::new(theta_h.sin(), 0.0, theta_h.cos());
            for id in 0..THETA_D {
                let theta_d = (id as f64 + 0.5) / THETA_D as f64 * FRAC_PI_2;
                for ip in 0..PHI_D {
                    let phi_d = (ip as f64 + 0.5) / PHI_D as f64 * PI;
                    let d = DVec3::new(theta_d.sin() * phi_d.cos(), theta_d.sin() * phi_d.sin(), theta_d.cos());
                    let l = rotate(d, DVec3::Y, theta_h);
                    let v = h * (2.0 * h.dot(l)) - l;
                    let k = ip + PHI_D * (id + THETA_D * ih);
                    let value = if l.z > 0.0 && v.z > 0.0 { f(l, v) } else { [-1.0; 3] };
                    for c in 0..3 {
                        raw[k + c * ENTRIES] = if value[c] < 0.0 { -1.0 } else { value[c] / SCALE[c] };
                    }
                }
            }
        }
        Merl { raw }
    }

    /// Read a `.binary` file. Wrong size, wrong dimensions or non-finite values are errors.
    /// Read under the file-access policy ([`crate::fsio`]): a FIFO or a device is refused by
    /// its type, before its size is judged.
    pub fn read(path: &Path) -> Result<Merl> {
        let len = crate::fsio::check_regular(path, u64::MAX)?;
        if len != FILE_BYTES as u64 {
            return Err(Error::format(
                path,
                format!(
                    "{len} bytes; a MERL BRDF file has exactly {FILE_BYTES} ({})",
                    if len < FILE_BYTES as u64 { "truncated?" } else { "trailing data?" }
                ),
            ));
        }
        let bytes = crate::fsio::read_regular(path, FILE_BYTES as u64)?;
        if bytes.len() != FILE_BYTES {
            return Err(Error::format(path, format!("{} bytes read of {FILE_BYTES} (truncated while read?)", bytes.len())));
        }
        let dims: Vec<i32> = bytes[..HEADER].chunks_exact(4).map(|b| i32::from_le_bytes(b.try_into().unwrap())).collect();
        if dims != [THETA_H as i32, THETA_D as i32, PHI_D as i32] {
            return Err(Error::format(path, format!("dimensions {dims:?}, expected [90, 90, 180]")));
        }
        let raw: Vec<f64> = bytes[HEADER..].chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().unwrap())).collect();
        if let Some(k) = raw.iter().position(|x| !x.is_finite()) {
            return Err(Error::format(path, format!("entry {k} is not a finite number")));
        }
        Ok(Merl { raw })
    }

    /// Write a `.binary` file, atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        let mut bytes = Vec::with_capacity(FILE_BYTES);
        for d in [THETA_H, THETA_D, PHI_D] {
            bytes.extend_from_slice(&(d as i32).to_le_bytes());
        }
        for x in &self.raw {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
        crate::commit::write_atomic(path, &bytes)
    }

    /// The BRDF at a light and view direction (local frame, unit vectors), or `None` where
    /// the table has no measurement or either direction is below the horizon.
    pub fn brdf(&self, l: DVec3, v: DVec3) -> Option<[f64; 3]> {
        if l.z <= 0.0 || v.z <= 0.0 {
            return None;
        }
        let (th, td, pd) = half_diff(l, v);
        let k = index(th, td, pd);
        let out = [0, 1, 2].map(|c| self.raw[k + c * ENTRIES] * SCALE[c]);
        if out.iter().any(|&x| x < 0.0) {
            None
        } else {
            Some(out)
        }
    }

    /// Samples of the shading function $S = f_r \cos\theta_l$ on a regular grid: `k` polar
    /// angles each for the light and the view, `2k` relative azimuths over $[0, \pi]$
    /// (isotropy and reciprocity make that half-turn enough), $2k^3$ pairs in all, less the
    /// missing measurements. Each pair is turned about the normal by a golden-angle step so
    /// that 2D factors see every azimuth. `k` = 16 gives about the thesis's 7.9k samples.
    pub fn samples(&self, k: usize) -> Result<Vec<Sample>> {
        let mut out = Vec::with_capacity(2 * k * k * k);
        for (l, v) in grid(k)? {
            if let Some(f) = self.brdf(l, v) {
                out.push(Sample { l, v, uv: None, value: f.map(|x| x * l.z) });
            }
        }
        if out.is_empty() {
            return Err(Error::input("the MERL table has no valid measurements"));
        }
        Ok(out)
    }
}

/// The (light, view) pairs of [`Merl::samples`]: `k` polar angles each, `2k` relative
/// azimuths over $[0, \pi]$, each pair turned about the normal by a golden-angle step. Any
/// reflectance sampled on it is "MERL-style dense sampling".
pub fn grid(k: usize) -> Result<Vec<(DVec3, DVec3)>> {
    if !(2..=256).contains(&k) {
        return Err(Error::input(format!("MERL sampling density {k} is outside 2..=256")));
    }
    let golden = PI * (3.0 - 5f64.sqrt());
    let mut out = Vec::with_capacity(2 * k * k * k);
    let polar = |i: usize| (i as f64 + 0.5) / k as f64 * FRAC_PI_2;
    for il in 0..k {
        for iv in 0..k {
            for ip in 0..2 * k {
                let phi = (ip as f64 + 0.5) / (2 * k) as f64 * PI;
                let (tl, tv) = (polar(il), polar(iv));
                let turn = golden * out.len() as f64;
                let l = DVec3::new(tl.sin() * turn.cos(), tl.sin() * turn.sin(), tl.cos());
                let v = DVec3::new(tv.sin() * (turn + phi).cos(), tv.sin() * (turn + phi).sin(), tv.cos());
                out.push((l, v));
            }
        }
    }
    Ok(out)
}

impl super::Reflectance for Merl {
    /// $S = f_r \cos\theta_l$ where the table has a measurement; 0 where it has none or
    /// either direction is below the horizon (no light arrives or leaves there).
    fn shading(&self, q: &crate::factor::Query) -> [f64; 3] {
        self.brdf(q.l, q.v).map_or([0.0; 3], |f| f.map(|x| x * q.l.z.max(0.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::Analytic;

    #[test]
    fn half_diff_of_the_mirror_configuration() {
        // l and v mirrored about the normal: h = n, θ_d = θ_l, and φ_d is l's azimuth.
        let t: f64 = 0.6;
        let l = DVec3::new(t.sin(), 0.0, t.cos());
        let v = DVec3::new(-t.sin(), 0.0, t.cos());
        let (th, td, pd) = half_diff(l, v);
        assert!(th.abs() < 1e-12 && (td - t).abs() < 1e-12 && pd.abs() < 1e-12, "{th} {td} {pd}");
    }

    #[test]
    fn tabulated_brdf_reads_back_at_bin_centres_and_near_them() {
        let model = Analytic::BlinnPhong { diffuse: [0.3, 0.2, 0.1], specular: [0.2, 0.2, 0.2], exponent: 20.0 };
        let merl = Merl::from_brdf(|l, v| model.brdf(l, v));
        let dir = |t: f64, p: f64| DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
        let mut worst = 0.0f64;
        for (tl, pl, tv, pv) in [(0.3, 0.1, 0.5, 2.0), (0.9, -1.0, 0.2, 0.4), (0.4, 0.0, 0.4, 3.1)] {
            let (l, v) = (dir(tl, pl), dir(tv, pv));
            let got = merl.brdf(l, v).unwrap();
            let want = model.brdf(l, v);
            for c in 0..3 {
                worst = worst.max((got[c] - want[c]).abs() / want[c]);
            }
        }
        // Anywhere, the nearest bin differs from the model by the bin's variation only.
        assert!(worst < 0.05, "relative error {worst}");
    }

    #[test]
    fn write_read_round_trip_is_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.binary");
        let merl = Merl::from_brdf(|l, v| Analytic::Lambert { albedo: [0.5, 0.4, 0.3] }.brdf(l, v));
        merl.write(&path).unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().len(), FILE_BYTES as u64);
        assert_eq!(Merl::read(&path).unwrap(), merl);
        let s = merl.samples(8).unwrap();
        // Lambert: S = albedo/π · cos θ_l exactly at every sample.
        for x in &s {
            assert!((x.value[1] - 0.4 / PI * x.l.z).abs() < 1e-12);
        }
        assert_eq!(s.len(), 2 * 8 * 8 * 8);
    }

    #[test]
    fn truncated_oversized_and_garbage_files_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.binary");
        std::fs::write(&path, vec![0u8; 1000]).unwrap();
        assert!(Merl::read(&path).unwrap_err().to_string().contains("bad.binary"));
        std::fs::write(&path, vec![0u8; FILE_BYTES + 8]).unwrap();
        assert!(Merl::read(&path).unwrap_err().to_string().contains("trailing"));
        // Right size, wrong dimensions (all zeros).
        std::fs::write(&path, vec![0u8; FILE_BYTES]).unwrap();
        assert!(Merl::read(&path).unwrap_err().to_string().contains("dimensions"));
        assert!(Merl::read(&dir.path().join("missing.binary")).is_err());
    }
}
