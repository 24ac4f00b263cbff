//! Photographs with a normal map on the command line: `fit --normals N (--image P --light
//! L ... | --photos DIR)` and `render MAT --normals N --light L` (the same view re-rendered,
//! to compare). The reading is [`brdfpaint::sample::photoset`]'s; the fit is the
//! pipeline's, as for paintings.

use std::path::{Path, PathBuf};

use clap::ValueEnum;
use glam::DVec3;

use super::Failure;
use brdfpaint::brdf::Reflectance;
use brdfpaint::error::{Error, Result};
use brdfpaint::images::{check_size, Painting};
use brdfpaint::material::Material;
use brdfpaint::note::Note;
use brdfpaint::sample::photoset::{self, Shot};
use brdfpaint::sample::{Encoding, Erosion, MapFrame, NormalMap, Photo, PhotoCamera, PhotoFolder, PhotoInput, PhotoLight};

/// How PNG and JPEG photographs are encoded.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(super) enum EncodingArg {
    Srgb,
    Linear,
}

impl EncodingArg {
    fn encoding(self) -> Encoding {
        match self {
            EncodingArg::Srgb => Encoding::Srgb,
            EncodingArg::Linear => Encoding::Linear,
        }
    }
}

/// The normal map and how the photographs over it were taken.
#[derive(clap::Args)]
pub(super) struct MapArgs {
    /// A normal map of the photographs' pixels: PNG (n = 2c - 1 of the raw codes, no sRGB
    /// curve), EXR (x, y, z as stored) or text (one x y z line per pixel, row by row).
    /// View space (x right, y up, z toward the camera) unless --camera-dir is given.
    /// Background: alpha 0 or all channels 0, or outside --mask.
    #[arg(long, value_name = "N.png|N.exr")]
    pub normals: Option<PathBuf>,
    /// With --normals: white where the object is; other pixels are not samples.
    #[arg(long, value_name = "M.png")]
    pub mask: Option<PathBuf>,
    /// With --normals: a perspective camera of this vertical field of view in degrees
    /// (each pixel seen through its centre). Default: orthographic, as photometric-stereo
    /// sets assume.
    #[arg(long, value_name = "DEG")]
    pub fov: Option<f64>,
    /// With --normals: the map (and the lights) are in world space, and the camera looks
    /// from this direction (X,Y,Z toward the camera, in the map's frame).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_direction, allow_hyphen_values = true)]
    pub camera_dir: Option<DVec3>,
    /// With --camera-dir: the image's up in the map's frame (default 0,1,0).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_direction, allow_hyphen_values = true, requires = "camera_dir")]
    pub camera_up: Option<DVec3>,
    /// How PNG and JPEG photographs are encoded: srgb or linear. Default: what a PNG
    /// declares (an sRGB or gAMA chunk), else linear in a --photos folder (sensor values, as
    /// photometric-stereo sets store them) and sRGB for --image (DESIGN.md). For render, the
    /// PNG written (default sRGB).
    #[arg(long, value_enum)]
    pub encoding: Option<EncodingArg>,
}

/// A light of a photograph, `X,Y,Z` toward it, then optionally its colour × intensity `R,G,B`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LightArg {
    pub direction: DVec3,
    pub rgb: Option<[f64; 3]>,
}

/// `X,Y,Z` or `X,Y,Z,R,G,B`.
pub(super) fn parse_light(text: &str) -> std::result::Result<LightArg, String> {
    let bad = || format!("'{text}' is not a light X,Y,Z or X,Y,Z,R,G,B (e.g. -0.5,0.5,1 or 0,0,1,1,0.9,0.8)");
    let v: Vec<f64> = text.split(',').map(|p| p.trim().parse::<f64>()).collect::<std::result::Result<_, _>>().map_err(|_| bad())?;
    if v.iter().any(|x| !x.is_finite()) {
        return Err(bad());
    }
    let direction = DVec3::new(v[0], *v.get(1).ok_or_else(bad)?, *v.get(2).ok_or_else(bad)?);
    if direction == DVec3::ZERO {
        return Err(format!("'{text}': the direction 0,0,0 points nowhere"));
    }
    match v.len() {
        3 => Ok(LightArg { direction, rgb: None }),
        6 if v[3..].iter().all(|&c| c > 0.0) => Ok(LightArg { direction, rgb: Some([v[3], v[4], v[5]]) }),
        6 => Err(format!("'{text}': the colour R,G,B needs every channel above 0 (it is divided out)")),
        _ => Err(bad()),
    }
}

