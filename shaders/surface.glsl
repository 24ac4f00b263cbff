// The shading geometry of a fragment, shared by every fragment stage.
//
// Local frame (DESIGN.md): z = interpolated shading normal, x = tangent made orthogonal to
// it (Gram-Schmidt), y = bitangent = sign · (z × x), as MikkTSpace defines it.

in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;

uniform int u_light_kind;   // 0 directional, 1 point
uniform vec3 u_light_vec;   // directional: unit direction toward the light; point: position
uniform vec3 u_light_rgb;   // colour × intensity
uniform int u_ortho;        // 1 for an orthographic camera
uniform vec3 u_eye;         // camera position (perspective)
uniform vec3 u_toward_eye;  // unit direction toward the camera (orthographic)

struct Surface {
    vec3 p;         // world position
    vec3 n, t, b;   // world-space frame
    vec3 lw, vw;    // world-space unit directions toward light and viewer
    vec3 l, v, h;   // the same in the local frame, and the half vector
    float falloff;  // 1/d^2 for point lights, 1 for directional ones
    vec2 uv;
};

vec3 to_local(Surface s, vec3 d) {
    return vec3(dot(d, s.t), dot(d, s.b), dot(d, s.n));
}

Surface surface() {
    Surface s;
    s.p = v_position;
    s.uv = v_uv;
    s.n = normalize(v_normal);
    // Gram-Schmidt: $t = \mathrm{normalize}(t - n (n \cdot t))$.
    vec3 t = v_tangent.xyz - s.n * dot(s.n, v_tangent.xyz);
    float tl = length(t);
    // A tangent (nearly) parallel to the normal has no usable direction: fall back to x
    // projected, as src/brdf/sphere.rs does at the poles; then z.
    if (tl < 1e-6) {
        t = vec3(1.0, 0.0, 0.0) - s.n * s.n.x;
        tl = length(t);
        if (tl < 1e-6) {
            t = vec3(0.0, 0.0, 1.0) - s.n * s.n.z;
            tl = length(t);
        }
    }
    s.t = t / tl;
    // The handedness interpolates across mirrored seams; only its sign counts.
    s.b = cross(s.n, s.t) * (v_tangent.w < 0.0 ? -1.0 : 1.0);

    if (u_light_kind == 1) {
        vec3 d = u_light_vec - s.p;
        float d2 = dot(d, d);
        s.lw = d * inversesqrt(d2);
        // glTF point light falloff; the light sits off the surface, so d2 > 0.
        s.falloff = 1.0 / d2;
    } else {
        s.lw = u_light_vec;
        s.falloff = 1.0;
    }
    s.vw = u_ortho == 1 ? u_toward_eye : normalize(u_eye - s.p);

    s.l = to_local(s, s.lw);
    s.v = to_local(s, s.vw);
    // $h = (l + v)/|l + v|$; undefined for $l = -v$, where the normal stands in
    // (as in Query::h).
    vec3 hs = s.l + s.v;
    float hl = length(hs);
    s.h = hl > 1e-6 ? hs / hl : vec3(0.0, 0.0, 1.0);
    return s;
}
