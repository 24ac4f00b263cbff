//! Photographs for a fit: one image per directional light over a normal map
//! ([`super::photo`]), given pair by pair or as a folder in the layout photometric-stereo
//! data sets use (DiLiGenT's):
//!
//! - `filenames.txt`: the images, one name a line, inside the folder;
//! - `light_directions.txt`: one `x y z` line per image, toward the light, in the normal
//!   map's frame (view space: x right, y up, z toward the camera);
//! - `light_intensities.txt`: one `r g b` line per image, the light's colour × intensity,
//!   divided out of the image (without the file: white, 1 1 1);
//! - `mask.png` (optional): white where the object is;
//! - the normal map, the first of `normal.exr`, `normal.txt` (one `x y z` line per pixel,
//!   row by row), `normal.png`, `Normal_gt.png`.
//!
//! Numbers are separated by spaces, tabs or commas; blank lines and lines that start with
//! `#` are skipped. A set's PNGs are linear unless they declare otherwise (its sensor
//! values: [`Encoding::Linear`]); photographs given one by one follow DESIGN.md (sRGB).

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::photo::{read_photograph, Encoding, LeftOut, MapFrame, NormalMap, Photo, PhotoCamera, PhotoLight};
use super::{Erosion, PaintedView};
use crate::error::{Error, Result};
use crate::fsio::{read_regular, resolve_inside};
use crate::images::Painting;
use crate::note::Note;

/// Largest text file read (a 4096² `normal.txt` is about 400 MiB; 2048² about 100).
const MAX_TEXT_BYTES: u64 = 512 << 20;

/// The folder's files (module docs).
pub const FILENAMES: &str = "filenames.txt";
pub const DIRECTIONS: &str = "light_directions.txt";
pub const INTENSITIES: &str = "light_intensities.txt";
pub const MASK: &str = "mask.png";
pub const NORMAL_MAPS: [&str; 4] = ["normal.exr", "normal.txt", "normal.png", "Normal_gt.png"];

/// One line of three numbers, with its line number (from 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triple {
    pub line: usize,
    pub values: [f64; 3],
}

/// The non-blank, non-comment lines of a text file, with their numbers (from 1).
pub fn read_lines(path: &Path) -> Result<Vec<(usize, String)>> {
    let bytes = read_regular(path, MAX_TEXT_BYTES)?;
    let text = String::from_utf8(bytes).map_err(|_| Error::format(path, "not a text file (invalid UTF-8)"))?;
    Ok(text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
        .map(|(k, l)| (k, l.to_string()))
        .collect())
}

/// Every line of `path` as three finite numbers (`what` names them in errors: "x y z").
pub fn read_triples(path: &Path, what: &str) -> Result<Vec<Triple>> {
    read_lines(path)?
        .into_iter()
        .map(|(line, text)| {
            let parts: Vec<&str> = text.split(|c: char| c.is_whitespace() || c == ',').filter(|p| !p.is_empty()).collect();
            let values: Vec<f64> = parts.iter().filter_map(|p| p.parse().ok()).filter(|x: &f64| x.is_finite()).collect();
            match (parts.len(), <[f64; 3]>::try_from(values)) {
                (3, Ok(values)) => Ok(Triple { line, values }),
                _ => Err(Error::format(path, format!("line {line}: '{text}' is not three numbers {what}"))),
            }
        })
        .collect()
}

/// One photograph and the light it was taken under.
#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    pub image: PathBuf,
    pub light: PhotoLight,
}

/// A folder in the photometric-stereo layout (module docs), its files found and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotoFolder {
    pub shots: Vec<Shot>,
    pub mask: Option<PathBuf>,
    /// The first normal map found ([`NORMAL_MAPS`]).
    pub normals: Option<PathBuf>,
    /// Whether the intensities came from [`INTENSITIES`] (else white).
    pub intensities: bool,
}

