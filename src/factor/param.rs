//! Parameterizations: how a direction (or a surface point) becomes a coordinate in a factor's
//! table. Each is a pair of small functions, forward and inverse, tested by round trip.
//!
//! All forward maps return table coordinates in $[0, 1]$ (1D) or $[0, 1]^2$ (2D), so a table
//! of any resolution indexes them the same way.
//!
//! **Below the horizon.** Paintings include the unlit side (DESIGN.md), so every directional
//! parameterization has a [`Domain::Sphere`] form that keeps directions with $z < 0$ distinct.
//! The upper hemisphere uses the thesis's map unchanged; the lower hemisphere uses the same
//! map mirrored through the tangent plane and placed in an outer ring, so the extension is
//! continuous across the horizon (a dual-paraboloid construction for the parabolic maps).

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

/// Which directions a directional factor represents.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Domain {
    /// Only $z \ge 0$; a direction below the horizon is clamped onto it.
    Hemisphere,
    /// The whole sphere: the upper hemisphere fills the inner half of the radius, the lower
    /// hemisphere the outer half.
    Sphere,
}

/// How a factor's input becomes a table coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Param {
    /// 1D: the length of the parabolic projection, $|\pi(d)| = \tan(\theta/2)$ (eq. 3.5).
    /// Isotropic factors are radially symmetric under the parabolic map (thesis 3.2.1).
    Radius,
    /// 2D: the parabolic map $\pi(d) = (d_x, d_y) / (1 + d_z)$ (McCool et al.; thesis 3.1).
    Parabolic,
    /// 2D: the hemispherical map, the orthographic projection $(d_x, d_y)$ (thesis fig. 3.1a).
    Hemispherical,
    /// 2D: surface texture coordinates $(u, v)$, clamped to $[0, 1]^2$.
    Uv,
    /// 2D: the radius map of two directions, one per axis: $(|\pi(h)|, |\pi(d)|)$ for the
    /// half/difference pair, so the table is a function of $(\theta_h, \theta_d)$.
    Radii,
}

impl Param {
    /// Number of table dimensions: 1 or 2.
    pub fn dim(self) -> usize {
        match self {
            Param::Radius => 1,
            Param::Parabolic | Param::Hemispherical | Param::Uv | Param::Radii => 2,
        }
    }
}

/// The "extended radius" of a direction, continuous over the whole sphere:
/// $\rho = \tan(\theta/2) \in [0, 1]$ above the horizon and
/// $\rho = 2 - \tan((\pi - \theta)/2) \in [1, 2]$ below it.
pub fn theta_to_rho(cos_theta: f64, sin_theta: f64) -> f64 {
    // $\tan(\theta/2) = \sin\theta / (1 + \cos\theta)$, stable for $\theta \le \pi/2$.
    if cos_theta >= 0.0 {
        sin_theta / (1.0 + cos_theta)
    } else {
        // Mirror through the tangent plane: $\tan((\pi-\theta)/2) = \sin\theta / (1 - \cos\theta)$.
        2.0 - sin_theta / (1.0 - cos_theta)
    }
}

/// Inverse of [`theta_to_rho`]: the polar angle $\theta \in [0, \pi]$ of an extended radius.
pub fn rho_to_theta(rho: f64) -> f64 {
    let rho = rho.clamp(0.0, 2.0);
    if rho <= 1.0 {
        2.0 * rho.atan()
    } else {
        std::f64::consts::PI - 2.0 * (2.0 - rho).atan()
    }
}

/// $\sqrt{x^2 + y^2}$ of a unit direction: $\sin\theta$. Directions are unit length, so
/// the squares can neither overflow nor underflow, and `hypot`'s guard (a fifth of the time
/// spent building a system) buys nothing.
#[inline]
fn planar_length(d: DVec3) -> f64 {
    (d.x * d.x + d.y * d.y).sqrt()
}

/// 1D radius map: direction to table coordinate $t \in [0, 1]$.
pub fn radius_forward(d: DVec3, domain: Domain) -> f64 {
    let sin_theta = planar_length(d);
    match domain {
        // Clamp below-horizon directions onto the horizon, where $\rho = 1$.
        Domain::Hemisphere => {
            if d.z <= 0.0 {
                1.0
            } else {
                (sin_theta / (1.0 + d.z)).min(1.0)
            }
        }
        Domain::Sphere => theta_to_rho(d.z, sin_theta) * 0.5,
    }
}

