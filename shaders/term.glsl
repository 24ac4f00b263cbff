// One term of a factored shading function (thesis eq. 3.1), the one GLSL evaluation of a
// material, shared by the key-light pass (factored.frag) and the environment pass (env.frag):
//   $f = B(l, v) \cdot \mathrm{inv}(\prod_j p_j(\pi_j(l, v, uv))) \cdot c(uv)$.
// term_product(s) is the mapped product at the Surface's (l, h, v, uv) times the term's
// analytic base B (issue 15, src/factor/base.rs; 1 without one); term_coefficient(s) is
// c(uv), 1 without a coefficient texture.
//
// Compile-time layout (prepended #defines, see src/render/shading.rs):
//   NUM_FACTORS 0..6; F<k>_INPUT, F<k>_PARAM, F<k>_DOMAIN per factor and MAP_KIND name
//   param.glsl's codes (INPUT_LIGHT, PARAM_RADIUS, DOMAIN_SPHERE, MAP_OFFSET, ...), the one
//   place they are defined; F<k>_DIM 1 or 2; F<k>_WARP the node warp of a radius axis (a
//   float literal, 1.0 for none); F<k>_LEAN the lean of a half-vector input (a float literal,
//   1.0 for none); HAS_COEF 0 or 1; HAS_BASE 0 or 1; BASE_LOBE 0..6 (the
//   base lobe's family); HAS_DETAIL 0 or 1 (the painting's detail, term_detail) and
//   DETAIL_GAIN (a float literal, Detail::GAIN).
// Uniforms: u_factor<k> (sampler), u_res<k> (nodes per axis), u_map_a (per-channel a),
//   u_coef (sampler) and u_coef_size (texels per axis); with a base u_base_ambient,
//   u_base_diffuse, u_base_specular, u_base_fresnel (per channel) and u_base_alpha (the
//   lobe's width), the lobe's family in BASE_LOBE; with detail u_detail (sampler),
//   u_detail_floor and the camera's right and up in world space, u_view_right and u_view_up.

uniform sampler2D u_factor0;
uniform sampler2D u_factor1;
uniform sampler2D u_factor2;
uniform sampler2D u_factor3;
uniform sampler2D u_factor4;
uniform sampler2D u_factor5;
uniform float u_res0;
uniform float u_res1;
uniform float u_res2;
uniform float u_res3;
uniform float u_res4;
uniform float u_res5;
uniform vec3 u_map_a;
uniform sampler2D u_coef;
uniform vec2 u_coef_size;

#if HAS_BASE
uniform vec3 u_base_ambient;
uniform vec3 u_base_diffuse;
uniform vec3 u_base_specular;
uniform vec3 u_base_fresnel;
uniform float u_base_alpha;

// The analytic base, as Base::shading computes it (src/factor/base.rs, Lobe::shape):
//   $B = a + d(l, v) k_d + (k_s + k_f (1 - \cos\theta_d)^5) s(l, v; \alpha)$, with the diffuse
//   shading d = cos^+ theta_l (but for Ashikhmin-Shirley) and the specular shading s of the
//   family BASE_LOBE (0 GGX, 1 Blinn-Phong, 2 Phong, 3 Ward, 4 Ashikhmin-Shirley,
//   5 Oren-Nayar, 6 Minnaert), zero when l or v is below the horizon; Schlick's Fresnel as
//   two linear coefficients. Exponents e = 2/alpha^2 - 2.
vec3 term_base(Surface s) {
    float cl = s.l.z;
    float cv = s.v.z;
#if BASE_LOBE == 4
    // Ashikhmin-Shirley's diffuse: cos theta_l g(cos theta_l) g(cos theta_v), g(c) = 1 - (1 - c/2)^5.
    float gl5 = 1.0 - 0.5 * max(cl, 0.0);
    float gv5 = 1.0 - 0.5 * max(cv, 0.0);
    float dif = max(cl, 0.0) * (1.0 - gl5 * gl5 * gl5 * gl5 * gl5) * (1.0 - gv5 * gv5 * gv5 * gv5 * gv5);
#else
    float dif = max(cl, 0.0);
#endif
    vec3 b = u_base_ambient + dif * u_base_diffuse;
    if (cl > 0.0 && cv > 0.0) {
        float alpha = u_base_alpha;
        float a2 = alpha * alpha;
        // Both directions above the horizon, so l + v != 0.
        vec3 h = normalize(s.l + s.v);
        float x = 1.0 - clamp(dot(s.l, h), 0.0, 1.0);
        float x5 = x * x * x * x * x;
#if BASE_LOBE == 0
        float t = (a2 - 1.0) * h.z * h.z + 1.0;
        float d = a2 / (3.14159265358979 * t * t);
        float gl = 1.0 / (cl + sqrt(a2 + (1.0 - a2) * cl * cl));
        float gv = 1.0 / (cv + sqrt(a2 + (1.0 - a2) * cv * cv));
        float lobe = cl * d * gl * gv;
#elif BASE_LOBE == 1 || BASE_LOBE == 2 || BASE_LOBE == 4
#if BASE_LOBE == 2
        float c = 2.0 * cl * cv - dot(s.l, s.v);
#else
        float c = h.z;
#endif
        float lobe = c > 0.0 ? cl * pow(c, 2.0 / a2 - 2.0) : 0.0;
#if BASE_LOBE == 4
        lobe /= max(dot(s.l, h), 1e-12) * max(cl, cv);
#endif
#elif BASE_LOBE == 3
        float c2 = max(h.z * h.z, 1e-30);
        float lobe = cl * exp(-(1.0 - c2) / (c2 * a2)) / (4.0 * 3.14159265358979 * a2 * sqrt(cl * cv));
#elif BASE_LOBE == 5
        // Oren-Nayar's B term: cos(phi_l - phi_v)^+ sin(theta_max) tan(theta_min).
        float pl = length(s.l.xy);
        float pv = length(s.v.xy);
        float cos_phi = (pl > 1e-12 && pv > 1e-12) ? max(dot(s.l.xy, s.v.xy) / (pl * pv), 0.0) : 0.0;
        float c_max = max(cl, cv);
        float c_min = min(cl, cv);
        float lobe = cl * cos_phi * sqrt(max(1.0 - c_min * c_min, 0.0)) * sqrt(max(1.0 - c_max * c_max, 0.0)) / c_max;
#else
        float lobe = cl * pow(cl * cv, alpha - 1.0);
#endif
        b += lobe * (u_base_specular + x5 * u_base_fresnel);
    }
    return b;
}
#endif

