//! Helpers shared by the GL integration tests: analytic sphere scenes and an independent CPU
//! evaluation of factored shading functions through `brdfpaint::factor`.
#![allow(dead_code)]

use brdfpaint::factor::{system, table, Domain, FactorSpec, Input, Param, Query};
use brdfpaint::material::{Coefficients, Factor, Kind, Material, Term};
use brdfpaint::render::{mesh::uv_sphere, GpuScene, Renderer};
use brdfpaint::scene::{Camera, Light, Projection, Scene};
use glam::{DVec3, Mat4, Vec3, Vec4};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Sphere tessellation used by the tests: fine enough that the polygon's silhouette is
/// within 0.01 px of the circle at the image sizes used (r (1 - cos(pi/256)) = 7.5e-5 r).
pub const SEGMENTS: usize = 256;
pub const RINGS: usize = 128;

/// The tolerance of [`compare_gl`] on a hardware GL driver. GPU texture units blend texels
/// with fixed-point weights (8 fractional bits on current hardware), so where a table
/// changes fast between nodes the filtered value is up to a few 1e-3 off the exact
/// interpolation the CPU does: measured on an NVIDIA H200 through EGL (November 2026), at
/// most 3.0e-3 relative for 1D tables (at grazing pixels of the silhouette), 6.2e-3 for the
/// 2D tables of random factors and 1.05e-2 for a fitted 2D material, whose sharp highlight
/// changes fastest between nodes. Filtering in the shader in float (four texel fetches per
/// lookup) would remove it; not done, since it is about two 8-bit display steps at most.
/// Mesa's llvmpipe, which CI runs, filters in float, and the tests' own tolerances hold there.
pub const HARDWARE_FILTER_TOL: f64 = 2e-2;

/// Whether `r` renders on a software rasterizer (llvmpipe, softpipe).
pub fn is_software(r: &Renderer) -> bool {
    use glow::HasContext;
    // SAFETY: a plain string query on the renderer's current context.
    let name = unsafe { r.gl().get_parameter_string(glow::RENDERER) }.to_ascii_lowercase();
    name.contains("llvmpipe") || name.contains("softpipe")
}

/// Camera basis of `src/brdf/sphere.rs`: right, up, back (toward the camera).
pub fn basis(back: DVec3) -> (DVec3, DVec3, DVec3) {
    let back = back.normalize();
    let helper = if back.y.abs() > 0.999 { DVec3::Z } else { DVec3::Y };
    let right = helper.cross(back).normalize();
    (right, back.cross(right), back)
}

/// world_from_camera for a camera at `eye` looking at the origin with the basis above.
pub fn looking_at_origin(eye: DVec3) -> Mat4 {
    let (r, u, b) = basis(eye);
    let f = |v: DVec3, w: f32| Vec4::new(v.x as f32, v.y as f32, v.z as f32, w);
    Mat4::from_cols(f(r, 0.0), f(u, 0.0), f(b, 0.0), f(eye, 1.0))
}

/// The unit sphere seen orthographically from direction `camera` with the view volume of
/// `brdf::SphereView` (ymag = 1, so the sphere just fills a square image).
pub fn ortho_sphere(camera: DVec3, light: Light) -> Scene {
    Scene {
        meshes: vec![uv_sphere(Vec3::ZERO, 1.0, SEGMENTS, RINGS)],
        camera: Camera {
            world_from_camera: looking_at_origin(camera.normalize() * 3.0),
            projection: Projection::Orthographic { xmag: 1.0, ymag: 1.0, znear: 0.5, zfar: 10.0 },
        },
        light,
    }
}

/// The unit sphere seen in perspective from `eye`.
pub fn perspective_sphere(eye: DVec3, yfov: f32, light: Light) -> Scene {
    Scene {
        meshes: vec![uv_sphere(Vec3::ZERO, 1.0, SEGMENTS, RINGS)],
        camera: Camera {
            world_from_camera: looking_at_origin(eye),
            projection: Projection::Perspective { yfov, aspect: None, znear: 0.1, zfar: Some(100.0) },
        },
        light,
    }
}

