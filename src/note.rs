//! What the library tells a user about a fit, one line each. Notes are typed: the command
//! line adds the option that changes what a note describes ([`Note::remedy`]), the viewer,
//! which has no options, shows the line alone, and a material's provenance keeps the line.
//!
//! Loaders deep below a fit (a scene read by a renderer) have no list to return notes in:
//! they [`tell`] the handler a program installs ([`set_handler`]); without one they are
//! dropped.

use std::fmt;
use std::sync::OnceLock;

use crate::error::one_line;

static HANDLER: OnceLock<fn(&Note)> = OnceLock::new();

/// Sends every note told later to `handler` (once per process; a second call is ignored).
pub fn set_handler(handler: fn(&Note)) {
    let _ = HANDLER.set(handler);
}

/// Passes `note` to the handler, if any.
pub(crate) fn tell(note: Note) {
    if let Some(handler) = HANDLER.get() {
        handler(&note);
    }
}

/// One thing worth telling the user.
#[derive(Clone, Debug, PartialEq)]
pub enum Note {
    /// A painting made on the sheet's page lost the page's own pixels.
    Page { painting: String, lines: usize, white: usize },
    /// How many of a view's pixels are samples, and why the others are not.
    Samples { painting: String, samples: usize, object: usize, silhouette: usize, unpainted: usize, strays: usize },
    /// A painting in flat tones, read as the smooth shading they suggest.
    FlatTones { painting: String, levels: [usize; 3] },
    /// A view's light turned to where the painting looks lit from: by the fit's relative
    /// RMS, or by how far its tones' edges are missed (`by_tones`).
    LightTurned { painting: String, degrees: f64, before: f64, after: f64, by_tones: bool },
    /// Stray strokes, repainted with the shading around them or left out.
    Strays { painting: String, pixels: usize, left_out: bool },
    /// A toned painting read through the lobe family that holds its tones best.
    TonesLobe { painting: String, lobe: &'static str, width: String },
    /// Paintings lit from the eye: the shading's falloff given to the light.
    Headlit,
    /// A lobe whose Fresnel the paintings cannot show (light and half vector at most
    /// `reach_deg` apart): given a dielectric's (`dielectric`) or none.
    FresnelUnseen { reach_deg: f64, lobe: &'static str, dielectric: bool },
    /// A factor of θ_d added for paintings under side or back light.
    DifferenceFactor { lo_deg: f64, hi_deg: f64 },
    /// The error of a uniform fit organized by region: not one material.
    Regional { percent: f64, rms: f64 },
    /// A normal map of which a share (`percent`) faces away from the camera: read in the
    /// wrong frame, or (`camera_given`) given a camera direction that is not the camera's.
    FacingAway { map: String, percent: f64, camera_given: bool },
    /// How many photographs were read with each encoding of their codes.
    Encodings { linear: usize, srgb: usize, float: usize },
    /// How many of the photographs' object pixels are samples, and why the others are not.
    PhotoSamples { images: usize, object: usize, kept: usize, saturated: usize, unlit: usize, dark: usize },
    /// Where a lit sphere's disk is (pixels of the file: centre, radius), the share of its
    /// outline the picture shows there (`seen`, 0 to 1), and where it came `from`.
    Disk { picture: String, cx: f64, cy: f64, r: f64, seen: f64, from: DiskFrom },
    /// Pixels of a lit sphere's disk beyond a straight edge across it that continues past the
    /// outline: something in front of the sphere, left out (`share` of the disk, 0 to 1).
    InFront { picture: String, pixels: usize, share: f64 },
    /// A lit sphere's light that the picture cannot decide: directions up to `spread_deg`
    /// from the one chosen explain its shading as well, and the plausible key light among
    /// them (upper front) was taken.
    LightUndecided { picture: String, spread_deg: f64 },
    /// A lit sphere whose light is behind it: most of the picture shows the side the light
    /// does not reach, and a light moved to the front shows more than the picture does.
    LightBehind { picture: String },
    /// A lit sphere read physically or as drawn (`decided`: by `--style auto`, from its
    /// `tones` flat tones holding `share` of the disk; `painted`: those of its shading
    /// profile along the light, where strokes and grain scatter its pixels').
    Style { picture: String, stylized: bool, decided: bool, tones: usize, share: f64, painted: bool },
    /// A material fitted with coupled channels (and the identity mapping when `identity`):
    /// fitted channel by channel with the mapping of least error, a share `before` of a
    /// sphere's lit pixels took colours the paintings do not have under a moved light; now
    /// `after`.
    KeptColours { identity: bool, before: f64, after: f64 },
    /// A scene with several cameras or lights (`what`), of which the first (`used`) is used.
    FirstOfMany { scene: String, what: &'static str, count: usize, used: String },
}

/// Where a lit sphere's disk came from ([`Note::Disk`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiskFrom {
    /// Found on a clear outline: the picture's alpha, background or edges.
    Found,
    /// Found on a faint arc of the edges, the best of none clear: to be checked.
    Faint,
    /// Given by the user.
    Given,
}

/// What a user can do about a note; the command line names the option.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Remedy {
    /// Fit flat tones as painted.
    KeepTones,
    /// Fit with the scene's light as given.
    KeepLight,
    /// Fit stray strokes as painted.
    KeepStrokes,
    /// Change the silhouette band left out.
    Erode,
    /// Add a view painted under a side light.
    SecondView,
    /// Leave the θ_d factor out.
    NoDifferenceFactor,
    /// Fit a material map.
    MaterialMap,
    /// Give the direction toward the camera in the normal map's frame.
    CameraDirection,
    /// Say how the photographs' codes are encoded.
    Encoding,
    /// Give the lit sphere's disk.
    GiveDisk,
    /// Give the lit sphere's light.
    GiveLight,
    /// Choose how a lit sphere is read, physical or stylized.
    Style,
    /// Choose the colour channels' fit or the log mapping.
    Colours,
}

impl Note {
    /// The option that changes what the note describes, if there is one.
    pub fn remedy(&self) -> Option<Remedy> {
        match self {
            Note::Samples { .. } => Some(Remedy::Erode),
            Note::FlatTones { .. } => Some(Remedy::KeepTones),
            Note::LightTurned { .. } => Some(Remedy::KeepLight),
            Note::Strays { .. } => Some(Remedy::KeepStrokes),
            Note::Headlit => Some(Remedy::SecondView),
            Note::DifferenceFactor { .. } => Some(Remedy::NoDifferenceFactor),
            Note::Regional { .. } => Some(Remedy::MaterialMap),
            Note::FacingAway { camera_given: false, .. } => Some(Remedy::CameraDirection),
            Note::Encodings { .. } => Some(Remedy::Encoding),
            Note::Disk { from: DiskFrom::Found | DiskFrom::Faint, .. } => Some(Remedy::GiveDisk),
            Note::LightUndecided { .. } | Note::LightBehind { .. } => Some(Remedy::GiveLight),
            Note::Style { decided: true, .. } => Some(Remedy::Style),
            Note::KeptColours { .. } => Some(Remedy::Colours),
            Note::Style { decided: false, .. } => None,
            Note::Page { .. }
            | Note::TonesLobe { .. }
            | Note::FresnelUnseen { .. }
            | Note::FirstOfMany { .. }
            | Note::FacingAway { camera_given: true, .. }
            | Note::PhotoSamples { .. }
            | Note::InFront { .. }
            | Note::Disk { from: DiskFrom::Given, .. } => None,
        }
    }