/// `X,Y,Z`, not zero.
fn parse_direction(text: &str) -> std::result::Result<DVec3, String> {
    match parse_light(text) {
        Ok(LightArg { direction, rgb: None }) => Ok(direction),
        _ => Err(format!("'{text}' is not a direction X,Y,Z (e.g. 0,0,1)")),
    }
}

impl MapArgs {
    /// The camera: orthographic unless --fov.
    fn camera(&self) -> std::result::Result<PhotoCamera, Failure> {
        match self.fov {
            None => Ok(PhotoCamera::Orthographic),
            Some(deg) if deg > 0.0 && deg < 180.0 => Ok(PhotoCamera::Perspective { yfov: deg.to_radians() }),
            Some(deg) => Err(Failure::Usage(format!("--fov {deg}: give a vertical field of view between 0 and 180 degrees"))),
        }
    }

    /// View space unless --camera-dir.
    fn frame(&self) -> MapFrame {
        match self.camera_dir {
            None => MapFrame::View,
            Some(toward_camera) => MapFrame::World { toward_camera, up: self.camera_up.unwrap_or(DVec3::Y) },
        }
    }

    /// The flags that only photographs use, given without --normals or --photos.
    pub(super) fn stray_flag(&self) -> Option<&'static str> {
        [(self.mask.is_some(), "--mask"), (self.fov.is_some(), "--fov"), (self.camera_dir.is_some(), "--camera-dir"), (self.encoding.is_some(), "--encoding")]
            .iter()
            .find(|(given, _)| *given)
            .map(|(_, flag)| *flag)
    }
}

/// What `fit` reads: a folder, or --image/--light pairs over --normals.
pub(super) fn input(map: &MapArgs, photos: Option<&Path>, images: &[PathBuf], lights: &[LightArg]) -> std::result::Result<PhotoInput, Failure> {
    let (camera, frame) = (map.camera()?, map.frame());
    let mut input = match photos {
        Some(dir) => {
            let folder = PhotoFolder::open(dir)?;
            if !folder.intensities {
                println!("note: {}: no {}: every light taken as white (1 1 1)", dir.display(), photoset::INTENSITIES);
            }
            PhotoInput::of_folder(dir, folder, map.normals.clone(), map.mask.clone(), camera, frame)?
        }
        None => {
            if images.len() != lights.len() || images.is_empty() {
                return Err(Failure::Usage(format!(
                    "{} --image and {} --light: give one --light X,Y,Z[,R,G,B] with each photograph --image, or a folder with --photos",
                    images.len(),
                    lights.len()
                )));
            }
            let shots = images.iter().zip(lights).map(|(image, l)| Shot { image: image.clone(), light: PhotoLight { direction: l.direction.normalize(), rgb: l.rgb.unwrap_or([1.0; 3]) } });
            let normals = map.normals.clone().expect("--normals is given without --photos");
            PhotoInput { normals, mask: map.mask.clone(), camera, frame, shots: shots.collect(), encoding: None, default_encoding: Encoding::Srgb }
        }
    };
    input.encoding = map.encoding.map(EncodingArg::encoding);
    Ok(input)
}

/// Reads the photographs as views for the fit, printing what was read and left out; their
/// notes, and the files to keep in the output folder.
pub(super) fn load(input: &PhotoInput, erosion: Erosion) -> Result<(Vec<brdfpaint::sample::PaintedView>, Vec<Note>)> {
    let read = input.load(erosion)?;
    for note in &read.notes {
        super::fit::say(note);
    }
    Ok((read.views, read.notes))
}

