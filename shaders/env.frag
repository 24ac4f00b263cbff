// One term of a factored material under an HDR environment, plus the key light:
//
//   $L_o(v) = c(uv) \big[ \int_{H^2} f(l, v, uv)\, L_{env}(l)\, d\omega_l
//             + f(l_key, v, uv)\, E_{key} \big]$
//
// where f is term.glsl's mapped product and $H^2$ the hemisphere above the shading normal.
// S = BRDF x cos(theta_l) already, so above the horizon the environment is a sum of
// directional lights with the same S a key light sees (a material lit by one small bright
// spot looks as under a point light there). Below the horizon the surface itself hides the
// environment: what a painting shows on its unlit side (a Gooch blue) is how the artist
// painted the absence of the key light, and adding it from every direction below the
// horizon would wash every painted material out to a flat tint.
//
// Estimator. Multi-sample importance sampling with the balance heuristic (Veach 1997,
// sec. 9.2): ENV_SAMPLES fixed directions in four strategies, n_k of strategy k, each
// weighted by $1 / \sum_k n_k p_k(l)$:
//   uniform over the hemisphere (ENV_UNIFORM; the guarantee that the mixture density is
//     positive over the whole domain, grazing directions included, so the estimator is
//     unbiased and bounded where S does not vanish at the horizon);
//   cosine around the normal (ENV_COSINE; diffuse terms);
//   Phong lobes $\cos^k$ around the mirror direction of v, k = LOBE_WIDE and LOBE_NARROW
//     (ENV_WIDE, ENV_NARROW; glossy terms, roughly GGX alpha 0.4 and 0.16 by $\alpha = \sqrt{2/(k+2)}$; sharper
//     painted highlights are still found, at more cost in error). A lobe
//     sample below the horizon adds nothing but still counts in the mixture, as the
//     balance heuristic needs.
// The directions are a Hammersley set per strategy, the same at every pixel: the error is
// a smooth bias, not noise, and a still image never flickers.
//
// Filtered importance sampling (Colbert and Krivanek, GPU Gems 3 ch. 20, eq. 20-7/20-8):
// each sample reads the mip-mapped environment averaged over the solid angle it stands
// for, $\Omega_s = 1/\sum_k n_k p_k(l)$, at
//   $\mathrm{lod} = \max(\tfrac12 \log_2(\Omega_s / \Omega_p), 0)$,
// $\Omega_p$ a level-0 texel's solid angle (env.glsl). Without the paper's +1 bias: with
// the pattern fixed per pixel it only blurred (the highlight of a bright source lost 15%
// against the Monte-Carlo reference), and aliasing shows as no noise here. Small bright sources (the
// sun) are spread over the sample's footprint instead of becoming fireflies; the price is
// a blur of the environment by about that footprint, which is what the tests' tolerance
// measures (tests/env_render.rs).

uniform float u_key;  // 1 adds the key light (the scene's light), 0 leaves the environment alone

layout(location = 0) out vec4 o_color;

const float LOBE_WIDE = 10.0;
const float LOBE_NARROW = 80.0;

// Van der Corput radical inverse in base 2, without bitfieldReverse (GLSL 4.00).
float radical_inverse(uint i) {
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
    i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
    i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
    return float(i) * 2.3283064365386963e-10;
}

// Point i of an n-point Hammersley set, the first coordinate stratified at (i + 1/2)/n.
vec2 hammersley(int i, int n) {
    return vec2((float(i) + 0.5) / float(n), radical_inverse(uint(i)));
}

vec3 uniform_hemisphere(vec2 xi) {
    float z = xi.x;
    float r = sqrt(max(1.0 - z * z, 0.0));
    float phi = 2.0 * ENV_PI * xi.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Malley's method: uniform on the disc, lifted; density $\cos\theta / \pi$.
vec3 cosine_hemisphere(vec2 xi) {
    float r = sqrt(xi.x);
    float phi = 2.0 * ENV_PI * xi.y;
    return vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0 - xi.x, 0.0)));
}

// $\cos^k$ lobe around the unit axis a: $\cos\alpha = \xi^{1/(k+1)}$, density
// $(k+1)/(2\pi) \cos^k\alpha$.
vec3 phong_lobe(vec2 xi, vec3 a, float k) {
    float c = pow(xi.x, 1.0 / (k + 1.0));
    float s = sqrt(max(1.0 - c * c, 0.0));
    float phi = 2.0 * ENV_PI * xi.y;
    // Any frame around a (Duff et al. 2017, "Building an orthonormal basis, revisited").
    float sign_z = a.z >= 0.0 ? 1.0 : -1.0;
    float p = -1.0 / (sign_z + a.z);
    float q = a.x * a.y * p;
    vec3 b1 = vec3(1.0 + sign_z * a.x * a.x * p, sign_z * q, -sign_z * a.x);
    vec3 b2 = vec3(q, sign_z + a.y * a.y * p, -a.y);
    return normalize(s * cos(phi) * b1 + s * sin(phi) * b2 + c * a);
}

// The balance heuristic's denominator $\sum_k n_k p_k(l)$ (r: mirror direction).
float mixture_density(vec3 l, vec3 r) {
    float c = max(l.z, 0.0);
    float a = max(dot(l, r), 0.0);
    return float(ENV_UNIFORM) / (2.0 * ENV_PI)
        + float(ENV_COSINE) * c / ENV_PI
        + float(ENV_WIDE) * (LOBE_WIDE + 1.0) / (2.0 * ENV_PI) * pow(a, LOBE_WIDE)
        + float(ENV_NARROW) * (LOBE_NARROW + 1.0) / (2.0 * ENV_PI) * pow(a, LOBE_NARROW);
}

void main() {
    Surface s = surface();
    // Mirror direction of v about the normal, local frame.
    vec3 r = vec3(-s.v.x, -s.v.y, s.v.z);
    vec3 sum = vec3(0.0);
    for (int i = 0; i < ENV_SAMPLES; ++i) {
        vec3 l;
        if (i < ENV_UNIFORM) {
            l = uniform_hemisphere(hammersley(i, ENV_UNIFORM));
        } else if (i < ENV_UNIFORM + ENV_COSINE) {
            l = cosine_hemisphere(hammersley(i - ENV_UNIFORM, ENV_COSINE));
        } else if (i < ENV_UNIFORM + ENV_COSINE + ENV_WIDE) {
            l = phong_lobe(hammersley(i - ENV_UNIFORM - ENV_COSINE, ENV_WIDE), r, LOBE_WIDE);
        } else {
            l = phong_lobe(hammersley(i - ENV_UNIFORM - ENV_COSINE - ENV_WIDE, ENV_NARROW), r, LOBE_NARROW);
        }
        if (l.z <= 0.0) continue;
        float density = mixture_density(l, r);
        // The sample as a light direction: the same Surface, another l (and h).
        Surface q = s;
        q.l = l;
        vec3 hs = l + s.v;
        float hl = length(hs);
        q.h = hl > 1e-6 ? hs / hl : vec3(0.0, 0.0, 1.0);
        vec3 lw = normalize(l.x * s.t + l.y * s.b + l.z * s.n);
        float lod = max(0.5 * log2(1.0 / (density * env_texel_solid_angle())) , 0.0);
        sum += term_product(q) * env_radiance(lw, lod) / density;
    }
    vec3 key = term_product(s) * u_light_rgb * s.falloff;
    o_color = vec4(term_detail(s, (sum + u_key * key) * term_coefficient(s)), 1.0);
}
