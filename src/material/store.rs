//! The material directory: `material.json` plus one float EXR per table (DESIGN.md,
//! Material directory; the README documents the format).
//!
//! A 1D table of M nodes is an M×1 image, a 2D table M×M with row $y$ of the table as image
//! row $y$; node $i$ sits at table coordinate $i/(M-1)$, so a GL sampler with linear
//! filtering reads it at texel coordinate $(t(M-1) + 0.5)/M$. Values are linear.
//! Coefficient textures hold one coefficient per colour channel.
//!
//! Saving is whole-or-nothing ([`crate::commit`]): everything is written into a temporary
//! sibling directory that then replaces the old one in one atomic exchange, so a failed or
//! killed save leaves the previous material untouched, and the user's other files in the
//! directory are kept.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{Coefficients, Detail, Factor, Kind, Material, Provenance, Term};
use crate::commit::{Claim, Legacy, StagedDir};
use crate::error::{Error, Result};
use crate::brdf::lobe::Base;
use crate::factor::{FactorSpec, LogMap};
use crate::images::Rgb;

/// The `format` field of every material.json.
pub const FORMAT: &str = "brdfpaint-material";
/// The version this build writes. Version 2 added the half/difference inputs
/// (`difference`, `half-difference` with the `radii` parameterization) and the node warp of
/// radius tables (`warp`, absent when 1). Version 3 added a term's analytic base (`base`:
/// ambient, diffuse, specular and Fresnel per channel, the GGX width `alpha`; absent without
/// one). Version 4 added the base lobe's family (`lobe`: `ggx`, `blinn-phong`, `phong`,
/// `ward`, `ashikhmin-shirley`, `oren-nayar` or `minnaert`), which a version 3 reader would
/// ignore and draw as GGX. Version 5 added the painting's detail (`detail`: `res`, `floor`
/// and `texture`, a square EXR looked up by the view-space normal; absent without one), which a
/// version 4 reader would ignore and draw without. Version 6 added a half-vector factor's lean
/// (`lean`, absent when 1: [`FactorSpec::lean`]), which a version 5 reader would ignore and
/// draw at the mirror direction.
pub const VERSION: u32 = 6;
/// The versions this build reads: version 1 files are version 2 files without those
/// (every factor unwarped), version 2 files are version 3 files without bases, version 3
/// files are version 4 files whose bases are all GGX, version 4 files are version 5 files
/// without detail, version 5 files are version 6 files without leans.
pub const READS: [u32; 6] = [1, 2, 3, 4, 5, 6];
/// Largest material.json read (the provenance is the only part that grows).
const MAX_JSON_BYTES: u64 = 16 << 20;

#[derive(Serialize, Deserialize)]
struct FileFactor {
    #[serde(flatten)]
    spec: FactorSpec,
    texture: String,
}

#[derive(Serialize, Deserialize)]
struct FileCoefficients {
    res: usize,
    texture: String,
}

#[derive(Serialize, Deserialize)]
struct FileTerm {
    mapping: LogMap,
    factors: Vec<FileFactor>,
    coefficients: Option<FileCoefficients>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    base: Option<Base>,
}

/// The detail texture's file: [`Detail`]'s square image, `res` texels a side, and its floor.
#[derive(Serialize, Deserialize)]
struct FileDetail {
    res: usize,
    floor: f32,
    texture: String,
}

/// The file name the detail texture is written under.
const DETAIL_TEXTURE: &str = "detail.exr";

#[derive(Serialize, Deserialize)]
struct FileMaterial {
    format: String,
    version: u32,
    kind: Kind,
    terms: Vec<FileTerm>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    detail: Option<FileDetail>,
    #[serde(default)]
    provenance: Provenance,
}

/// Just enough of the file to check what it is before parsing the rest.
#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<u32>,
}

impl Material {
    /// Save into directory `dir` (created; an existing material there is replaced only once
    /// the new one is complete, keeping the user's other files: [`Material::stage`]).
    pub fn save(&self, dir: &Path) -> Result<()> {
        self.stage(dir)?.commit()
    }

    /// Writes the material into a staged directory that becomes `dir` when committed, so a
    /// caller can add its own files (a fit's report.png) before the material appears: it
    /// appears whole, with them, or not at all ([`crate::commit`]).
    ///
    /// `dir` must be missing, an empty directory or a material directory; anything else (a
    /// file, a link, a directory of other things) is refused with one line. In a material
    /// directory only the files the tool recorded writing are replaced ([`crate::commit::owned`]);
    /// the user's other files there (notes, paintings, a scene) are kept, and a user's file
    /// at a name the new material writes stops the save with one line.
    pub fn stage(&self, dir: &Path) -> Result<StagedDir> {
        self.validate(dir)?;
        let legacy = check_target(dir)?;
        let staged = StagedDir::new(dir, Claim::new(&["material.json", "report.png"], legacy))?;
        staged.fill(|tmp| self.write_into(tmp))?;
        Ok(staged)
    }

