// One term of a factored shading function under the scene's light (thesis eq. 3.1):
//   $f = \mathrm{inv}(\prod_j p_j(\pi_j(l, v, uv))) \cdot c(uv)$,
// times the light's colour, intensity and falloff. Terms of a material map are drawn one
// pass each and added by blending. The evaluation itself is term.glsl's.

layout(location = 0) out vec4 o_color;

void main() {
    Surface s = surface();
    vec3 f = term_product(s) * term_coefficient(s);
    // S(l, v) is BRDF x cos(theta_l) already; the light scales it.
    o_color = vec4(term_detail(s, f * u_light_rgb * s.falloff), 1.0);
}
