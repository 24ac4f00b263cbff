//! Materials on the GPU: a [`Material`] uploaded as float textures with the `#define`s of
//! its shader program. The renderer draws exactly the function [`Material`] evaluates on the
//! CPU,
//!
//! $$ S(l, v, uv) = \sum_k c_k(uv)\, \mathrm{inv}_k\Big(\prod_j p_{kj}(\pi_{kj}(l, v, uv))\Big) $$
//!
//! where $\mathrm{inv}_k$ undoes the term's log mapping (thesis eq. 3.14, 3.16) and $c_k$ is
//! its coefficient texture (1 when absent), with the same node-based tables, so the GL image
//! of a material equals its CPU evaluation at the G-buffer's queries
//! (tests/render_material.rs). The GLSL codes of inputs, parameterizations, domains and
//! mappings are defined once, in `shaders/param.glsl`; a program's `#define`s name them.

use glam::Vec3;

use crate::error::{Error, Result};
use crate::brdf::lobe::Lobe;
use crate::factor::{Domain, Input, LogMap, Param};
use crate::gl::{Filter, Gl, Limits, TexelFormat, Texture2D};
use crate::material::Material;

/// Most factors one term may have.
pub const MAX_FACTORS: usize = 6;
/// Most terms a material may have to be drawn.
pub const MAX_TERMS: usize = 8;

/// Checks that the renderer can draw `material`. Errors ([`Error::Input`]) name the term and factor:
/// no terms, too many terms or factors, custom inputs, a parameterization that does not
/// fit the input, a texel count that does not match the resolution, non-finite values.
pub fn check(material: &Material) -> Result<()> {
    if material.terms.is_empty() {
        return Err(Error::input("the material has no terms"));
    }
    if let Some(d) = &material.detail {
        d.validate().map_err(Error::input)?;
    }
    if material.terms.len() > MAX_TERMS {
        return Err(Error::input(format!(
            "the material has {} terms; the renderer draws at most {MAX_TERMS}",
            material.terms.len()
        )));
    }
    for (k, term) in material.terms.iter().enumerate() {
        if term.factors.len() > MAX_FACTORS {
            return Err(Error::input(format!(
                "term {k} has {} factors; the renderer multiplies at most {MAX_FACTORS}",
                term.factors.len()
            )));
        }
        for (j, f) in term.factors.iter().enumerate() {
            let at = || format!("term {k}, factor {j} ({})", f.spec.input.name());
            match (&f.spec.input, f.spec.param) {
                (Input::Custom(_), _) => {
                    return Err(Error::input(format!("{}: custom inputs cannot be rendered", at())));
                }
                (Input::Uv, Param::Uv) => {}
                (Input::Uv, p) => {
                    return Err(Error::input(format!("{}: uv input with the {p:?} parameterization", at())));
                }
                (Input::HalfDifference, Param::Radii) => {}
                (input, p) if (*input == Input::HalfDifference) != (p == Param::Radii) => {
                    return Err(Error::input(format!("{}: {} input with the {p:?} parameterization", at(), input.name())));
                }
                _ => {}
            }
            if f.spec.res < 2 {
                return Err(Error::input(format!("{}: resolution {} is below 2", at(), f.spec.res)));
            }
            if f.texels.len() != f.spec.len() {
                return Err(Error::input(format!(
                    "{}: {} texels for a {}D table of resolution {} ({} expected)",
                    at(),
                    f.texels.len(),
                    f.spec.dim(),
                    f.spec.res,
                    f.spec.len()
                )));
            }
            if let Some(bad) = f.texels.iter().position(|t| !t.iter().all(|x| x.is_finite())) {
                return Err(Error::input(format!("{}: texel {bad} is not finite", at())));
            }
        }
        if !term.map.constant().iter().all(|x| x.is_finite()) {
            return Err(Error::input(format!("term {k}: mapping constant is not finite")));
        }
        if let Some(b) = &term.base {
            b.validate().map_err(|e| Error::input(format!("term {k}: base: {e}")))?;
        }
        if let Some(c) = &term.coefficients {
            if c.res == 0 || c.texels.len() != c.res * c.res {
                return Err(Error::input(format!(
                    "term {k}: coefficient texture has {} texels for resolution {}",
                    c.texels.len(),
                    c.res
                )));
            }
            if !c.texels.iter().all(|t| t.iter().all(|x| x.is_finite())) {
                return Err(Error::input(format!("term {k}: a coefficient is not finite")));
            }
        }
    }
    Ok(())
}

