//! Helpers shared by the `sheet` and `render` command tests: running the binary, a fitted
//! material, a scene file, a folder's listing.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

use brdfpaint::brdf::{Analytic, Reflectance, SphereView};
use brdfpaint::factor::{prepare, Mapping, Settings};
use brdfpaint::material::{Material, Provenance};
use brdfpaint::scene::{self, Camera, Light, Projection, Scene};
use glam::DVec3;

use crate::gl_common::looking_at_origin;

pub fn brdfpaint(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_brdfpaint"))
        .args(args)
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .output()
        .expect("run brdfpaint");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

pub fn ok(args: &[&str]) -> String {
    let (code, stdout, stderr) = brdfpaint(args);
    assert_eq!(code, 0, "{args:?}: {stderr}");
    stdout
}

pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Every file under `dir`, hidden ones included, sorted.
pub fn listing(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(listing(&p));
        }
        out.push(p);
    }
    out.sort();
    out
}

/// A material fitted to Blinn-Phong painted on one sphere view (three 1D factors).
pub fn fitted_material(dir: &Path) -> (PathBuf, Material) {
    let model = Analytic::BlinnPhong { diffuse: [0.45, 0.25, 0.12], specular: [0.3, 0.35, 0.4], exponent: 16.0 };
    let pattern = SphereView::new(DVec3::new(-0.5, 0.5, 1.0), 64).pattern();
    let settings = Settings::uniform(1, 64);
    let fit =
        prepare(&pattern, &settings).unwrap().solve(&pattern.shade(|q| model.shading(q)), Mapping::Auto).unwrap();
    let material = Material::from_fit(&settings, &fit, Provenance::default()).unwrap();
    let path = dir.join("mat");
    material.save(&path).unwrap();
    (path, material)
}

/// A scene file: one mesh, a perspective camera at `eye` looking at the origin, a light.
pub fn write_scene(path: &Path, mesh: scene::CpuMesh, eye: DVec3, aspect: Option<f32>, light: Light) -> Scene {
    let scene = Scene {
        meshes: vec![mesh],
        camera: Camera {
            world_from_camera: looking_at_origin(eye),
            projection: Projection::Perspective { yfov: 0.7, aspect, znear: 0.1, zfar: Some(50.0) },
        },
        light,
    };
    scene.write_gltf(path).unwrap();
    scene
}