vec3 factor(sampler2D tex, int input_kind, int param, int domain, int dim, float warp, float lean, float m, Surface s) {
    // The half vector leaned by k, h_k = (l + k v) / |l + k v| (FactorSpec::lean; 1: h).
    vec3 hk = s.l + lean * s.v;
    vec3 h = lean == 1.0 ? s.h : (length(hk) > 1e-6 ? normalize(hk) : vec3(0.0, 0.0, 1.0));
    vec2 t = table_coordinate(input_kind, param, domain, s.l, h, s.v, s.uv);
    t.x = warp_forward(t.x, warp);
    // 1D tables are M x 1 textures (GLES has no 1D textures): sample the row's centre.
    vec2 size = dim == 1 ? vec2(m, 1.0) : vec2(m);
    vec2 tc = node_to_texel(t, size);
    if (dim == 1) tc.y = 0.5;
    return texture(tex, tc).rgb;
}

vec3 term_product(Surface s) {
    vec3 prod = vec3(1.0);
#if NUM_FACTORS > 0
    prod *= factor(u_factor0, F0_INPUT, F0_PARAM, F0_DOMAIN, F0_DIM, F0_WARP, F0_LEAN, u_res0, s);
#endif
#if NUM_FACTORS > 1
    prod *= factor(u_factor1, F1_INPUT, F1_PARAM, F1_DOMAIN, F1_DIM, F1_WARP, F1_LEAN, u_res1, s);
#endif
#if NUM_FACTORS > 2
    prod *= factor(u_factor2, F2_INPUT, F2_PARAM, F2_DOMAIN, F2_DIM, F2_WARP, F2_LEAN, u_res2, s);
#endif
#if NUM_FACTORS > 3
    prod *= factor(u_factor3, F3_INPUT, F3_PARAM, F3_DOMAIN, F3_DIM, F3_WARP, F3_LEAN, u_res3, s);
#endif
#if NUM_FACTORS > 4
    prod *= factor(u_factor4, F4_INPUT, F4_PARAM, F4_DOMAIN, F4_DIM, F4_WARP, F4_LEAN, u_res4, s);
#endif
#if NUM_FACTORS > 5
    prod *= factor(u_factor5, F5_INPUT, F5_PARAM, F5_DOMAIN, F5_DIM, F5_WARP, F5_LEAN, u_res5, s);
#endif

    // Inverse of the log mapping (thesis eq. 3.14, 3.16), clamped at zero.
#if MAP_KIND == MAP_OFFSET
    vec3 f = max(prod - u_map_a, 0.0);
#elif MAP_KIND == MAP_INVERTED
    vec3 f = max(u_map_a - prod, 0.0);
#else
    vec3 f = max(prod, 0.0);
#endif
#if HAS_BASE
    f *= term_base(s);
#endif
    return f;
}

vec3 term_coefficient(Surface s) {
#if HAS_COEF
    // Material-map coefficient over uv, node-based like the uv factor.
    return texture(u_coef, node_to_texel(clamp(s.uv, 0.0, 1.0), u_coef_size)).rgb;
#else
    return vec3(1.0);
#endif
}

#if HAS_DETAIL
uniform sampler2D u_detail;
uniform float u_detail_floor;
uniform vec3 u_view_right;
uniform vec3 u_view_up;
#endif

// A term's output `value` with the painting's detail (src/material/detail.rs): the shading
// normal in view space reads d from a square texture with the unit disk inscribed, as a
// MatCap is read, clamped to the disk (texel centres, row 0 at the top, y = 1), and the value
// becomes value min(d, DETAIL_GAIN) + floor (d - 1), the floor's part added in the first
// term's pass only (u_detail_floor is 0 in the others). The value as it is without detail.
vec3 term_detail(Surface s, vec3 value) {
#if HAS_DETAIL
    vec2 c = vec2(dot(s.n, u_view_right), dot(s.n, u_view_up));
    float r = length(c);
    if (r > 1.0) c /= r;
    vec3 d = texture(u_detail, vec2(0.5 + 0.5 * c.x, 0.5 - 0.5 * c.y)).rgb;
    return max(value * min(d, vec3(DETAIL_GAIN)) + u_detail_floor * (d - 1.0), 0.0);
#else
    return value;
#endif
}
