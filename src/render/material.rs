//! Materials as the renderer takes them: [`Shading::from_material`].
//!
//! A [`Material`] and a [`Shading`] describe the same function,
//!
//! $$ S(l, v, uv) = \sum_k c_k(uv)\, m_k^{-1}\Big(\prod_j p_{kj}(\pi_{kj}(l, v, uv))\Big), $$
//!
//! with the same node-based tables: every factor texture is copied as is, and a material's
//! RGB $M \times M$ coefficient texture becomes a [`CoefTexture`] with its nodes at
//! $uv = (x/(M-1), y/(M-1))$, exactly where [`crate::material::Coefficients::lookup`] puts
//! them. So the GL image of a material equals [`Material::eval`] at the G-buffer's queries
//! (tests/render_material.rs).

use super::shading::{CoefTexture, FactorTexture, Shading, Term};
use crate::error::{Error, Result};
use crate::material::Material;

impl Shading {
    /// The shading function of `material`: every term, with its factor tables, log mapping
    /// and coefficient texture.
    ///
    /// Errors ([`Error::Input`]): what [`Shading::validate`] refuses (more terms or factors
    /// than the renderer draws, non-finite values), and coefficient textures whose texel
    /// count does not match their resolution.
    pub fn from_material(material: &Material) -> Result<Shading> {
        let mut terms = Vec::with_capacity(material.terms.len());
        for (k, term) in material.terms.iter().enumerate() {
            let factors =
                term.factors.iter().map(|f| FactorTexture { spec: f.spec.clone(), texels: f.texels.clone() }).collect();
            let coefficients = match &term.coefficients {
                Some(c) if c.texels.len() != c.res * c.res => {
                    return Err(Error::input(format!(
                        "term {k}: coefficient texture has {} texels for resolution {}",
                        c.texels.len(),
                        c.res
                    )));
                }
                Some(c) => Some(CoefTexture { width: c.res, height: c.res, texels: c.texels.clone() }),
                None => None,
            };
            terms.push(Term { factors, map: term.map, coefficients });
        }
        let shading = Shading { terms };
        shading.validate()?;
        Ok(shading)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factor::{Domain, FactorSpec, Input, LogMap, Param};
    use crate::material::{Coefficients, Factor, Kind, Term as MaterialTerm};

    fn factor(input: Input, res: usize) -> Factor {
        let spec =
            FactorSpec { input, param: Param::Radius, domain: Domain::Sphere, res, smooth: 0.0, damp: 0.0, ridge: 0.0 };
        Factor { texels: (0..res).map(|i| [i as f32, 1.0, 2.0]).collect(), spec }
    }

    #[test]
    fn terms_factors_mappings_and_coefficients_carry_over() {
        let material = Material {
            kind: Kind::MaterialMap,
            terms: vec![
                MaterialTerm {
                    factors: vec![factor(Input::Light, 4)],
                    map: LogMap::Offset { a: [0.1, 0.2, 0.3] },
                    coefficients: None,
                },
                MaterialTerm {
                    factors: vec![factor(Input::Half, 3), factor(Input::View, 5)],
                    map: LogMap::Identity { floor: [1e-3; 3] },
                    coefficients: Some(Coefficients::grey(2, &[0.0, 0.25, 0.5, 1.0])),
                },
            ],
            provenance: Default::default(),
        };
        let s = Shading::from_material(&material).unwrap();
        assert_eq!(s.terms.len(), 2);
        assert_eq!(s.terms[0].map, LogMap::Offset { a: [0.1, 0.2, 0.3] });
        assert_eq!(s.terms[1].factors[1].spec, material.terms[1].factors[1].spec);
        assert_eq!(s.terms[1].factors[1].texels, material.terms[1].factors[1].texels);
        assert!(s.terms[0].coefficients.is_none());
        let c = s.terms[1].coefficients.as_ref().unwrap();
        assert_eq!((c.width, c.height), (2, 2));
        assert_eq!(c.texels[1], [0.25; 3]);

        let mut bad = material.clone();
        bad.terms[1].coefficients = Some(Coefficients::grey(3, &[1.0; 4]));
        assert!(Shading::from_material(&bad).unwrap_err().to_string().contains("term 1"));
        bad.terms = vec![material.terms[0].clone(); super::super::MAX_TERMS + 1];
        assert!(Shading::from_material(&bad).is_err());
    }
}
