//! The glTF metallic-roughness material of a material that varies over the surface (material
//! maps, hybrids, four-factor products): one material per texel, written as base-colour,
//! metallic-roughness and `KHR_materials_specular` colour textures.
//!
//! Each texel gets the material closest to the factored one at its texture coordinates, by
//! [`super::pbr_fit`]'s loss. Over the surface the factored shading lies in a small linear
//! space: $S(uv; l, v) = \sum_i \gamma_i(uv)\, \beta_i(l, v)$ per channel, with a column
//! $\beta_i$ per term (its coefficient and uv factor are the gain $\gamma_i$; [`columns`]).
//! At a fixed (metallic, roughness, $F_0$) node the PBR shading is $a + b\,c$
//! ([`super::pbr::affine_in_base_color`]), so the loss of a texel at that node needs only
//! the moments $\sum w a^2$, $\sum w a b$, $\sum w b^2$, $\sum w a \beta_i$, $\sum w b \beta_i$,
//! computed once over the direction pairs; every texel then searches a fine grid in
//! $O(\text{columns})$ per node.

use rayon::prelude::*;

use glam::DVec2;

use crate::brdf::Reflectance;
use crate::error::{Error, Result};
use crate::factor::{Input, LogMap, Query};
use crate::images::{encode_srgb8, srgb_to_linear_f64};
use crate::material::{Material, Term};

use super::coverage::Directions;
use super::gltf::Textures;
use super::pbr::{affine_in_base_color, Pbr, DIELECTRIC_F0, MIN_ROUGHNESS};
use super::pbr_fit::{f0_grid, grid, relative_rms};

/// Grid steps of the per-texel search: a quarter of [`super::pbr_fit`]'s coarse steps in
/// roughness and metallic, about the fine grid of its refinement; $F_0$ in ratios of
/// $1.5^{1/3}$.
const ROUGHNESS_STEP: f64 = 0.0125;
const METALLIC_STEP: f64 = 0.025;
const F0_RATIO: f64 = 1.144_714_242_553_331_4;

/// Texture side limits: below 8 a map loses its layout; above 256 the textures outgrow the
/// coefficient textures any fit writes (`fit --coef-res` is at most 256).
const MIN_RES: usize = 8;
const MAX_RES: usize = 256;

/// One PBR material per texel, row by row; row 0 is the image's top row, at
/// $v = 0.5/\text{res}$ (glTF's texture coordinates, which brdfpaint's meshes keep).
#[derive(Clone, Debug, PartialEq)]
pub struct PbrMap {
    pub res: usize,
    pub texels: Vec<Pbr>,
}

/// The result of [`fit`]: the textured material, as its 8-bit textures store it, and its
/// relative RMS against the material.
#[derive(Clone, Debug)]
pub struct MapApproximation {
    pub map: PbrMap,
    /// Over the covered directions, at their own texture coordinates (all when unknown).
    pub covered: f64,
    pub all: f64,
}