/// Inverse of [`radius_forward`]: the polar angle $\theta$ of a table coordinate.
pub fn radius_inverse(t: f64, domain: Domain) -> f64 {
    match domain {
        Domain::Hemisphere => rho_to_theta(t.clamp(0.0, 1.0)),
        Domain::Sphere => rho_to_theta(t.clamp(0.0, 1.0) * 2.0),
    }
}

/// Rusinkiewicz's difference vector (1998): $l$ in the frame whose pole is $h$, reached by
/// rotating $h$ onto the normal, $d = R_y(-\theta_h) R_z(-\phi_h)\, l$. Its polar angle is
/// $\theta_d$, the angle between $l$ and $h$ ($d_z = l \cdot h$).
pub fn difference(l: DVec3, h: DVec3) -> DVec3 {
    let sin_h = planar_length(h);
    // $\phi_h$ is undefined at the pole, where $R_y(0)$ leaves any choice equivalent.
    let (c, s) = if sin_h > 1e-12 { (h.x / sin_h, h.y / sin_h) } else { (1.0, 0.0) };
    // Rotate by $-\phi_h$ about z ...
    let l1 = DVec3::new(c * l.x + s * l.y, -s * l.x + c * l.y, l.z);
    // ... then by $-\theta_h$ about y.
    DVec3::new(h.z * l1.x - sin_h * l1.z, l1.y, sin_h * l1.x + h.z * l1.z)
}

/// Node warp of a radius coordinate: $s = t^{1/\gamma}$, so a table uniform in $s$ has its
/// nodes dense near $t = 0$ ($dt/ds = \gamma s^{\gamma - 1}$ vanishes there).
pub fn warp_forward(t: f64, gamma: f64) -> f64 {
    if gamma == 1.0 {
        t
    } else if gamma == 3.0 {
        // The half factor's default warp, on every sample of every prepare.
        cube_root(t.clamp(0.0, 1.0))
    } else {
        t.clamp(0.0, 1.0).powf(1.0 / gamma)
    }
}

/// $x^{1/3}$ for $x \in [0, 1]$ to a few ulp: a first guess from the exponent divided by
/// three (within 4%), then three steps of Halley's iteration (each cubes the relative error),
/// several times cheaper than a library root.
#[inline]
fn cube_root(x: f64) -> f64 {
    if !(x >= 1e-300) {
        return x.max(0.0).cbrt();
    }
    // 0x2A9F7893782DA1CE ≈ (2/3)·1023 in the exponent field, less a bias that centres the error.
    let mut y = f64::from_bits(x.to_bits() / 3 + 0x2A9F_7893_782D_A1CE);
    for _ in 0..3 {
        let y3 = y * y * y;
        y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
    }
    y
}

/// Inverse of [`warp_forward`]: $t = s^\gamma$.
pub fn warp_inverse(s: f64, gamma: f64) -> f64 {
    s.clamp(0.0, 1.0).powf(gamma)
}

/// The planar radius a 2D map assigns to polar angle $\theta$ (before scaling to the table).
fn planar_radius(param: Param, cos_theta: f64, sin_theta: f64) -> f64 {
    match param {
        Param::Parabolic => theta_to_rho(cos_theta, sin_theta),
        // Hemispherical: $\sin\theta$ above, mirrored to $2 - \sin\theta$ below the horizon.
        _ => {
            if cos_theta >= 0.0 {
                sin_theta
            } else {
                2.0 - sin_theta
            }
        }
    }
}

/// Inverse of [`planar_radius`]: $\theta$ from a planar radius in $[0, 2]$.
fn planar_theta(param: Param, r: f64) -> f64 {
    match param {
        Param::Parabolic => rho_to_theta(r),
        _ => {
            let r = r.clamp(0.0, 2.0);
            if r <= 1.0 {
                r.asin()
            } else {
                std::f64::consts::PI - (2.0 - r).asin()
            }
        }
    }
}

