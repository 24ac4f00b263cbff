//! Photographs held out by light (issue 37): a photometric-stereo folder
//! ([`crate::sample::photoset`]) of one object under a dozen calibrated lights is fitted on
//! a few of them as `brdfpaint fit --photos DIR` fits it, and judged on the others by
//! [`super::rendered_error`]: relative RMS over each held-out photograph's usable pixels
//! (unsaturated, lit, not near black, off the eroded silhouette), the median over them.
//!
//! `cargo run --release --example photo_study` prints the table for the Mitsuba sets
//! `tools/mitsuba/render_photos.py` makes.

use std::path::Path;
use std::time::Instant;

use super::{median, rendered_error};
use crate::error::{Error, Result};
use crate::read::lobe::BaseChoice;
use crate::material::{Kind, Material};
use crate::pipeline::{self, Options};
use crate::sample::{Erosion, MapFrame, PhotoCamera, PhotoFolder, PhotoInput};

/// The lights fitted, by their index in the folder; the rest are held out. With the
/// generator's twelve lights (three rings of polar angle 20°, 40° and 60°, 30° apart in
/// azimuth), one of each ring, 120° apart.
pub const FIT_LIGHTS: [usize; 3] = [0, 4, 8];

/// The photographs of `input` at `indices`, in that order.
pub fn subset(input: &PhotoInput, indices: &[usize]) -> Result<PhotoInput> {
    let shots = indices
        .iter()
        .map(|&k| input.shots.get(k).cloned().ok_or_else(|| Error::input(format!("there is no photograph {k} of {}", input.shots.len()))))
        .collect::<Result<Vec<_>>>()?;
    Ok(PhotoInput { shots, ..input.clone() })
}

/// The photographs of `input` not at `indices`.
pub fn others(input: &PhotoInput, indices: &[usize]) -> PhotoInput {
    let shots = input.shots.iter().enumerate().filter(|(k, _)| !indices.contains(k)).map(|(_, s)| s.clone()).collect();
    PhotoInput { shots, ..input.clone() }
}

/// One folder's fit and its judgment.
#[derive(Clone, Debug)]
pub struct Row {
    /// Relative RMS on the fitted samples.
    pub train: f64,
    /// Relative RMS on each held-out photograph.
    pub views: Vec<f64>,
    /// The analytic base kept, if any.
    pub base: Option<String>,
    /// Seconds to read the fitted photographs, and to fit them (prepare, solve, base).
    pub load_s: f64,
    pub fit_s: f64,
    /// Samples fitted.
    pub samples: usize,
}

impl Row {
    /// The median over the held-out photographs.
    pub fn median(&self) -> f64 {
        median(&self.views)
    }
}

/// `material` against each photograph of `held_out`, read as a fit reads them.
pub fn judge(material: &Material, held_out: &PhotoInput) -> Result<Vec<f64>> {
    let read = held_out.load(Erosion::default())?;
    rendered_error(material, &read.views)
}

/// Fits the folder `dir` (orthographic camera, view-space normals) on [`FIT_LIGHTS`] with
/// `base` and the fit's other defaults, without the prepare cache, and judges it on the
/// other photographs.
pub fn measure(dir: &Path, base: BaseChoice) -> Result<Row> {
    let input = PhotoInput::of_folder(dir, PhotoFolder::open(dir)?, None, None, PhotoCamera::Orthographic, MapFrame::View)?;
    let start = Instant::now();
    let read = subset(&input, &FIT_LIGHTS)?.load(Erosion::default())?;
    let load_s = start.elapsed().as_secs_f64();
    let opts = Options { base, ..Options::new(Kind::Uniform, 1, None, None, None)? };
    let start = Instant::now();
    let fitted = pipeline::fit(&read.views, &opts, None)?;
    let fit_s = start.elapsed().as_secs_f64();
    let views = judge(&fitted.material, &others(&input, &FIT_LIGHTS))?;
    let base = fitted.material.terms.first().and_then(|t| t.base).map(|b| b.lobe.name().to_string());
    Ok(Row { train: fitted.errors().rms_relative, views, base, load_s, fit_s, samples: fitted.samples.len() })
}
