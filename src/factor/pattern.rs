//! Sample patterns: where the samples are, without their values. A prepared system depends
//! on the pattern only (thesis 3.2.2), so it is a type of its own.

use glam::{DVec2, DVec3};

use crate::error::{Error, Result};

/// Where one sample is: light and view directions in the local shading frame (z = normal,
/// x = tangent, y = bitangent), and the surface's texture coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Query {
    /// Unit direction toward the light.
    pub l: DVec3,
    /// Unit direction toward the viewer.
    pub v: DVec3,
    /// Texture coordinates (zero when the pattern has none).
    pub uv: DVec2,
}

impl Query {
    /// A query without texture coordinates.
    pub fn at(l: DVec3, v: DVec3) -> Query {
        Query { l, v, uv: DVec2::ZERO }
    }

    /// The half vector $h = (l + v) / |l + v|$. When $l = -v$ it is undefined; the normal is
    /// returned then, a choice that only affects a set of measure zero.
    pub fn h(&self) -> DVec3 {
        leaned_half(self.l, self.v, 1.0)
    }
}

/// The half vector leaned by $k$: $h_k = (l + k v) / |l + k v|$, $h_1 = h$. A drawn highlight
/// is a circle about $h_k$ ([`FactorSpec::lean`](super::FactorSpec::lean)); undefined where
/// $l = -k v$, where the normal is returned, as [`Query::h`] does.
pub fn leaned_half(l: DVec3, v: DVec3, k: f64) -> DVec3 {
    let s = l + k * v;
    let len = s.length();
    if len > 1e-12 {
        s / len
    } else {
        DVec3::Z
    }
}

/// One sample with its value: the public plain-list form (l, v, optional uv, RGB).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    pub l: DVec3,
    pub v: DVec3,
    pub uv: Option<DVec2>,
    /// Linear RGB value of the shading function $S = f_r \cos\theta_l$.
    pub value: [f64; 3],
}

/// A view whose light is within this many degrees of the eye at most of its samples is
/// headlit ([`headlit`]).
pub const HEADLIT_DEG: f64 = 30.0;

/// Whether most of the (light, view) pairs see the light within [`HEADLIT_DEG`] of the eye:
/// a painting lit from the viewer, where $\theta_l$, $\theta_h$ and $\theta_v$ move together
/// and the samples fix only the product of the factors along that diagonal.
pub fn headlit(pairs: impl Iterator<Item = (DVec3, DVec3)>) -> bool {
    let near = HEADLIT_DEG.to_radians().cos();
    let (mut all, mut lit) = (0usize, 0usize);
    for (l, v) in pairs {
        all += 1;
        lit += usize::from(l.dot(v) > near);
    }
    2 * lit > all
}

/// The positions of a set of samples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pattern {
    pub queries: Vec<Query>,
    /// Whether the queries carry texture coordinates (required by uv factors).
    pub has_uv: bool,
}

impl Pattern {
    /// Whether the samples are lit from the eye ([`headlit`]).
    pub fn headlit(&self) -> bool {
        headlit(self.queries.iter().map(|q| (q.l, q.v)))
    }

    /// A pattern from queries; `has_uv` says whether their `uv` fields are meaningful.
    pub fn new(queries: Vec<Query>, has_uv: bool) -> Self {
        Pattern { queries, has_uv }
    }

    /// Split plain samples into a pattern and their values. Directions are normalized;
    /// zero-length or non-finite directions are an error naming the sample.
    pub fn from_samples(samples: &[Sample]) -> Result<(Pattern, Vec<[f64; 3]>)> {
        let has_uv = samples.first().is_some_and(|s| s.uv.is_some());
        let mut queries = Vec::with_capacity(samples.len());
        let mut values = Vec::with_capacity(samples.len());
        for (k, s) in samples.iter().enumerate() {
            if s.uv.is_some() != has_uv {
                return Err(Error::input(format!("sample {k}: some samples have uv and some do not")));
            }
            let unit = |d: DVec3, what: &str| {
                let len = d.length();
                if len.is_finite() && len > 1e-12 {
                    Ok(d / len)
                } else {
                    Err(Error::input(format!("sample {k}: {what} direction {d} is not a direction")))
                }
            };
            let uv = s.uv.unwrap_or(DVec2::ZERO);
            if !uv.is_finite() {
                return Err(Error::input(format!("sample {k}: uv {uv} is not finite")));
            }
            queries.push(Query { l: unit(s.l, "light")?, v: unit(s.v, "view")?, uv });
            values.push(s.value);
        }
        Ok((Pattern { queries, has_uv }, values))
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.queries.len()
    }

    /// Whether the pattern is empty.
    pub fn is_empty(&self) -> bool {
        self.queries.is_empty()
    }

    /// Evaluate a shading function at every sample: the values a painting of it would have.
    pub fn shade(&self, f: impl Fn(&Query) -> [f64; 3]) -> Vec<[f64; 3]> {
        self.queries.iter().map(f).collect()
    }

    /// Concatenate patterns (several views of one material, thesis 4.4).
    pub fn concat(patterns: &[Pattern]) -> Pattern {
        Pattern {
            queries: patterns.iter().flat_map(|p| p.queries.iter().copied()).collect(),
            has_uv: !patterns.is_empty() && patterns.iter().all(|p| p.has_uv),
        }
    }

    /// A 64-bit fingerprint of the pattern, for cache keys.
    pub fn fingerprint(&self) -> u64 {
        let mut h = crate::util::Fnv::new();
        h.write(&[self.has_uv as u8]);
        for q in &self.queries {
            for x in [q.l.x, q.l.y, q.l.z, q.v.x, q.v.y, q.v.z, q.uv.x, q.uv.y] {
                h.write(&x.to_bits().to_le_bytes());
            }
        }
        h.finish()
    }
}
/// Which sample each pixel of one painted view holds (`None`: not a sample).
#[derive(Clone, Debug)]
pub struct Grid {
    pub width: usize,
    pub height: usize,
    pub sample: Vec<Option<u32>>,
}