/// A term on the GPU: its textures and the `#define`s of its program.
pub(crate) struct GpuTerm {
    pub factors: Vec<(Texture2D, f32)>,
    pub coefficients: Option<Texture2D>,
    pub map_a: Vec3,
    /// The analytic base's uniforms (`HAS_BASE`): ambient, diffuse, specular, Fresnel; alpha.
    pub base: Option<([Vec3; 4], f32)>,
    /// `#define`s selecting the shader layout; also the program cache key.
    pub defines: Vec<(&'static str, String)>,
    pub key: String,
}

/// A [`Material`] uploaded as float textures (RGBA32F with alpha 1, linear filtering,
/// clamped). RGBA rather than RGB: llvmpipe filters RGB32F on a slower path (measured 1.8×
/// against 1.4× the GGX shader's frame time for three 1D factors at 1024²).
pub struct GpuShading {
    pub(crate) terms: Vec<GpuTerm>,
    /// The material's detail texture, which every term's pass multiplies (`HAS_DETAIL`).
    pub(crate) detail: Option<(Texture2D, f32)>,
}

impl GpuTerm {
    /// Binds the term's textures and sets its uniforms on the bound `program`
    /// (`shaders/term.glsl`).
    pub(crate) fn apply(&self, program: &crate::gl::Program) {
        for (j, (texture, res)) in self.factors.iter().enumerate() {
            texture.bind(j as u32);
            program.set_i32(FACTOR_UNIFORMS[j][0], j as i32);
            program.set_f32(FACTOR_UNIFORMS[j][1], *res);
        }
        program.set_vec3("u_map_a", self.map_a);
        if let Some(([ambient, diffuse, specular, fresnel], alpha)) = self.base {
            program.set_vec3("u_base_ambient", ambient);
            program.set_vec3("u_base_diffuse", diffuse);
            program.set_vec3("u_base_specular", specular);
            program.set_vec3("u_base_fresnel", fresnel);
            program.set_f32("u_base_alpha", alpha);
        }
        if let Some(c) = &self.coefficients {
            c.bind(COEF_UNIT);
            program.set_i32("u_coef", COEF_UNIT as i32);
            program.set_vec2("u_coef_size", glam::Vec2::new(c.width() as f32, c.height() as f32));
        }
    }
}

impl GpuShading {
    /// Binds term `k`'s textures and the material's detail, and sets their uniforms on the
    /// bound `program` (`shaders/term.glsl`).
    pub(crate) fn apply(&self, k: usize, program: &crate::gl::Program) {
        self.terms[k].apply(program);
        if let Some((d, floor)) = &self.detail {
            d.bind(DETAIL_UNIT);
            program.set_i32("u_detail", DETAIL_UNIT as i32);
            // The floor is added once, in the first term's pass (`term_detail`).
            program.set_f32("u_detail_floor", if k == 0 { *floor } else { 0.0 });
        }
    }