impl PhotoFolder {
    /// Reads the folder's lists; every image named must exist inside it.
    pub fn open(dir: &Path) -> Result<PhotoFolder> {
        if !dir.is_dir() {
            return Err(Error::format(dir, "is not a folder of photographs"));
        }
        let list = dir.join(FILENAMES);
        if !list.is_file() {
            return Err(Error::format(dir, format!("no {FILENAMES}: a photometric-stereo folder names its images there, one a line")));
        }
        let names = read_lines(&list)?;
        if names.is_empty() {
            return Err(Error::format(&list, "names no image"));
        }
        let images = names
            .iter()
            .map(|(line, name)| resolve_inside(dir, name).map_err(|r| Error::format(&list, format!("line {line}: {r}"))))
            .collect::<Result<Vec<_>>>()?;
        let directions = counted(&dir.join(DIRECTIONS), "x y z", images.len())?;
        let intensities_path = dir.join(INTENSITIES);
        let intensities = intensities_path.exists();
        let rgb = match intensities {
            true => counted(&intensities_path, "r g b", images.len())?,
            false => directions.iter().map(|d| Triple { values: [1.0; 3], ..*d }).collect(),
        };
        let shots = images
            .into_iter()
            .zip(directions.iter().zip(&rgb))
            .map(|(image, (d, c))| {
                let light = light(d.values, c.values).map_err(|why| match why {
                    Bad::Direction => Error::format(dir.join(DIRECTIONS), format!("line {}: {}", d.line, why.text(d.values))),
                    Bad::Colour => Error::format(&intensities_path, format!("line {}: {}", c.line, why.text(c.values))),
                })?;
                Ok(Shot { image, light })
            })
            .collect::<Result<Vec<_>>>()?;
        let mask = Some(dir.join(MASK)).filter(|p| p.exists());
        let normals = NORMAL_MAPS.iter().map(|n| dir.join(n)).find(|p| p.exists());
        Ok(PhotoFolder { shots, mask, normals, intensities })
    }
}

/// The triples of `path`, one per image: too few or too many lines is an error.
fn counted(path: &Path, what: &str, images: usize) -> Result<Vec<Triple>> {
    let rows = read_triples(path, what)?;
    if rows.len() != images {
        return Err(Error::format(path, format!("{} lines of {what} for the {images} images {FILENAMES} names: one line per image", rows.len())));
    }
    Ok(rows)
}

/// Why a light cannot be used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bad {
    Direction,
    Colour,
}

impl Bad {
    /// The reason, with the numbers given.
    pub fn text(self, v: [f64; 3]) -> String {
        let [a, b, c] = v;
        match self {
            Bad::Direction => format!("{a} {b} {c} is not a direction (zero length)"),
            Bad::Colour => format!("intensity {a} {b} {c} has a zero or negative channel, which cannot be divided out"),
        }
    }
}

/// A light toward `direction` (normalized) of colour × intensity `rgb`.
pub fn light(direction: [f64; 3], rgb: [f64; 3]) -> std::result::Result<PhotoLight, Bad> {
    let d = DVec3::from_array(direction);
    let len = d.length();
    if !(len.is_finite() && len > 1e-9) {
        return Err(Bad::Direction);
    }
    if rgb.iter().any(|&c| !(c > 0.0 && c.is_finite())) {
        return Err(Bad::Colour);
    }
    Ok(PhotoLight { direction: d / len, rgb })
}

/// What a fit of photographs reads: a normal map, an optional mask, the camera, and the
/// photographs with their lights.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotoInput {
    pub normals: PathBuf,
    pub mask: Option<PathBuf>,
    pub camera: PhotoCamera,
    pub frame: MapFrame,
    pub shots: Vec<Shot>,
    /// Every PNG or JPEG decoded so; else as it declares, else `default_encoding`.
    pub encoding: Option<Encoding>,
    pub default_encoding: Encoding,
}

/// Photographs read for a fit.
pub struct Photographs {
    pub photo: Photo,
    pub views: Vec<PaintedView>,
    /// The pixels left out, over all photographs.
    pub left_out: LeftOut,
    /// One line each: how the photographs were read and what was left out.
    pub notes: Vec<Note>,
    /// Whether a view-space map looks like a world-space one ([`Photo::facing_away`]).
    pub world_space_suspected: bool,
}

/// Above this share of normals facing away from the camera a view-space map is noted as
/// probably world space ([`Photo::facing_away`]).
const AWAY_SHARE: f64 = 0.1;

impl PhotoInput {
    /// The input of a [`PhotoFolder`]: its normal map unless `normals` is given, its mask
    /// unless `mask` is.
    pub fn of_folder(dir: &Path, folder: PhotoFolder, normals: Option<PathBuf>, mask: Option<PathBuf>, camera: PhotoCamera, frame: MapFrame) -> Result<PhotoInput> {
        let normals = normals.or(folder.normals).ok_or_else(|| {
            Error::format(dir, format!("no normal map: none of {} is there, and none was given", NORMAL_MAPS.join(", ")))
        })?;
        let mask = mask.or(folder.mask);
        Ok(PhotoInput { normals, mask, camera, frame, shots: folder.shots, encoding: None, default_encoding: Encoding::Linear })
    }

    /// The files read: normal map, mask, photographs.
    pub fn files(&self) -> Vec<&Path> {
        let shots = self.shots.iter().map(|s| s.image.as_path());
        std::iter::once(self.normals.as_path()).chain(self.mask.as_deref()).chain(shots).collect()
    }