/// 2D directional map (parabolic or hemispherical): direction to $t \in [0, 1]^2$.
///
/// Hemisphere domain: the unit disk (the thesis's map) scaled into the square.
/// Sphere domain: the disk of radius 2, keeping the azimuth, scaled into the square.
pub fn planar_forward(param: Param, d: DVec3, domain: Domain) -> DVec2 {
    let sin_theta = planar_length(d);
    // The azimuth is undefined at the poles; any unit vector works there since r = 0 (north)
    // and the south pole is a single point on the outer circle.
    let azimuth = if sin_theta > 1e-12 { DVec2::new(d.x, d.y) / sin_theta } else { DVec2::X };
    let (r, scale) = match domain {
        Domain::Hemisphere => {
            let cos_theta = d.z.max(0.0);
            // Clamp onto the horizon: below-horizon directions keep their azimuth.
            let sin_theta = if d.z <= 0.0 { 1.0 } else { sin_theta };
            (planar_radius(param, cos_theta, sin_theta).min(1.0), 1.0)
        }
        Domain::Sphere => (planar_radius(param, d.z, sin_theta), 0.5),
    };
    (azimuth * r * scale + DVec2::ONE) * 0.5
}

/// Inverse of [`planar_forward`]: the unit direction of a table coordinate. Coordinates
/// outside the domain's disk map to its boundary.
pub fn planar_inverse(param: Param, t: DVec2, domain: Domain) -> DVec3 {
    let p = t * 2.0 - DVec2::ONE;
    let scale = match domain {
        Domain::Hemisphere => 1.0,
        Domain::Sphere => 2.0,
    };
    let r = (p.length() * scale).min(scale);
    let azimuth = if p.length() > 1e-12 { p / p.length() } else { DVec2::X };
    let theta = planar_theta(param, r);
    let (s, c) = theta.sin_cos();
    DVec3::new(azimuth.x * s, azimuth.y * s, c)
}

/// Texture coordinates to table coordinates: clamped to the unit square.
pub fn uv_forward(uv: DVec2) -> DVec2 {
    uv.clamp(DVec2::ZERO, DVec2::ONE)
}

