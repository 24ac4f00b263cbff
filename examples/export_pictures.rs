//! The pictures of README's "Out into other tools": each material beside the glTF PBR
//! material `export --gltf` writes for it, on a sphere under the light and view its paintings
//! had, with their difference; and a lit-sphere picture beside its MatCaps under its own light
//! and turned to others (`export --matcap`).
//!
//! ```sh
//! brdfpaint demo --out demo
//! cargo run --release --example export_pictures -- gltf demo docs/export/pbr.png
//! cargo run --release --example export_pictures -- matcap docs/export/matcap.png \
//!     assets/paintings/gold-paint.png ../shared/data/matcaps/blender_cc0/exr/clay_brown.exr
//! ```
//!
//! The sphere is shaded on the CPU from the two `Reflectance`s (the factored material and
//! the PBR one), seen along the camera's axis, its texture coordinates those of the built-in
//! sphere model (`scene::preset::sphere_mesh`) about the camera's axes.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use brdfpaint::brdf::Reflectance;
use brdfpaint::export::coverage::Directions;
use brdfpaint::export::{pbr_fit, pbr_map, picture_light};
use brdfpaint::factor::Query;
use brdfpaint::images::text::Label;
use brdfpaint::images::Rgb;
use brdfpaint::material::Material;
use glam::{DVec2, DVec3};

/// Each sphere's side, pixels.
const SIDE: usize = 200;
/// The demo's physical materials.
const MATERIALS: [&str; 4] = ["gold-paint", "purple-paint", "plastic", "lacquered-wood"];
/// Behind the spheres: a dark grey, so an unlit side keeps its outline.
const BACKDROP: [f32; 3] = [0.03, 0.03, 0.03];
/// The difference is drawn this many times brighter.
const DIFFERENCE_GAIN: f32 = 4.0;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
        ["gltf", demo, out] => gltf(Path::new(demo), Path::new(out)),
        ["matcap", out, pictures @ ..] if !pictures.is_empty() => matcap(pictures, Path::new(out)),
        _ => {
            eprintln!("usage: export_pictures gltf DEMO_DIR OUT.png | matcap OUT.png PICTURE...");
            std::process::exit(2);
        }
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn gltf(demo: &Path, out: &Path) -> brdfpaint::error::Result<()> {
    let label = Label::new(2);
    let header = label.height() + 4;
    let mut sheet = Rgb::new(3 * SIDE, header + MATERIALS.len() * (SIDE + header))?;
    sheet.pixels.fill(BACKDROP);
    for (col, title) in ["factored", "glTF PBR", &format!("difference x{DIFFERENCE_GAIN}")].iter().enumerate() {
        label.draw(&mut sheet, col * SIDE + 2, 2, title);
    }
    for (row, name) in MATERIALS.iter().enumerate() {
        let path: PathBuf = demo.join("materials").join(name);
        let material = Material::load(&path)?;
        let covered = Directions::covered(&path, &material);
        let all = Directions::all();
        let (pbr, error): (Box<dyn Reflectance>, f64) = if material.needs_uv() {
            let t = pbr_map::fit(&material, covered.as_ref(), &all, pbr_map::resolution(&material));
            (Box::new(t.map), t.covered)
        } else {
            let a = pbr_fit::fit(&material, covered.as_ref(), &all);
            (Box::new(a.pbr), a.covered)
        };
        let light = picture_light(&path, &material).unwrap_or(DVec3::new(-0.5, 0.5, 0.7).normalize());
        let y0 = header + row * (SIDE + header);
        let factored = sphere(&material, light);
        let approximated = sphere(pbr.as_ref(), light);
        let difference: Vec<[f32; 3]> =
            factored.iter().zip(&approximated).map(|(a, b)| [0, 1, 2].map(|c| (a[c] - b[c]).abs() * DIFFERENCE_GAIN)).collect();
        for (col, pixels) in [factored, approximated, difference].iter().enumerate() {
            blit(&mut sheet, pixels, col * SIDE, y0 + header);
        }
        label.draw(&mut sheet, 2, y0 + 2, &format!("{name}: relative RMS {error:.3}"));
        println!("{name}: relative RMS {error:.4} over the covered directions");
    }
    sheet.write_png(out)
}