impl PbrMap {
    /// The material at texture coordinates `uv`: texels bilinearly interpolated with
    /// centres at $(i + 0.5)/\text{res}$, clamped at the edges, as the exported sampler reads
    /// them (the factored material clamps uv too).
    pub fn at(&self, uv: DVec2) -> Pbr {
        let n = self.res;
        let axis = |t: f64| {
            let x = (t * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
            let i = (x.floor() as usize).min(n.saturating_sub(2));
            (i, x - i as f64)
        };
        let ((i, fx), (j, fy)) = (axis(uv.x), axis(uv.y));
        let mut out = Pbr { base_color: [0.0; 3], metallic: 0.0, roughness: 0.0, specular_f0: 0.0, coat: None, sheen: None };
        for (di, dj, w) in [(0, 0, (1.0 - fx) * (1.0 - fy)), (1, 0, fx * (1.0 - fy)), (0, 1, (1.0 - fx) * fy), (1, 1, fx * fy)] {
            let p = &self.texels[((j + dj).min(n - 1)) * n + (i + di).min(n - 1)];
            for c in 0..3 {
                out.base_color[c] += w * p.base_color[c];
            }
            out.metallic += w * p.metallic;
            out.roughness += w * p.roughness;
            out.specular_f0 += w * p.specular_f0;
        }
        out
    }

    /// The largest dielectric $F_0$ of any texel: `KHR_materials_specular`'s
    /// `specularColorFactor` is it over 0.04, its texture the ratio of each texel's to it.
    pub fn max_f0(&self) -> f64 {
        self.texels.iter().map(|p| p.specular_f0).fold(DIELECTRIC_F0, f64::max)
    }

    /// The factors the textures multiply: 1, and the largest $F_0$ (see [`PbrMap::max_f0`]).
    pub fn factors(&self) -> Pbr {
        Pbr { base_color: [1.0; 3], metallic: 1.0, roughness: 1.0, specular_f0: self.max_f0(), coat: None, sheen: None }
    }

    /// The map as its 8-bit textures store it: base colour and the specular ratio in sRGB
    /// codes, metallic and roughness in linear ones.
    fn quantized(&self) -> PbrMap {
        let max_f0 = self.max_f0();
        let srgb = |x: f64| srgb_to_linear_f64(encode_srgb8(x as f32) as f64 / 255.0);
        let linear = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() / 255.0;
        let texels = self
            .texels
            .iter()
            .map(|p| Pbr {
                base_color: p.base_color.map(srgb),
                metallic: linear(p.metallic),
                roughness: linear(p.roughness).max(MIN_ROUGHNESS),
                specular_f0: (srgb(p.specular_f0 / max_f0) * max_f0).max(DIELECTRIC_F0),
                coat: None,
                sheen: None,
            })
            .collect();
        PbrMap { res: self.res, texels }
    }

    /// The PNG textures of the map (module documentation).
    pub fn textures(&self) -> Result<Textures> {
        let max_f0 = self.max_f0();
        let base: Vec<u8> = self.texels.iter().flat_map(|p| p.base_color.map(|c| encode_srgb8(c as f32))).collect();
        let linear8 = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
        // glTF: roughness in green, metallic in blue; red (occlusion in packed files) unused.
        let mr: Vec<u8> = self.texels.iter().flat_map(|p| [0, linear8(p.roughness), linear8(p.metallic)]).collect();
        let specular = (max_f0 > DIELECTRIC_F0 * (1.0 + 1e-9)).then(|| {
            self.texels.iter().flat_map(|p| [encode_srgb8((p.specular_f0 / max_f0) as f32); 3]).collect::<Vec<u8>>()
        });
        Ok(Textures {
            base_color: rgb_png(self.res, base)?,
            metallic_roughness: rgb_png(self.res, mr)?,
            specular_color: specular.map(|s| rgb_png(self.res, s)).transpose()?,
        })
    }
}

impl Reflectance for PbrMap {
    fn shading(&self, q: &Query) -> [f64; 3] {
        self.at(q.uv).shading(q)
    }
}

fn rgb_png(res: usize, pixels: Vec<u8>) -> Result<Vec<u8>> {
    let img = image::RgbImage::from_raw(res as u32, res as u32, pixels).ok_or_else(|| Error::input("texture buffer does not match its size"))?;
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).map_err(|e| Error::input(format!("cannot encode a texture PNG: {e}")))?;
    Ok(out.into_inner())
}

/// The texture side for `material`: its largest coefficient or uv-factor table, within
/// [8, 256].
pub fn resolution(material: &Material) -> usize {
    let tables = material.terms.iter().flat_map(|t| {
        let uv = t.factors.iter().filter(|f| f.spec.input == Input::Uv).map(|f| f.spec.res);
        t.coefficients.as_ref().map(|c| c.res).into_iter().chain(uv)
    });
    tables.max().unwrap_or(MIN_RES).clamp(MIN_RES, MAX_RES)
}

/// The per-texel material closest to `material` (module documentation), fitted on `covered`
/// (all directions when `None`) and judged there and on `all`.
pub fn fit(material: &Material, covered: Option<&Directions>, all: &Directions, res: usize) -> MapApproximation {
    let dirs = covered.unwrap_or(all);
    let uvs: Vec<DVec2> = (0..res * res).map(|k| DVec2::new(((k % res) as f64 + 0.5) / res as f64, ((k / res) as f64 + 0.5) / res as f64)).collect();
    let columns: Vec<Column> = material.terms.iter().flat_map(|t| columns(t, &dirs.queries, &uvs)).collect();
    let nodes = nodes();
    let moments: Vec<Moments> = nodes.par_iter().map(|n| Moments::new(n, dirs, &columns)).collect();
    let texels: Vec<Pbr> = (0..uvs.len())
        .into_par_iter()
        .map(|k| {
            let gains: Vec<[f64; 3]> = columns.iter().map(|col| col.gains[k]).collect();
            best_node(&nodes, &moments, &gains)
        })
        .collect();
    let map = PbrMap { res, texels }.quantized();
    MapApproximation { covered: relative_rms(&map, material, dirs), all: relative_rms(&map, material, all), map }
}

/// One column of the shading's linear space: values $\beta$ over the direction pairs and the
/// gain $\gamma$ of each texel.
struct Column {
    values: Vec<[f64; 3]>,
    gains: Vec<[f64; 3]>,
}