    fn write_into(&self, dir: &Path) -> Result<()> {
        let mut terms = Vec::new();
        for (k, term) in self.terms.iter().enumerate() {
            let mut factors = Vec::new();
            for (j, f) in term.factors.iter().enumerate() {
                let texture = format!("term{k}-factor{j}-{}.exr", f.spec.input.name());
                let (w, h) = if f.spec.dim() == 1 { (f.spec.res, 1) } else { (f.spec.res, f.spec.res) };
                Rgb { width: w, height: h, pixels: f.texels.clone() }.write_exr(&dir.join(&texture))?;
                factors.push(FileFactor { spec: f.spec.clone(), texture });
            }
            let coefficients = match &term.coefficients {
                Some(c) => {
                    let texture = format!("term{k}-coefficients.exr");
                    let pixels = c.texels.clone();
                    Rgb { width: c.res, height: c.res, pixels }.write_exr(&dir.join(&texture))?;
                    Some(FileCoefficients { res: c.res, texture })
                }
                None => None,
            };
            terms.push(FileTerm { mapping: term.map, factors, coefficients, base: term.base });
        }
        let detail = match &self.detail {
            Some(d) => {
                Rgb { width: d.res, height: d.res, pixels: d.texels.clone() }.write_exr(&dir.join(DETAIL_TEXTURE))?;
                Some(FileDetail { res: d.res, floor: d.floor, texture: DETAIL_TEXTURE.into() })
            }
            None => None,
        };
        let file = FileMaterial {
            format: FORMAT.into(),
            version: VERSION,
            kind: self.kind,
            terms,
            detail,
            provenance: self.provenance.clone(),
        };
        let json = serde_json::to_string_pretty(&file).map_err(|e| Error::format(dir, e.to_string()))?;
        crate::commit::write_atomic(&dir.join("material.json"), json.as_bytes())
    }

    /// Load a material directory (or its material.json, or a .glb that carries one:
    /// [`super::packed`]).
    pub fn load(path: &Path) -> Result<Material> {
        if super::packed::is_glb(path) {
            return super::packed::load_glb(path);
        }
        let (dir, json_path) = if path.is_dir() {
            (path.to_path_buf(), path.join("material.json"))
        } else {
            (path.parent().map(Path::to_path_buf).unwrap_or_default(), path.to_path_buf())
        };
        let bytes = crate::fsio::read_regular(&json_path, MAX_JSON_BYTES)?;
        let text = String::from_utf8(bytes).map_err(|_| Error::format(&json_path, "not a material: not UTF-8 text"))?;
        let header: Header =
            serde_json::from_str(&text).map_err(|e| Error::format(&json_path, format!("not a material: {e}")))?;
        if header.format.as_deref() != Some(FORMAT) {
            return Err(Error::format(&json_path, format!("not a brdfpaint material (no \"format\": \"{FORMAT}\")")));
        }
        match header.version {
            Some(v) if READS.contains(&v) => {}
            Some(v) => {
                return Err(Error::format(
                    &json_path,
                    format!("material version {v}; this brdfpaint reads versions {} to {VERSION}", READS[0]),
                ))
            }
            None => return Err(Error::format(&json_path, "material has no version")),
        }
        let file: FileMaterial =
            serde_json::from_str(&text).map_err(|e| Error::format(&json_path, format!("invalid material: {e}")))?;
        check_before_decoding(&file, &dir, &json_path)?;
        let mut terms = Vec::new();
        for t in file.terms {
            let mut factors = Vec::new();
            for f in t.factors {
                let path = texture_path(&dir, &json_path, &f.texture)?;
                let img = Rgb::read_exr(&path)?;
                let (w, h) = if f.spec.dim() == 1 { (f.spec.res, 1) } else { (f.spec.res, f.spec.res) };
                if (img.width, img.height) != (w, h) {
                    return Err(Error::format(
                        &path,
                        format!("texture is {}x{} but its factor needs {w}x{h}", img.width, img.height),
                    ));
                }
                factors.push(Factor { spec: f.spec, texels: img.pixels });
            }
            let coefficients = match t.coefficients {
                Some(c) => {
                    let path = texture_path(&dir, &json_path, &c.texture)?;
                    let img = Rgb::read_exr(&path)?;
                    if (img.width, img.height) != (c.res, c.res) {
                        return Err(Error::format(
                            &path,
                            format!("coefficient texture is {}x{} but should be {}x{}", img.width, img.height, c.res, c.res),
                        ));
                    }
                    Some(Coefficients { res: c.res, texels: img.pixels })
                }
                None => None,
            };
            terms.push(Term { base: t.base, factors, map: t.mapping, coefficients });
        }
        let detail = match file.detail {
            Some(d) => {
                let img = Rgb::read_exr(&texture_path(&dir, &json_path, &d.texture)?)?;
                Some(Detail { res: d.res, floor: d.floor, texels: img.pixels })
            }
            None => None,
        };
        let material = Material { kind: file.kind, terms, detail, provenance: file.provenance };
        material.validate(&json_path)?;
        Ok(material)
    }

