use glam::DVec3;

/// Analytic reflectance models in the local shading frame (z = normal).
#[derive(Clone, Debug, PartialEq)]
pub enum Analytic {
    /// Lambertian diffuse.
    Lambert { albedo: [f64; 3] },
}

impl Analytic {
    /// The BRDF $f_r(\omega_l, \omega_v)$.
    pub fn brdf(&self, _l: DVec3, _v: DVec3) -> [f64; 3] {
        todo!()
    }

    /// The shading function $S = f_r \cos\theta_l$ a painting shows.
    pub fn shading(&self, l: DVec3, v: DVec3) -> [f64; 3] {
        let f = self.brdf(l, v);
        let c = l.z.max(0.0);
        [f[0] * c, f[1] * c, f[2] * c]
    }
}