/// `render MAT --normals N --light L`: the material over the normal map, per pixel at its
/// centre, times the light (no GL: the same shading the fit was judged with). Where the light
/// does not reach ($n \cdot l \le 0$) the pixel is black, as in a photograph: photographs
/// have no samples there. Background alpha 0.
pub(super) fn render(material_path: &Path, map: &MapArgs, light: Option<&str>, size: Option<&str>, scale: f32, out: &Path) -> std::result::Result<(), Failure> {
    let light = light.ok_or_else(|| Failure::Usage("--normals needs --light X,Y,Z[,R,G,B]: the light to render under".into()))?;
    let light = parse_light(light).map_err(|e| Failure::Usage(format!("--light {e}")))?;
    let exr = match out.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("png") => false,
        Some("exr") => true,
        _ => return Err(Error::input(format!("{}: the output must be a .png or .exr file", out.display())).into()),
    };
    let material = Material::load(material_path)?;
    let mask = map.mask.as_ref().map(|m| Painting::read(m).map(|p| (p, m.display().to_string()))).transpose()?;
    let normals_path = map.normals.as_ref().expect("render with --normals");
    let normals = NormalMap::read_masked(normals_path, None, mask.as_ref().map(|(p, n)| (p, n.as_str())))?;
    let (w, h) = (normals.width, normals.height);
    if let Some(size) = size {
        if super::render::parse_size(size)? != (w, h) {
            return Err(Failure::Usage(format!("--size {size}: a render over a normal map has the map's size, {w}x{h} (leave --size out)")));
        }
    }
    check_size(w, h)?;
    let photo = Photo::new(normals, map.camera()?, map.frame())?;
    let light = PhotoLight { direction: light.direction.normalize(), rgb: light.rgb.unwrap_or([1.0; 3]) };
    let geometry = photo.geometry(&light, Erosion::NONE)?;
    let mut image = Painting::opaque(w, h, vec![[0.0; 3]; w * h])?;
    for (k, px) in geometry.pixels.iter().enumerate() {
        image.alpha[k] = if photo.normals.normals[k].is_some() { 1.0 } else { 0.0 };
        let Some(px) = px.filter(|p| p.query.l.z > 0.0) else { continue };
        let s = material.shading(&px.query);
        let mut value = [0, 1, 2].map(|c| s[c] * light.rgb[c]);
        // The painting's detail, at the normal in view space (the map's frame turned back).
        if let (Some(detail), Some(n)) = (&material.detail, photo.normals.normals[k]) {
            let view = photo.camera_to_frame.transpose() * n;
            value = detail.apply(value, glam::DVec2::new(view.x, view.y));
        }
        image.pixels[k] = value.map(|v| v as f32 * scale);
    }
    let encoding = map.encoding.map_or(Encoding::Srgb, EncodingArg::encoding);
    match (exr, encoding) {
        (true, _) => image.write(out)?,
        (false, Encoding::Srgb) => image.write(out)?,
        (false, Encoding::Linear) => write_linear_png(&image, out)?,
    }
    let clipped = image.pixels.iter().filter(|p| p.iter().any(|&c| c > 1.0)).count();
    let what = if exr { "linear float" } else { encoding.name() };
    println!(
        "rendered {} over {} under light ({:.3}, {:.3}, {:.3}) at {w}x{h} ({what}{}): {}",
        material_path.display(),
        normals_path.display(),
        light.direction.x,
        light.direction.y,
        light.direction.z,
        if clipped > 0 && !exr { format!(", {clipped} pixels clipped at white") } else { String::new() },
        out.display()
    );
    Ok(())
}

/// A 16-bit PNG of linear codes (value × 65535), with alpha, written atomically.
fn write_linear_png(image: &Painting, path: &Path) -> Result<()> {
    let mut raw = Vec::with_capacity(image.pixels.len() * 4);
    for (p, &a) in image.pixels.iter().zip(&image.alpha) {
        raw.extend(p.iter().map(|&x| (x.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16));
        raw.push(if a > 0.0 { u16::MAX } else { 0 });
    }
    let img = image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(image.width as u32, image.height as u32, raw)
        .ok_or_else(|| Error::format(path, "pixel buffer does not match the image size"))?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png).map_err(|e| Error::format(path, e.to_string()))?;
    brdfpaint::commit::write_atomic(path, bytes.get_ref())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lights_parse_with_and_without_colour() {
        assert_eq!(parse_light("0,0,1").unwrap(), LightArg { direction: DVec3::Z, rgb: None });
        assert_eq!(parse_light("-1, 2,3,1,0.5,2").unwrap().rgb, Some([1.0, 0.5, 2.0]));
        for bad in ["0,0", "0,0,1,1", "0,0,1,1,1", "a,b,c", "0,0,0", "0,0,1,1,0,1", "0,0,1,1,1,1,1", "nan,0,1", ""] {
            assert!(parse_light(bad).is_err(), "{bad}");
        }
        assert!(parse_direction("0,0,1,1,1,1").is_err());
    }
}