    /// Structural checks shared by save and load: at least one term, resolutions in range,
    /// texel counts matching, finite non-negative texels, finite mapping constants.
    fn validate(&self, path: &Path) -> Result<()> {
        let bad = |why: String| Err(Error::format(path, why));
        if self.terms.is_empty() {
            return bad("material has no terms".into());
        }
        for (k, t) in self.terms.iter().enumerate() {
            if t.factors.is_empty() {
                return bad(format!("term {k} has no factors"));
            }
            let settings = crate::factor::Settings { factors: t.factors.iter().map(|f| f.spec.clone()).collect(), method: Default::default(), light_prior: None, light_radius_deg: 0.0, channels: Default::default() };
            settings.validate().or_else(|e| bad(format!("term {k}: {e}")))?;
            for (j, f) in t.factors.iter().enumerate() {
                if f.texels.len() != f.spec.len() {
                    return bad(format!("term {k} factor {j}: {} texels for a table of {}", f.texels.len(), f.spec.len()));
                }
                if f.texels.iter().flatten().any(|x| !x.is_finite() || *x < 0.0) {
                    return bad(format!("term {k} factor {j}: table has negative or non-finite values"));
                }
            }
            if t.map.constant().iter().any(|x| !x.is_finite()) {
                return bad(format!("term {k}: mapping constant is not finite"));
            }
            if let Some(b) = &t.base {
                b.validate().or_else(|e| bad(format!("term {k}: base: {e}")))?;
            }
            if let Some(c) = &t.coefficients {
                if c.res < 2 || c.res > super::map::MAX_COEF_RES || c.texels.len() != c.res * c.res {
                    return bad(format!("term {k}: coefficient texture of {} texels at resolution {}", c.texels.len(), c.res));
                }
                if c.texels.iter().flatten().any(|x| !x.is_finite() || *x < 0.0) {
                    return bad(format!("term {k}: coefficient texture has negative or non-finite values"));
                }
            }
        }
        if let Some(d) = &self.detail {
            d.validate().or_else(bad)?;
        }
        Ok(())
    }
}

/// A texture named in material.json, which must stay inside the material directory: a
/// plain file name, and not a symbolic link out of it (README, "File access").
fn texture_path(dir: &Path, json: &Path, name: &str) -> Result<PathBuf> {
    let p = Path::new(name);
    if p.is_absolute() || p.components().any(|c| !matches!(c, std::path::Component::Normal(_))) {
        return Err(Error::format(json, format!("texture path '{name}' must be a plain file name")));
    }
    let dir = if dir.as_os_str().is_empty() { Path::new(".") } else { dir };
    crate::fsio::resolve_inside(dir, name).map_err(|refused| match refused {
        crate::fsio::Refused::Missing(path, e) => Error::io(path, e),
        crate::fsio::Refused::Outside(reason) => Error::format(json, format!("texture {reason}")),
    })
}