    /// Whether the note warns that the fit is likely wrong (rather than says what was done).
    pub fn is_warning(&self) -> bool {
        matches!(self, Note::Regional { .. })
    }
}

impl fmt::Display for Note {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Note::Page { painting, lines, white } => write!(
                f,
                "{painting} was made on the sheet's page: left out {lines} pixel(s) of its lines and {white} of untouched (or clipped) white"
            ),
            Note::Samples { painting, samples, object, silhouette, unpainted, strays } => {
                let strays = if *strays > 0 { format!("; {strays} left out as stray strokes") } else { String::new() };
                write!(f, "{painting}: {samples} samples of the {object} pixels that see the object ({silhouette} in the silhouette band; {unpainted} unpainted{strays})")
            }
            Note::FlatTones { painting, levels: [r, g, b] } => {
                write!(f, "{painting}: painted in flat tones ({r}, {g} and {b} levels in R, G, B): read as the smooth shading they suggest")
            }
            Note::LightTurned { painting, degrees, before, after, by_tones: true } => write!(
                f,
                "{painting}: the painting's tones look lit {degrees:.0}° away from the scene's light (their edges missed by {before:.3} → {after:.3} with the light turned); fitted with the painting's light"
            ),
            Note::LightTurned { painting, degrees, before, after, by_tones: false } => write!(
                f,
                "{painting}: the painting looks lit {degrees:.0}° away from the scene's light (relative RMS {before:.3} → {after:.3} with the light turned); fitted with the painting's light"
            ),
            Note::Strays { painting, pixels, left_out } => {
                let done = if *left_out { "left out, and the painting read again without them" } else { "repainted with the shading around them" };
                write!(f, "{painting}: {pixels} painted pixels read as stray strokes (the fit misses them far more than the rest) and {done}")
            }
            Note::TonesLobe { painting, lobe, width } => {
                let width = if width.is_empty() { String::new() } else { format!(" ({width})") };
                write!(f, "{painting}: its tones are held best by the {lobe} lobe{width}: read through it")
            }
            Note::Headlit => f.write_str(
                "the paintings are lit from the eye: they show each point under one angle between light, view and normal, so the shading's falloff was given to the light (as cos θ_l) where they leave it open; a second view painted under a side light shows how the material answers a moving light",
            ),
            Note::FresnelUnseen { reach_deg, lobe, dielectric: true } => write!(
                f,
                "the paintings show light and half vector at most {reach_deg:.0}° apart, too close to see Fresnel: the {lobe} highlight, colourless over a diffuse body, was given a dielectric's (F0 0.04, as plastic, paint and glaze), so under light from the side or behind it grows brighter; a view painted under side or back light shows by how much"
            ),
            Note::FresnelUnseen { reach_deg, lobe, dielectric: false } => write!(
                f,
                "the paintings show light and half vector at most {reach_deg:.0}° apart, too close to see Fresnel: the {lobe} highlight was given none, so under light from the side or behind it stays as bright as head-on where a real glossy material grows brighter; a view painted under side or back light shows by how much"
            ),
            Note::DifferenceFactor { lo_deg, hi_deg } => write!(
                f,
                "the paintings show side or back light: the angle between light and half vector goes from {lo_deg:.0}° to {hi_deg:.0}°, so a factor s(θ_d) was added for Fresnel and grazing terms"
            ),
            Note::Regional { percent, rms } => write!(
                f,
                "warning: this does not look like one uniform material: {percent:.0}% of the error is organized by region on the surface (relative RMS {rms:.2}); a material map fits one, best with a second view (thesis 4.2, 4.4)"
            ),
            Note::FacingAway { map, percent, camera_given } => {
                let why = if *camera_given {
                    "so the direction toward the camera given is probably not the camera's"
                } else {
                    "as in a world-space map read as view space (a world-space map needs the direction toward the camera in its frame)"
                };
                write!(f, "{}: {percent:.0}% of the normals face away from the camera, {why}", one_line(map))
            }
            Note::Encodings { linear, srgb, float } => {
                let parts: Vec<String> = [(*linear, "linear (codes over their largest value)"), (*srgb, "sRGB-encoded"), (*float, "linear float (EXR)")]
                    .iter()
                    .filter(|(n, _)| *n > 0)
                    .map(|(n, what)| format!("{n} read as {what}"))
                    .collect();
                write!(f, "photographs: {}", parts.join(", "))
            }
            Note::PhotoSamples { images, object, kept, saturated, unlit, dark } => write!(
                f,
                "{images} photograph{}: {kept} of {object} object pixels are samples; left out {saturated} saturated (a channel at the file's largest code) and {} in shadow ({unlit} facing away from the light, {dark} near black)",
                if *images == 1 { "" } else { "s" },
                unlit + dark
            ),
            Note::Disk { picture, cx, cy, r, seen, from: DiskFrom::Found } => {
                write!(f, "{}: disk at ({cx:.1}, {cy:.1}), radius {r:.1}, from {:.0}% of its outline", one_line(picture), 100.0 * seen)
            }
            Note::Disk { picture, cx, cy, r, seen, from: DiskFrom::Faint } => write!(
                f,
                "{}: disk at ({cx:.1}, {cy:.1}), radius {r:.1}, from a faint arc, {:.0}% of its outline (no clearer one): check that it is the sphere",
                one_line(picture),
                100.0 * seen
            ),
            Note::Disk { picture, cx, cy, r, seen, from: DiskFrom::Given } => write!(
                f,
                "{}: disk at ({cx:.1}, {cy:.1}), radius {r:.1}, as given; the picture shows {:.0}% of that outline",
                one_line(picture),
                100.0 * seen
            ),
            Note::InFront { picture, pixels, share } => write!(
                f,
                "{}: {pixels} pixels of the disk ({:.0}%) lie beyond a straight edge that crosses it and runs on past its outline, something in front of the sphere: they are not samples",
                one_line(picture),
                100.0 * share
            ),
            Note::LightUndecided { picture, spread_deg } => write!(
                f,
                "{}: the shading does not decide the light (lit by its surroundings: directions up to {spread_deg:.0}° apart explain it as well); took the plausible key light among them, the one nearest the upper front",
                one_line(picture)
            ),
            Note::LightBehind { picture } => write!(
                f,
                "{}: lit from behind the sphere: the light reaches only the crescent turned to it, and the rest, lit by its surroundings, sets how light the material stays where no light reaches; lit from the front, the material shows more than the picture does",
                one_line(picture)
            ),
            Note::Style { picture, stylized: true, tones, share, painted: false, .. } => write!(
                f,
                "{}: read as drawn (stylized): {tones} flat tones hold {:.0}% of the disk; its tone edges set the light, and the fit keeps them hard",
                one_line(picture),
                100.0 * share
            ),
            Note::Style { picture, stylized: true, tones, share, painted: true, .. } => write!(
                f,
                "{}: read as drawn (stylized): {tones} flat tones, painted (strokes and grain inside them), hold {:.0}% of the disk's shading along the light; its tone edges set the light, and the fit keeps them hard",
                one_line(picture),
                100.0 * share
            ),
            Note::Style { picture, stylized: false, tones, share, .. } => write!(
                f,
                "{}: read as physical shading: its values spread (its {tones} most common tones hold {:.0}% of the disk; a drawing in flat tones, 90% or more)",
                one_line(picture),
                100.0 * share
            ),
            Note::FirstOfMany { scene, what, count, used } => {
                write!(f, "{} has {count} {what}; {} is used (the first in node order), the others are ignored", one_line(scene), one_line(used))
            }
            Note::KeptColours { identity, before, after } => write!(
                f,
                "colours fitted together{}: fitted one channel at a time, {:.0}% of a sphere's lit pixels took colours the paintings do not have under a moved light; now {:.0}%",
                if *identity { ", with the identity mapping" } else { "" },
                100.0 * before,
                100.0 * after
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every note is one line, names no option, and the ones a user can act on have a remedy.
    #[test]
    fn notes_are_one_line_and_name_no_option() {
        let notes = [
            Note::Page { painting: "p.png".into(), lines: 3, white: 4 },
            Note::Samples { painting: "p.png".into(), samples: 10, object: 12, silhouette: 1, unpainted: 1, strays: 0 },
            Note::FlatTones { painting: "p.png".into(), levels: [4, 4, 5] },
            Note::LightTurned { painting: "p.png".into(), degrees: 8.0, before: 0.1, after: 0.05, by_tones: false },
            Note::Strays { painting: "p.png".into(), pixels: 40, left_out: true },
            Note::TonesLobe { painting: "p.png".into(), lobe: "ggx", width: "alpha 0.04".into() },
            Note::Headlit,
            Note::FresnelUnseen { reach_deg: 30.0, lobe: "ggx", dielectric: false },
            Note::FresnelUnseen { reach_deg: 30.0, lobe: "ggx", dielectric: true },
            Note::DifferenceFactor { lo_deg: 5.0, hi_deg: 70.0 },
            Note::Regional { percent: 60.0, rms: 0.2 },
            Note::FirstOfMany { scene: "s.gltf".into(), what: "cameras", count: 2, used: "front\nback".into() },
            Note::FacingAway { map: "n.png".into(), percent: 40.0, camera_given: false },
            Note::Encodings { linear: 2, srgb: 0, float: 1 },
            Note::PhotoSamples { images: 3, object: 100, kept: 80, saturated: 5, unlit: 10, dark: 5 },
            Note::Disk { picture: "s.jpg".into(), cx: 100.0, cy: 90.5, r: 60.0, seen: 0.78, from: DiskFrom::Found },
            Note::Disk { picture: "s.jpg".into(), cx: 100.0, cy: 90.5, r: 60.0, seen: 0.42, from: DiskFrom::Faint },
            Note::Disk { picture: "s.jpg".into(), cx: 100.0, cy: 90.5, r: 60.0, seen: 0.78, from: DiskFrom::Given },
            Note::InFront { picture: "s.jpg".into(), pixels: 1200, share: 0.09 },
            Note::LightUndecided { picture: "m.exr".into(), spread_deg: 40.0 },
            Note::LightBehind { picture: "m.exr".into() },
            Note::Style { picture: "toon.png".into(), stylized: true, decided: true, tones: 3, share: 0.97, painted: false },
            Note::Style { picture: "toon.jpg".into(), stylized: true, decided: true, tones: 2, share: 0.96, painted: true },
            Note::Style { picture: "clay.png".into(), stylized: false, decided: false, tones: 1, share: 0.2, painted: false },
            Note::KeptColours { identity: true, before: 0.2, after: 0.0 },
        ];
        for note in &notes {
            let line = note.to_string();
            assert!(!line.contains('\n') && !line.contains("--"), "{line}");
        }
        assert_eq!(notes.iter().filter(|n| n.remedy().is_some()).count(), 16);
    }
}