    /// Checks ([`check`]) and uploads `material`.
    pub fn upload(gl: &Gl, material: &Material) -> Result<GpuShading> {
        check(material)?;
        if material.terms.len() > 1 && !Limits::query(gl).float_blend {
            return Err(Error::Gl("several terms need blending of float targets (EXT_float_blend missing)".into()));
        }
        let mut terms = Vec::with_capacity(material.terms.len());
        for term in &material.terms {
            let mut factors = Vec::new();
            let mut defines: Vec<(&'static str, String)> = vec![("NUM_FACTORS", term.factors.len().to_string())];
            for (j, f) in term.factors.iter().enumerate() {
                let m = f.spec.res;
                let (w, h) = if f.spec.dim() == 1 { (m, 1) } else { (m, m) };
                let tex = Texture2D::new(gl, w, h, TexelFormat::Rgba32F, Filter::Linear, Some(&rgba(&f.texels)))?;
                factors.push((tex, m as f32));
                // Names of param.glsl's codes, which the preprocessor expands.
                let input = match f.spec.input {
                    Input::Light => "INPUT_LIGHT",
                    Input::Half => "INPUT_HALF",
                    Input::View => "INPUT_VIEW",
                    Input::Uv => "INPUT_UV",
                    Input::Difference => "INPUT_DIFFERENCE",
                    Input::HalfDifference => "INPUT_HALF_DIFFERENCE",
                    Input::Custom(_) => unreachable!("rejected by check"),
                };
                let param = match f.spec.param {
                    Param::Radius => "PARAM_RADIUS",
                    Param::Parabolic => "PARAM_PARABOLIC",
                    Param::Hemispherical => "PARAM_HEMISPHERICAL",
                    Param::Uv => "PARAM_UV",
                    Param::Radii => "PARAM_RADII",
                };
                let domain = match f.spec.domain {
                    Domain::Hemisphere => "DOMAIN_HEMISPHERE",
                    Domain::Sphere => "DOMAIN_SPHERE",
                };
                defines.push((FACTOR_DEFINES[j][0], input.to_string()));
                defines.push((FACTOR_DEFINES[j][1], param.to_string()));
                defines.push((FACTOR_DEFINES[j][2], domain.to_string()));
                defines.push((FACTOR_DEFINES[j][3], f.spec.dim().to_string()));
                // A float literal ("1.0", "2.5"): f32's Debug form always has a decimal point.
                defines.push((FACTOR_DEFINES[j][4], format!("{:?}", f.spec.warp as f32)));
                defines.push((FACTOR_DEFINES[j][5], format!("{:?}", f.spec.lean as f32)));
            }
            let (kind, a) = match term.map {
                LogMap::Identity { .. } => ("MAP_IDENTITY", [0.0; 3]),
                LogMap::Offset { a } => ("MAP_OFFSET", a),
                LogMap::Inverted { a } => ("MAP_INVERTED", a),
            };
            defines.push(("MAP_KIND", kind.to_string()));
            let coefficients = match &term.coefficients {
                Some(c) => {
                    let data = rgba(&c.texels);
                    Some(Texture2D::new(gl, c.res, c.res, TexelFormat::Rgba32F, Filter::Linear, Some(&data))?)
                }
                None => None,
            };
            defines.push(("HAS_COEF", (coefficients.is_some() as i32).to_string()));
            defines.push(("HAS_BASE", (term.base.is_some() as i32).to_string()));
            defines.push(("HAS_DETAIL", (material.detail.is_some() as i32).to_string()));
            defines.push(("DETAIL_GAIN", format!("{:?}", crate::material::detail::GAIN)));
            // The lobe's family selects the program (`shaders/term.glsl`), as `Lobe::ALL` orders them.
            let lobe = term.base.map_or(0, |b| Lobe::ALL.iter().position(|&l| l == b.lobe).unwrap_or(0));
            defines.push(("BASE_LOBE", lobe.to_string()));
            let v3 = |x: [f64; 3]| Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32);
            let base = term.base.map(|b| ([v3(b.ambient), v3(b.diffuse), v3(b.specular), v3(b.fresnel)], b.alpha as f32));
            let key = defines.iter().map(|(n, v)| format!("{n}={v}")).collect::<Vec<_>>().join(",");
            terms.push(GpuTerm {
                factors,
                coefficients,
                map_a: Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32),
                base,
                defines,
                key,
            });
        }
        let detail = match &material.detail {
            Some(d) => Some((Texture2D::new(gl, d.res, d.res, TexelFormat::Rgba32F, Filter::Linear, Some(&rgba(&d.texels)))?, d.floor)),
            None => None,
        };
        Ok(GpuShading { terms, detail })
    }

    /// Number of terms (one render pass each).
    pub fn terms(&self) -> usize {
        self.terms.len()
    }
}

impl std::fmt::Debug for GpuShading {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.terms.iter().map(|t| &t.key)).finish()
    }
}

/// RGB texels padded to RGBA with alpha 1.
fn rgba(texels: &[[f32; 3]]) -> Vec<f32> {
    texels.iter().flat_map(|t| [t[0], t[1], t[2], 1.0]).collect()
}