/// A white directional light arriving from direction `toward` (pointing at the light).
pub fn sun(toward: DVec3, rgb: [f32; 3]) -> Light {
    let t = toward.normalize();
    Light::Directional {
        direction: -Vec3::new(t.x as f32, t.y as f32, t.z as f32),
        color: Vec3::from_array(rgb),
        intensity: 1.0,
    }
}

/// The analytic pixel-centre geometry of an orthographic `res`² view of the unit sphere
/// (as `brdf::SphereView`): `Some(world normal)` where the centre ray hits.
pub fn sphere_normal(camera: DVec3, res: usize, i: usize, j: usize) -> Option<DVec3> {
    let (right, up, back) = basis(camera);
    let x = 2.0 * (i as f64 + 0.5) / res as f64 - 1.0;
    let y = 1.0 - 2.0 * (j as f64 + 0.5) / res as f64;
    let rr = x * x + y * y;
    (rr < 1.0).then(|| right * x + up * y + back * (1.0 - rr).sqrt())
}

pub fn spec(input: Input, param: Param, domain: Domain, res: usize) -> FactorSpec {
    FactorSpec { input, param, domain, res, smooth: 0.0, damp: 0.0, ridge: 0.0, warp: 1.0, lean: 1.0 }
}

/// A table of independent random values in [0.3, 1.3] per node and channel: the hardest
/// case for interpolation agreement.
pub fn random_factor(spec: FactorSpec, seed: u64) -> Factor {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let texels = (0..spec.len()).map(|_| [0; 3].map(|_| rng.random_range(0.3f32..1.3))).collect();
    Factor { spec, texels }
}

/// A smooth table, $0.7 + 0.3 \cos(2 t_x + c) \cos(1.5 t_y + c)$ per channel $c$.
pub fn smooth_factor(spec: FactorSpec) -> Factor {
    let m = spec.res;
    let dim = spec.dim();
    let texels = (0..spec.len())
        .map(|k| {
            let tx = (k % m) as f64 / (m - 1) as f64;
            let ty = if dim == 2 { (k / m) as f64 / (m - 1) as f64 } else { 0.0 };
            [0, 1, 2].map(|c| (0.7 + 0.3 * (2.0 * tx + c as f64).cos() * (1.5 * ty + c as f64).cos()) as f32)
        })
        .collect();
    Factor { spec, texels }
}

/// A one-term material without coefficients.
pub fn uniform(term: Term) -> Material {
    Material::new(Kind::Uniform, vec![term])
}

/// A material map of `terms`.
pub fn map_of(terms: Vec<Term>) -> Material {
    Material::new(Kind::MaterialMap, terms)
}

/// Bilinear node-based lookup of a coefficient texture (independent of the renderer).
pub fn coef_lookup(c: &Coefficients, uv: [f64; 2]) -> [f64; 3] {
    let axis = |t: f64, n: usize| -> (usize, usize, f64) {
        if n == 1 {
            return (0, 0, 0.0);
        }
        let x = t.clamp(0.0, 1.0) * (n - 1) as f64;
        let i = (x.floor() as usize).min(n - 2);
        (i, i + 1, x - i as f64)
    };
    let (x0, x1, fx) = axis(uv[0], c.res);
    let (y0, y1, fy) = axis(uv[1], c.res);
    let at = |x: usize, y: usize| c.texels[y * c.res + x].map(|v| v as f64);
    let (a, b, cc, d) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
    [0, 1, 2]
        .map(|k| (1.0 - fx) * (1.0 - fy) * a[k] + fx * (1.0 - fy) * b[k] + (1.0 - fx) * fy * cc[k] + fx * fy * d[k])
}

