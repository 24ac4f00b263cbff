// G-buffer: one RGBA32F quantity per pass, chosen by u_output. All passes share the vertex
// stage and surface() with the factored shader, so l, v and uv are exactly what it sees.
//   0: world position xyz, 1 (coverage)
//   1: local l xyz, light falloff (1/d^2 or 1)
//   2: local v xyz, eye-space depth (distance along the view axis)
//   3: world shading normal xyz (normalized), u
//   4: world tangent xyz (orthonormalized), bitangent sign
//   5: world face normal xyz (from screen-space derivatives), v

uniform int u_output;
uniform vec3 u_view_axis;  // unit camera forward (world), for the depth output

layout(location = 0) out vec4 o_color;

void main() {
    Surface s = surface();
    vec4 o;
    if (u_output == 0) {
        o = vec4(s.p, 1.0);
    } else if (u_output == 1) {
        o = vec4(s.l, s.falloff);
    } else if (u_output == 2) {
        o = vec4(s.v, dot(s.p - u_eye, u_view_axis));
    } else if (u_output == 3) {
        o = vec4(s.n, s.uv.x);
    } else if (u_output == 4) {
        o = vec4(s.t, v_tangent.w < 0.0 ? -1.0 : 1.0);
    } else {
        // The triangle's plane normal: derivatives of the position within one triangle.
        // Oriented to agree with the shading normal (winding is not trusted).
        vec3 fn_ = cross(dFdx(s.p), dFdy(s.p));
        float len = length(fn_);
        fn_ = len > 0.0 ? fn_ / len : s.n;
        if (dot(fn_, s.n) < 0.0) fn_ = -fn_;
        o = vec4(fn_, s.uv.y);
    }
    o_color = o;
}