/// `#define` names of factor k: input, param, domain, dim, node warp, lean.
const FACTOR_DEFINES: [[&str; 6]; MAX_FACTORS] = [
    ["F0_INPUT", "F0_PARAM", "F0_DOMAIN", "F0_DIM", "F0_WARP", "F0_LEAN"],
    ["F1_INPUT", "F1_PARAM", "F1_DOMAIN", "F1_DIM", "F1_WARP", "F1_LEAN"],
    ["F2_INPUT", "F2_PARAM", "F2_DOMAIN", "F2_DIM", "F2_WARP", "F2_LEAN"],
    ["F3_INPUT", "F3_PARAM", "F3_DOMAIN", "F3_DIM", "F3_WARP", "F3_LEAN"],
    ["F4_INPUT", "F4_PARAM", "F4_DOMAIN", "F4_DIM", "F4_WARP", "F4_LEAN"],
    ["F5_INPUT", "F5_PARAM", "F5_DOMAIN", "F5_DIM", "F5_WARP", "F5_LEAN"],
];

/// Sampler uniform name and resolution uniform name of factor k.
pub(crate) const FACTOR_UNIFORMS: [[&str; 2]; MAX_FACTORS] = [
    ["u_factor0", "u_res0"],
    ["u_factor1", "u_res1"],
    ["u_factor2", "u_res2"],
    ["u_factor3", "u_res3"],
    ["u_factor4", "u_res4"],
    ["u_factor5", "u_res5"],
];

/// Texture unit of the coefficient texture (after the factors' units 0..MAX_FACTORS).
pub(crate) const COEF_UNIT: u32 = MAX_FACTORS as u32;
/// Texture unit of the detail texture (after the environment's, [`super::env`]).
pub(crate) const DETAIL_UNIT: u32 = COEF_UNIT + 2;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factor::FactorSpec;
    use crate::material::{Coefficients, Factor, Kind, Term};

    fn spec(input: Input, param: Param, res: usize) -> FactorSpec {
        FactorSpec { input, param, domain: Domain::Sphere, res, smooth: 0.0, damp: 0.0, ridge: 0.0, warp: 1.0, lean: 1.0 }
    }

    fn uniform(factors: Vec<Factor>) -> Material {
        Material::new(Kind::Uniform, vec![Term { base: None, factors, map: LogMap::Identity { floor: [1e-3; 3] }, coefficients: None }])
    }

    #[test]
    fn check_names_the_problem() {
        let ok = Factor { spec: spec(Input::Light, Param::Radius, 4), texels: vec![[1.0; 3]; 4] };
        assert!(check(&uniform(vec![ok.clone()])).is_ok());
        assert!(check(&Material::new(Kind::Uniform, vec![])).is_err());
        let short = Factor { texels: vec![[1.0; 3]; 3], ..ok.clone() };
        let e = check(&uniform(vec![short])).unwrap_err().to_string();
        assert!(e.contains("term 0, factor 0 (light)") && e.contains("4 expected"), "{e}");
        let two_d = Factor { spec: spec(Input::Half, Param::Parabolic, 4), texels: vec![[1.0; 3]; 4] };
        assert!(check(&uniform(vec![two_d])).unwrap_err().to_string().contains("16 expected"));
        let nan = Factor { texels: vec![[f32::NAN, 0.0, 0.0]; 4], ..ok.clone() };
        assert!(check(&uniform(vec![nan])).is_err());
        let uv_bad = Factor { spec: spec(Input::Uv, Param::Radius, 4), texels: vec![[1.0; 3]; 4] };
        assert!(check(&uniform(vec![uv_bad])).is_err());
        assert!(check(&uniform(vec![ok.clone(); MAX_FACTORS + 1])).is_err());
        let mut m = uniform(vec![ok.clone()]);
        m.terms[0].coefficients = Some(Coefficients::grey(2, &[1.0; 3]));
        assert!(check(&m).unwrap_err().to_string().contains("term 0"));
        m.terms = vec![uniform(vec![ok]).terms[0].clone(); MAX_TERMS + 1];
        assert!(check(&m).is_err());
    }
}