/// A term's columns. Without a uv factor, the term itself times its coefficient (exact).
/// With one, $s(uv)$ multiplies the product under the log mapping, so the mapped term is
/// $B\,m^{-1}(s P)$: $B P$ with gain $c\,s$, plus $B$ with gain $\mp c\,a$ for the offset
/// and inverted mappings (their clamp at zero is left out).
fn columns(term: &Term, queries: &[Query], uvs: &[DVec2]) -> Vec<Column> {
    let coefficient = |uv: DVec2| term.coefficients.as_ref().map_or([1.0; 3], |c| c.lookup(uv));
    let (uv_factors, direction_factors): (Vec<_>, Vec<_>) = term.factors.iter().partition(|f| f.spec.input == Input::Uv);
    if uv_factors.is_empty() {
        return vec![Column { values: queries.iter().map(|q| term.eval(q)).collect(), gains: uvs.iter().map(|&uv| coefficient(uv)).collect() }];
    }
    let base = |q: &Query| term.base.as_ref().map_or([1.0; 3], |b| b.shading(q));
    let product = |q: &Query| direction_factors.iter().fold([1.0; 3], |p, f| mul(p, f.lookup(q)));
    let bp: Vec<[f64; 3]> = queries.iter().map(|q| mul(base(q), product(q))).collect();
    let b: Vec<[f64; 3]> = queries.iter().map(base).collect();
    let cs: Vec<[f64; 3]> = uvs
        .iter()
        .map(|&uv| {
            let q = Query { uv, ..Query::at(glam::DVec3::Z, glam::DVec3::Z) };
            uv_factors.iter().fold(coefficient(uv), |p, f| mul(p, f.lookup(&q)))
        })
        .collect();
    let ca = |a: [f64; 3], sign: f64| uvs.iter().map(|&uv| mul(coefficient(uv), a.map(|x| sign * x))).collect();
    let negated = |g: &[[f64; 3]]| g.iter().map(|x| x.map(|v| -v)).collect();
    match term.map {
        LogMap::Identity { .. } => vec![Column { values: bp, gains: cs }],
        LogMap::Offset { a } => vec![Column { values: bp, gains: cs }, Column { values: b, gains: ca(a, -1.0) }],
        LogMap::Inverted { a } => vec![Column { values: b, gains: ca(a, 1.0) }, Column { values: bp, gains: negated(&cs) }],
    }
}

fn mul(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}

/// A node of the search: metallic and roughness at core glTF's $F_0$, and dielectrics with
/// a higher $F_0$ (`KHR_materials_specular`), as in [`super::pbr_fit`].
fn nodes() -> Vec<Pbr> {
    let roughness = grid(MIN_ROUGHNESS, 1.0, ROUGHNESS_STEP);
    let mut out = Vec::new();
    for &r in &roughness {
        for m in grid(0.0, 1.0, METALLIC_STEP) {
            out.push(Pbr::core([0.0; 3], m, r));
        }
        for f in f0_grid(DIELECTRIC_F0, 1.0, F0_RATIO).into_iter().skip(1) {
            out.push(Pbr { base_color: [0.0; 3], metallic: 0.0, roughness: r, specular_f0: f, coat: None, sheen: None });
        }
    }
    out
}

/// A node's weighted moments over the direction pairs (module documentation).
struct Moments {
    aa: f64,
    ab: f64,
    bb: f64,
    /// $\sum w a \beta_i$ and $\sum w b \beta_i$ per column and channel.
    a_col: Vec<[f64; 3]>,
    b_col: Vec<[f64; 3]>,
}

impl Moments {
    fn new(node: &Pbr, dirs: &Directions, columns: &[Column]) -> Moments {
        let mut m = Moments { aa: 0.0, ab: 0.0, bb: 0.0, a_col: vec![[0.0; 3]; columns.len()], b_col: vec![[0.0; 3]; columns.len()] };
        for (j, (q, &w)) in dirs.queries.iter().zip(&dirs.weights).enumerate() {
            let (a, b) = affine_in_base_color(node.metallic, node.roughness, node.specular_f0, q);
            m.aa += w * a * a;
            m.ab += w * a * b;
            m.bb += w * b * b;
            for (i, col) in columns.iter().enumerate() {
                for c in 0..3 {
                    m.a_col[i][c] += w * a * col.values[j][c];
                    m.b_col[i][c] += w * b * col.values[j][c];
                }
            }
        }
        m
    }
}