/// What can be checked before any texture is decoded, so a small material.json cannot make
/// a load decode gigabytes it then refuses: the term and factor counts the renderer draws
/// ([`crate::render::MAX_TERMS`], [`crate::render::MAX_FACTORS`]), each table's and
/// coefficient texture's resolution, and each texture file's size from its header.
fn check_before_decoding(file: &FileMaterial, dir: &Path, json: &Path) -> Result<()> {
    use crate::render::{MAX_FACTORS, MAX_TERMS};
    let bad = |why: String| Err(Error::format(json, why));
    if !(1..=MAX_TERMS).contains(&file.terms.len()) {
        return bad(format!("material has {} terms; 1 to {MAX_TERMS} are read (the most the renderer draws)", file.terms.len()));
    }
    for (k, t) in file.terms.iter().enumerate() {
        if !(1..=MAX_FACTORS).contains(&t.factors.len()) {
            return bad(format!("term {k} has {} factors; 1 to {MAX_FACTORS} are read (the most the renderer multiplies)", t.factors.len()));
        }
        let settings = crate::factor::Settings { factors: t.factors.iter().map(|f| f.spec.clone()).collect(), method: Default::default(), light_prior: None, light_radius_deg: 0.0, channels: Default::default() };
        settings.validate().or_else(|e| bad(format!("term {k}: {e}")))?;
        for f in &t.factors {
            let side = if f.spec.dim() == 1 { (f.spec.res, 1) } else { (f.spec.res, f.spec.res) };
            check_texture_size(&texture_path(dir, json, &f.texture)?, side, "its factor needs")?;
        }
        if let Some(c) = &t.coefficients {
            if !(2..=super::map::MAX_COEF_RES).contains(&c.res) {
                return bad(format!("term {k}: coefficient resolution {} is outside 2..={}", c.res, super::map::MAX_COEF_RES));
            }
            check_texture_size(&texture_path(dir, json, &c.texture)?, (c.res, c.res), "its coefficients need")?;
        }
    }
    if let Some(d) = &file.detail {
        if !(2..=super::detail::MAX_DETAIL_RES).contains(&d.res) {
            return bad(format!("detail resolution {} is outside 2..={}", d.res, super::detail::MAX_DETAIL_RES));
        }
        check_texture_size(&texture_path(dir, json, &d.texture)?, (d.res, d.res), "the detail needs")?;
    }
    Ok(())
}

/// The texture at `path` is `want` (width, height) by its header; `what` ("its factor
/// needs") says why, in the error.
fn check_texture_size(path: &Path, want: (usize, usize), what: &str) -> Result<()> {
    let got = crate::images::header_size(path)?;
    if got != want {
        return Err(Error::format(path, format!("texture is {}x{} but {what} {}x{}", got.0, got.1, want.0, want.1)));
    }
    Ok(())
}

/// Whether a file name is one the tool writes for a term's table or coefficients:
/// `term{k}-factor{j}-{input}.exr`, `term{k}-coefficients.exr`, or the detail's.
fn is_texture_name(name: &str) -> bool {
    if name == DETAIL_TEXTURE {
        return true;
    }
    let Some((k, rest)) = name.strip_prefix("term").and_then(|r| r.split_once('-')) else { return false };
    let number = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let table = rest.strip_prefix("factor").and_then(|r| r.split_once('-')).is_some_and(|(j, input)| {
        number(j) && input.strip_suffix(".exr").is_some_and(|i| !i.is_empty() && i.bytes().all(|b| b.is_ascii_lowercase() || b == b'-'))
    });
    number(k) && (table || rest == "coefficients.exr")
}

/// Checks that a material may be written at `dir`, and returns what a directory without an
/// ownership record may have replaced besides material.json and report.png: the textures the
/// old material.json names, where they have the names the tool gives its textures (so a
/// crafted material.json cannot claim a user's file). Files, links and directories of other
/// things are refused.
fn check_target(dir: &Path) -> Result<Legacy> {
    let mut ours = BTreeSet::new();
    let refuse = || {
        Err(Error::input(format!(
            "{} exists and is not a material directory; not overwriting it",
            dir.display()
        )))
    };
    let meta = match std::fs::symlink_metadata(dir) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Legacy::Paths(ours)),
        Err(e) => return Err(Error::io(dir, e)),
    };
    if !meta.is_dir() {
        return refuse();
    }
    if crate::commit::output_dir_is_fresh(dir)? {
        return Ok(Legacy::Paths(ours));
    }
    let json = dir.join("material.json");
    if !std::fs::symlink_metadata(&json).is_ok_and(|m| m.is_file()) {
        return refuse();
    }
    if let Ok(text) = crate::fsio::read_regular(&json, MAX_JSON_BYTES) {
        if let Ok(file) = serde_json::from_slice::<FileMaterial>(&text) {
            for t in file.terms {
                let names = t.factors.into_iter().map(|f| f.texture).chain(t.coefficients.map(|c| c.texture));
                ours.extend(names.filter(|n| is_texture_name(n)));
            }
            ours.extend(file.detail.map(|d| d.texture).filter(|n| is_texture_name(n)));
        }
    }
    Ok(Legacy::Paths(ours))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_names_are_the_tools_own_pattern_only() {
        for ours in ["term0-factor0-l.exr", "term12-factor3-half-difference.exr", "term1-coefficients.exr"] {
            assert!(is_texture_name(ours), "{ours}");
        }
        for theirs in ["term1-sketches.exr", "notes.txt", "term-factor0-l.exr", "term0-factor0-.exr", "term0-factor0-l.png", "term0-factor0-../x.exr", "paintings"] {
            assert!(!is_texture_name(theirs), "{theirs}");
        }
    }
}
