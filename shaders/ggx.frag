// Analytic Cook-Torrance with the GGX distribution, Smith masking and Schlick Fresnel: the
// same model as brdf::Analytic::Ggx, for speed comparisons with the factored shader.
//   $S = [k_d/\pi + F D G / (4 \cos\theta_l \cos\theta_v)] \cos\theta_l$, $\alpha = r^2$.

uniform vec3 u_diffuse;
uniform vec3 u_f0;
uniform float u_roughness;

layout(location = 0) out vec4 o_color;

const float PI = 3.14159265358979;

float ggx_d(float cos_h, float alpha) {
    float a2 = alpha * alpha;
    float t = (a2 - 1.0) * cos_h * cos_h + 1.0;
    return a2 / (PI * max(t * t, 1e-30));  // the floor only guards alpha = 0
}

float ggx_g1(float c, float alpha) {
    float a2 = alpha * alpha;
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

void main() {
    Surface s = surface();
    float cos_l = s.l.z;
    float cos_v = s.v.z;
    vec3 f = vec3(0.0);
    // Zero when either direction is at or below the horizon, as in Analytic::brdf.
    if (cos_l > 0.0 && cos_v > 0.0) {
        float alpha = u_roughness * u_roughness;
        float d = ggx_d(s.h.z, alpha);
        float g = ggx_g1(cos_l, alpha) * ggx_g1(cos_v, alpha);
        vec3 fresnel = u_f0 + (1.0 - u_f0) * pow(1.0 - clamp(dot(s.l, s.h), 0.0, 1.0), 5.0);
        f = (u_diffuse / PI + fresnel * (d * g / (4.0 * cos_l * cos_v))) * cos_l;
    }
    o_color = vec4(f * u_light_rgb * s.falloff, 1.0);
}