/// The node, with its best base colour, of least loss for a texel of column gains `gains`:
/// per channel $\sum w (a + b x - v)^2$ less the texel's constant $\sum w v^2$.
fn best_node(nodes: &[Pbr], moments: &[Moments], gains: &[[f64; 3]]) -> Pbr {
    let mut best = (nodes[0], f64::INFINITY);
    for (node, m) in nodes.iter().zip(moments) {
        let mut loss = 0.0;
        let mut base_color = [0.0; 3];
        for c in 0..3 {
            let (mut av, mut bv) = (0.0, 0.0);
            for (g, (ac, bc)) in gains.iter().zip(m.a_col.iter().zip(&m.b_col)) {
                av += g[c] * ac[c];
                bv += g[c] * bc[c];
            }
            let x = if m.bb > 0.0 { ((bv - m.ab) / m.bb).clamp(0.0, 1.0) } else { 0.0 };
            base_color[c] = x;
            loss += m.aa + 2.0 * x * m.ab + x * x * m.bb - 2.0 * av - 2.0 * x * bv;
        }
        if loss < best.1 {
            best = (Pbr { base_color, ..*node }, loss);
        }
    }
    best.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A texel whose shading is a PBR material's finds that material on the grid.
    #[test]
    fn a_texel_of_a_pbr_material_finds_it() {
        let truth = Pbr::core([0.6, 0.3, 0.1], 0.0, 0.45);
        let all = Directions::all();
        let columns = vec![Column { values: all.queries.iter().map(|q| truth.shading(q)).collect(), gains: vec![[1.0; 3]] }];
        let nodes = nodes();
        let moments: Vec<Moments> = nodes.iter().map(|n| Moments::new(n, &all, &columns)).collect();
        let p = best_node(&nodes, &moments, &[[1.0; 3]]);
        assert!((p.roughness - 0.45).abs() < 0.01 && p.metallic < 0.03, "{p:?}");
        for c in 0..3 {
            assert!((p.base_color[c] - truth.base_color[c]).abs() < 0.01, "{p:?}");
        }
    }

    /// The columns and gains add up to the material's shading, for a term with a uv factor
    /// under each log mapping (constants where the mapping's clamp at zero stays inactive).
    #[test]
    fn columns_rebuild_a_four_factor_material() {
        use crate::brdf::{Analytic, Striped};
        use crate::factor::{prepare, Mapping, Pattern, Settings};
        let model = Analytic::BlinnPhong { diffuse: [0.4, 0.3, 0.2], specular: [0.3, 0.3, 0.3], exponent: 20.0 };
        let queries: Vec<Query> = Striped::painted_views(40).iter().flat_map(|v| v.pixels()).map(|p| p.query).collect();
        let values: Vec<[f64; 3]> = queries.iter().map(|q| model.shading(q).map(|x| x * (1.0 + q.uv.x))).collect();
        let settings = Settings::four_factor(1, 32, 16);
        let fit = prepare(&Pattern::new(queries.clone(), true), &settings).unwrap().solve(&values, Mapping::Auto).unwrap();
        let mut material = Material::from_fit(&settings, &fit, Default::default()).unwrap();
        let uvs = [DVec2::new(0.1, 0.3), DVec2::new(0.62, 0.5), DVec2::new(0.9, 0.85)];
        let probes: Vec<Query> = queries.iter().step_by(211).copied().collect();
        for map in [LogMap::Identity { floor: [0.0; 3] }, LogMap::Offset { a: [1e-6; 3] }, LogMap::Inverted { a: [10.0; 3] }] {
            material.terms[0].map = map;
            let columns = columns(&material.terms[0], &probes, &uvs);
            for (t, &uv) in uvs.iter().enumerate() {
                for (j, q) in probes.iter().enumerate() {
                    let want = material.shading(&Query { uv, ..*q });
                    for c in 0..3 {
                        let got: f64 = columns.iter().map(|col| col.gains[t][c] * col.values[j][c]).sum();
                        assert!((got - want[c]).abs() <= 1e-9 * (1.0 + want[c].abs()), "{map:?} at {uv}: {got} vs {}", want[c]);
                    }
                }
            }
        }
    }

    #[test]
    fn bilinear_lookup_hits_texel_centres_and_clamps() {
        let texel = |r: f64| Pbr::core([r; 3], 0.0, r);
        let map = PbrMap { res: 2, texels: vec![texel(0.2), texel(0.4), texel(0.6), texel(0.8)] };
        assert!((map.at(DVec2::new(0.25, 0.25)).roughness - 0.2).abs() < 1e-12);
        assert!((map.at(DVec2::new(0.75, 0.75)).roughness - 0.8).abs() < 1e-12);
        assert!((map.at(DVec2::new(0.5, 0.25)).roughness - 0.3).abs() < 1e-12);
        assert!((map.at(DVec2::new(0.0, 1.0)).roughness - 0.6).abs() < 1e-12);
    }
}