/// Index (row by row) of the node of a `res` × `res` uv table nearest to texture coordinates
/// `uv`, nodes at $t_i = i/(res - 1)$.
pub fn uv_nearest_node(uv: DVec2, res: usize) -> usize {
    let t = uv_forward(uv) * (res - 1) as f64;
    t.y.round() as usize * res + t.x.round() as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn cube_root_agrees_with_the_library_root() {
        let mut worst = 0.0f64;
        for k in 0..=100_000 {
            // Uniform in [0, 1] and geometric down to 1e-300.
            for x in [k as f64 / 100_000.0, 10f64.powf(-300.0 * k as f64 / 100_000.0)] {
                let (ours, exact) = (cube_root(x), x.cbrt());
                worst = worst.max((ours - exact).abs() / exact.max(f64::MIN_POSITIVE));
            }
        }
        assert!(worst < 4.0 * f64::EPSILON, "{worst:e}");
        assert_eq!((cube_root(0.0), cube_root(1.0), cube_root(0.125)), (0.0, 1.0, 0.5));
    }

    fn dir(theta: f64, phi: f64) -> DVec3 {
        DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
    }

    #[test]
    fn radius_is_tan_half_theta_above_the_horizon() {
        for i in 0..=20 {
            let theta = i as f64 / 20.0 * PI / 2.0;
            let t = radius_forward(dir(theta, 0.3), Domain::Hemisphere);
            assert!((t - (theta / 2.0).tan()).abs() < 1e-12, "theta {theta}: {t}");
        }
    }

    #[test]
    fn radius_round_trips_over_the_sphere() {
        for i in 0..=40 {
            let theta = i as f64 / 40.0 * PI;
            let t = radius_forward(dir(theta, 1.1), Domain::Sphere);
            assert!((0.0..=1.0).contains(&t));
            let back = radius_inverse(t, Domain::Sphere);
            assert!((back - theta).abs() < 1e-9, "theta {theta} -> t {t} -> {back}");
        }
    }

    #[test]
    fn radius_is_continuous_and_monotonic_across_the_horizon() {
        let mut last = -1.0;
        for i in 0..=1000 {
            let theta = i as f64 / 1000.0 * PI;
            let t = radius_forward(dir(theta, 0.0), Domain::Sphere);
            assert!(t > last, "not monotonic at theta {theta}");
            assert!(t - last < 0.01 || i == 0, "jump at theta {theta}");
            last = t;
        }
    }

    #[test]
    fn hemisphere_domain_clamps_below_the_horizon() {
        assert_eq!(radius_forward(dir(2.0, 0.0), Domain::Hemisphere), 1.0);
        let t = planar_forward(Param::Parabolic, dir(2.5, 0.0), Domain::Hemisphere);
        assert!((t - DVec2::new(1.0, 0.5)).length() < 1e-12, "{t}");
    }

    #[test]
    fn planar_maps_round_trip() {
        for param in [Param::Parabolic, Param::Hemispherical] {
            for domain in [Domain::Hemisphere, Domain::Sphere] {
                let max_theta = if domain == Domain::Sphere { PI * 0.999 } else { PI / 2.0 };
                for i in 0..=16 {
                    for k in 0..12 {
                        let theta = i as f64 / 16.0 * max_theta;
                        let d = dir(theta, k as f64 * 0.5);
                        let t = planar_forward(param, d, domain);
                        assert!(t.x >= 0.0 && t.x <= 1.0 && t.y >= 0.0 && t.y <= 1.0);
                        let back = planar_inverse(param, t, domain);
                        // The hemispherical map loses precision at the horizon (d sin = 0).
                        let tol = if param == Param::Hemispherical { 1e-6 } else { 1e-10 };
                        assert!(
                            (back - d).length() < tol || (theta - PI / 2.0).abs() < 1e-9,
                            "{param:?} {domain:?}: {d} -> {t} -> {back}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn difference_vector_is_light_seen_from_the_half_vector() {
        // Hand-worked: l and v at 60 degrees on either side of the normal in the xz plane:
        // h = n, so d = l; theta_d = 60 degrees.
        let (l, v) = (dir(PI / 3.0, 0.0), dir(PI / 3.0, PI));
        let h = (l + v).normalize();
        assert!((difference(l, h) - l).length() < 1e-12);
        // Any pair: d is a unit vector with d.z = l.h, and h maps to the pole.
        for k in 0..50 {
            let l = dir(0.03 * k as f64, 0.7 * k as f64);
            let v = dir(1.5 - 0.02 * k as f64, 2.0 - 0.3 * k as f64);
            let h = (l + v).normalize();
            let d = difference(l, h);
            assert!((d.length() - 1.0).abs() < 1e-12 && (d.z - l.dot(h)).abs() < 1e-12, "l {l} v {v}: d {d}");
            assert!((difference(h, h) - DVec3::Z).length() < 1e-12, "h {h}");
            // Rusinkiewicz: v is l mirrored about the pole in the (h, d) frame, d_v = (-d_x, -d_y, d_z).
            let dv = difference(v, h);
            assert!((dv - DVec3::new(-d.x, -d.y, d.z)).length() < 1e-12, "{d} vs {dv}");
        }
    }

    #[test]
    fn warp_round_trips_and_crowds_nodes_near_zero() {
        for gamma in [1.0, 1.5, 3.0, 8.0] {
            for i in 0..=100 {
                let t = i as f64 / 100.0;
                let s = warp_forward(t, gamma);
                assert!((warp_inverse(s, gamma) - t).abs() < 1e-12, "gamma {gamma} t {t}");
            }
        }
        // Hand-worked: with gamma = 3, t = 0.1 sits at s = 0.1^(1/3) = 0.4642: 46% of the nodes.
        assert!((warp_forward(0.1, 3.0) - 0.464_158_883_361_277_9).abs() < 1e-12);
        assert_eq!(warp_forward(0.37, 1.0), 0.37);
    }

    #[test]
    fn parabolic_matches_the_thesis_formula() {
        let d = DVec3::new(0.3, -0.4, (1.0f64 - 0.25).sqrt());
        let t = planar_forward(Param::Parabolic, d, Domain::Hemisphere);
        let expected = DVec2::new(d.x, d.y) / (1.0 + d.z);
        assert!(((t * 2.0 - DVec2::ONE) - expected).length() < 1e-12);
    }
}
