// Reference shading shown beside the outline (thesis 4.1): Lambert plus Phong under the
// scene's light, so the artist can read the light direction.
//   $c = k_a + E\,[k_d \max(\cos\theta_l, 0) + k_s \max(r \cdot v, 0)^n]$, with
//   $r = 2 (n \cdot l) n - l$, the specular term only where $\cos\theta_l > 0$,
//   and $E$ = light colour x intensity x falloff.

uniform vec3 u_ambient;
uniform vec3 u_diffuse;
uniform vec3 u_specular;
uniform float u_shininess;

layout(location = 0) out vec4 o_color;

void main() {
    Surface s = surface();
    float cos_l = s.l.z;
    vec3 c = u_diffuse * max(cos_l, 0.0);
    if (cos_l > 0.0) {
        vec3 r = 2.0 * cos_l * vec3(0.0, 0.0, 1.0) - s.l;  // mirror of l about n, local frame
        c += u_specular * pow(max(dot(r, s.v), 0.0), u_shininess);
    }
    o_color = vec4(u_ambient + c * u_light_rgb * s.falloff, 1.0);
}
