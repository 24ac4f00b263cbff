// Vertex stage shared by every mesh pass (factored, reference, G-buffer, outline, analytic),
// so that all passes rasterize exactly the same pixels and depths.
// The #version line and precision are prepended at run time (src/gl/shader.rs).

layout(location = 0) in vec3 a_position;  // world space (node transforms applied)
layout(location = 1) in vec3 a_normal;    // world-space shading normal
layout(location = 2) in vec4 a_tangent;   // world-space tangent, w = bitangent sign
layout(location = 3) in vec2 a_uv;        // TEXCOORD_0 (constant 0 when the mesh has none)

uniform mat4 u_view_proj;  // clip from world

out vec3 v_position;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;

// Identical clip positions in every program: later passes of a multi-term material test
// depth with GL_LEQUAL against the first pass's depth.
invariant gl_Position;

void main() {
    v_position = a_position;
    v_normal = a_normal;
    v_tangent = a_tangent;
    v_uv = a_uv;
    gl_Position = u_view_proj * vec4(a_position, 1.0);
}
