// The background: the environment seen along each pixel's camera ray, or a flat colour.
// The ray is the difference of two unprojected points of the pixel (near plane and
// NDC depth 0), which works for perspective (also with an infinite far plane) and
// orthographic cameras alike. Alpha stays 0: alpha is the object's coverage.

in vec2 v_ndc;
uniform mat4 u_world_from_clip;
uniform int u_show_env;    // 1: the environment, 0: u_background
uniform vec3 u_background;

layout(location = 0) out vec4 o_color;

void main() {
    vec4 a = u_world_from_clip * vec4(v_ndc, -1.0, 1.0);
    vec4 b = u_world_from_clip * vec4(v_ndc, 0.0, 1.0);
    vec3 d = normalize(b.xyz / b.w - a.xyz / a.w);
    o_color = vec4(u_show_env == 1 ? env_radiance(d, 0.0) : u_background, 0.0);
}