    /// Reads the photographs, the mask and the normal map (a text map takes the
    /// photographs' size), and each photograph as a view without its unreadable pixels
    /// ([`Photo::photograph`]).
    pub fn load(&self, erosion: Erosion) -> Result<Photographs> {
        if self.shots.is_empty() {
            return Err(Error::input("no photographs to fit"));
        }
        let images = self
            .shots
            .iter()
            .map(|s| read_photograph(&s.image, self.encoding, self.default_encoding))
            .collect::<Result<Vec<_>>>()?;
        let mask = self.mask.as_ref().map(|m| Painting::read(m).map(|p| (p, m.display().to_string()))).transpose()?;
        let size = (images[0].0.width, images[0].0.height);
        let normals = NormalMap::read_masked(&self.normals, Some(size), mask.as_ref().map(|(p, n)| (p, n.as_str())))?;
        let photo = Photo::new(normals, self.camera, self.frame)?;
        let mut notes = Vec::new();
        let away = photo.facing_away();
        let world_space_suspected = away > AWAY_SHARE;
        if world_space_suspected {
            let camera_given = matches!(self.frame, MapFrame::World { .. });
            notes.push(Note::FacingAway { map: photo.normals.name.clone(), percent: 100.0 * away, camera_given });
        }
        notes.push(encodings(&images));
        let (mut views, mut left_out) = (Vec::new(), LeftOut::default());
        for (shot, (image, encoding)) in self.shots.iter().zip(images) {
            // A float file has no white of its own: its largest value stands in.
            let white = match encoding {
                Some(_) => 1.0,
                None => image.pixels.iter().flatten().copied().fold(0.0, f32::max),
            };
            let (view, left) = photo.photograph(&shot.light, image, white, &shot.image.display().to_string(), erosion)?;
            left_out.add(&left);
            views.push(view);
        }
        notes.push(left_out.note(views.len()));
        Ok(Photographs { photo, views, left_out, notes, world_space_suspected })
    }
}

/// One line on how the photographs were decoded.
fn encodings(images: &[(Painting, Option<Encoding>)]) -> Note {
    let count = |e: Option<Encoding>| images.iter().filter(|(_, x)| *x == e).count();
    Note::Encodings { linear: count(Some(Encoding::Linear)), srgb: count(Some(Encoding::Srgb)), float: count(None) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triples_read_spaces_commas_and_comments_and_name_bad_lines() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("l.txt");
        std::fs::write(&path, "# lights\n0 0 1\n\n0.5,0.5, 1\n1\t2\t3\n").unwrap();
        let rows = read_triples(&path, "x y z").unwrap();
        assert_eq!(rows.iter().map(|r| r.line).collect::<Vec<_>>(), [2, 4, 5]);
        assert_eq!(rows[1].values, [0.5, 0.5, 1.0]);
        for bad in ["0 0\n", "0 0 1 2\n", "a b c\n", "1 nan 2\n", "1 inf 2\n"] {
            std::fs::write(&path, format!("0 0 1\n{bad}")).unwrap();
            let e = read_triples(&path, "x y z").unwrap_err().to_string();
            assert!(e.contains("l.txt: line 2:") && e.contains("not three numbers x y z"), "{bad}: {e}");
        }
    }

    #[test]
    fn text_normal_maps_go_row_by_row_at_the_photographs_size() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("normal.txt");
        std::fs::write(&path, "0 0 1\n0 0 0\n0.6 0 0.8\n0 0 1.2\n").unwrap();
        let map = NormalMap::read_masked(&path, Some((2, 2)), None).unwrap();
        assert_eq!(map.normals, vec![Some(DVec3::Z), None, Some(DVec3::new(0.6, 0.0, 0.8)), Some(DVec3::Z)]);
        let e = NormalMap::read_masked(&path, Some((3, 2)), None).unwrap_err().to_string();
        assert!(e.contains("normal.txt") && e.contains("4 normals for 3x2 images"), "{e}");
        std::fs::write(&path, "0 0 1\n0 0 0\n0.6 0 0.8\n0 0 2\n").unwrap();
        let e = NormalMap::read_masked(&path, Some((2, 2)), None).unwrap_err().to_string();
        assert!(e.contains("pixel (1, 1)") && e.contains("length 2.000"), "{e}");
    }

    #[test]
    fn lights_refuse_zero_directions_and_dark_channels() {
        assert_eq!(light([0.0; 3], [1.0; 3]), Err(Bad::Direction));
        assert_eq!(light([0.0, 0.0, 2.0], [1.0, 0.0, 1.0]), Err(Bad::Colour));
        let l = light([0.0, 3.0, 4.0], [1.0, 2.0, 3.0]).unwrap();
        assert!((l.direction - DVec3::new(0.0, 0.6, 0.8)).length() < 1e-12);
    }
}