/// $S(q)$ of a shading function on the CPU, in f64, through `brdfpaint::factor`: table
/// coordinates from `system::coordinate`, linear/bilinear lookups from `table`, the
/// mapping's `inverse`, the coefficient texture bilinearly, the term's analytic base
/// (`brdf::lobe::Base::shading`).
pub fn cpu_shading(shading: &Material, q: &Query) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for term in &shading.terms {
        let mut prod = [1.0f64; 3];
        for f in &term.factors {
            let t = system::coordinate(&f.spec, q);
            let table: Vec<[f64; 3]> = f.texels.iter().map(|x| x.map(|v| v as f64)).collect();
            let value = if f.spec.dim() == 1 {
                table::lookup_1d(&table, t[0])
            } else {
                table::lookup_2d(&table, f.spec.res, t)
            };
            for c in 0..3 {
                prod[c] *= value[c];
            }
        }
        let coef = term.coefficients.as_ref().map_or([1.0; 3], |c| coef_lookup(c, [q.uv.x, q.uv.y]));
        // The term's analytic base (issue 15), f64 on the CPU.
        let base = term.base.map_or([1.0; 3], |b| b.shading(q));
        for c in 0..3 {
            // The renderer clamps every mapping at zero; LogMap::inverse clamps offset and
            // inverted, and identity products are positive.
            sum[c] += term.map.inverse(c, prod[c]).max(0.0) * coef[c] * base[c];
        }
    }
    sum
}

/// Renders `shading` on `scene` at `w` × `h` with the factored shader, and its G-buffer; every
/// covered pixel must be opaque and match `expected` at the G-buffer's query (l, v, uv) times
/// the light's colour × intensity and, for a point light, 1/d² from the G-buffer's world
/// position, within `tol` relative to max(|expected|, 1); every other pixel must be
/// (0, 0, 0, 0). `what` names the expectation in messages. Returns the worst relative error
/// and the number of pixels compared. On a hardware driver the tolerance is at least
/// [`HARDWARE_FILTER_TOL`].
#[allow(clippy::too_many_arguments)]
pub fn compare_gl(
    r: &mut Renderer,
    scene: &Scene,
    shading: &Material,
    w: usize,
    h: usize,
    tol: f64,
    what: &str,
    expected: impl Fn(&Query) -> [f64; 3],
) -> (f64, usize) {
    let tol = if is_software(r) { tol } else { tol.max(HARDWARE_FILTER_TOL) };
    let gpu = GpuScene::upload(r.gl(), scene).unwrap();
    let image = r.factored(&gpu, &r.upload(shading).unwrap(), w, h).unwrap();
    let g = r.gbuffer(&gpu, w, h).unwrap();
    let (rgb, light_at) = match scene.light {
        Light::Directional { color, intensity, .. } => (color * intensity, None),
        Light::Point { position, color, intensity } => (color * intensity, Some(position)),
    };
    let (mut worst, mut n) = (0.0f64, 0usize);
    for j in 0..h {
        for i in 0..w {
            let px = g.at(i, j);
            let got = image.at(i, j);
            let Some(q) = px.query() else {
                assert_eq!(got, [0.0; 4], "background at ({i}, {j})");
                continue;
            };
            assert_eq!(got[3], 1.0, "coverage alpha at ({i}, {j})");
            // glTF point lights: 1/d² from the surface point to the light.
            let falloff = light_at.map_or(1.0, |p| 1.0 / (p - px.position).as_dvec3().length_squared());
            let s = expected(&q);
            let want = [0, 1, 2].map(|c| s[c] * rgb[c] as f64 * falloff);
            let scale = want.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            let e = rel_err(got, want, scale);
            assert!(
                e < tol,
                "pixel ({i}, {j}): GL {got:?} vs {what} {want:?} (rel {e:.2e}); l {:?} v {:?} uv {:?}",
                q.l,
                q.v,
                q.uv
            );
            worst = worst.max(e);
            n += 1;
        }
    }
    (worst, n)
}

/// Largest error of `got` against `want` relative to `scale`, over channels.
pub fn rel_err(got: [f32; 4], want: [f64; 3], scale: f64) -> f64 {
    (0..3).map(|c| (got[c] as f64 - want[c]).abs() / scale).fold(0.0, f64::max)
}

/// Query at a G-buffer pixel, with Input::Custom excluded (not renderable).
pub fn uses_custom(spec: &FactorSpec) -> bool {
    matches!(spec.input, Input::Custom(_))
}