/// `brdf` on a unit sphere seen along $-z$ (orthographic), lit from `light`, a unit white
/// light: the shading of each pixel, [`BACKDROP`] off the sphere.
fn sphere(brdf: &dyn Reflectance, light: DVec3) -> Vec<[f32; 3]> {
    let mut out = vec![BACKDROP; SIDE * SIDE];
    for j in 0..SIDE {
        for i in 0..SIDE {
            let x = 2.0 * (i as f64 + 0.5) / SIDE as f64 - 1.0;
            let y = 1.0 - 2.0 * (j as f64 + 0.5) / SIDE as f64;
            let rr = x * x + y * y;
            if rr >= 1.0 {
                continue;
            }
            let n = DVec3::new(x, y, (1.0 - rr).sqrt());
            // The built-in sphere's parametrization: θ from +y, φ about y from -z.
            let (theta, phi) = (n.y.clamp(-1.0, 1.0).acos(), n.x.atan2(n.z));
            let uv = DVec2::new((phi + PI) / (2.0 * PI), theta / PI);
            let t = DVec3::new(phi.cos(), 0.0, -phi.sin());
            let b = n.cross(t);
            let local = |d: DVec3| DVec3::new(d.dot(t), d.dot(b), d.dot(n));
            let q = Query { l: local(light), v: local(DVec3::Z), uv };
            out[j * SIDE + i] = brdf.shading(&q).map(|s| s as f32);
        }
    }
    out
}

/// Each picture, its MatCap under the light the fit found, and MatCaps under that light
/// mirrored left to right and under a rim light from behind: a row each.
fn matcap(pictures: &[&str], out: &Path) -> brdfpaint::error::Result<()> {
    let label = Label::new(2);
    let header = label.height() + 4;
    let mut sheet = Rgb::new(4 * SIDE, header + pictures.len() * SIDE)?;
    sheet.pixels.fill(BACKDROP);
    for (k, name) in ["picture", "its light", "mirrored", "rim, behind"].iter().enumerate() {
        label.draw(&mut sheet, k * SIDE + 2, 2, name);
    }
    for (row, picture) in pictures.iter().enumerate() {
        matcap_row(Path::new(picture), &mut sheet, header + row * SIDE)?;
    }
    sheet.write_png(out)
}

fn matcap_row(picture: &Path, sheet: &mut Rgb, y0: usize) -> brdfpaint::error::Result<()> {
    use brdfpaint::export::matcap::{render, Lighting};
    use brdfpaint::litsphere::{fit_in, Ask};
    let lit = fit_in(picture, &Ask::default(), &Default::default(), None)?;
    let l = lit.light;
    let lights = [l, DVec3::new(-l.x, l.y, l.z), DVec3::new(0.8, 0.3, -0.5).normalize()];
    let painting = brdfpaint::images::Painting::read(picture)?;
    blit(sheet, &resized(&painting.pixels, painting.width, painting.height), 0, y0);
    for (k, light) in lights.iter().enumerate() {
        let m = render(&lit.fitted.material, SIDE, &Lighting::Light(*light));
        let pixels: Vec<[f32; 3]> = m.total.iter().zip(&m.mask).map(|(p, &on)| if on { *p } else { BACKDROP }).collect();
        blit(sheet, &pixels, (k + 1) * SIDE, y0);
    }
    println!("{}: light ({:.2}, {:.2}, {:.2})", picture.display(), l.x, l.y, l.z);
    Ok(())
}

/// `pixels` of `w` × `h` box-filtered to [`SIDE`]².
fn resized(pixels: &[[f32; 3]], w: usize, h: usize) -> Vec<[f32; 3]> {
    let mut out = vec![[0.0; 3]; SIDE * SIDE];
    for j in 0..SIDE {
        for i in 0..SIDE {
            let (x0, x1) = (i * w / SIDE, ((i + 1) * w / SIDE).max(i * w / SIDE + 1));
            let (y0, y1) = (j * h / SIDE, ((j + 1) * h / SIDE).max(j * h / SIDE + 1));
            let mut sum = [0.0; 3];
            for y in y0..y1 {
                for x in x0..x1 {
                    for c in 0..3 {
                        sum[c] += pixels[y * w + x][c];
                    }
                }
            }
            let n = ((x1 - x0) * (y1 - y0)) as f32;
            out[j * SIDE + i] = sum.map(|v| v / n);
        }
    }
    out
}

fn blit(sheet: &mut Rgb, pixels: &[[f32; 3]], x0: usize, y0: usize) {
    for j in 0..SIDE {
        for i in 0..SIDE {
            sheet.pixels[(y0 + j) * sheet.width + x0 + i] = pixels[j * SIDE + i];
        }
    }
}
