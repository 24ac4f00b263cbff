// Parameterizations: a direction in the local frame to table coordinates in [0,1] or
// [0,1]^2. Exactly the formulas of src/factor/param.rs (see there for the derivations),
// in float32.

#define INPUT_LIGHT 0
#define INPUT_HALF 1
#define INPUT_VIEW 2
#define INPUT_UV 3
#define INPUT_DIFFERENCE 4
#define INPUT_HALF_DIFFERENCE 5

#define PARAM_RADIUS 0
#define PARAM_PARABOLIC 1
#define PARAM_HEMISPHERICAL 2
#define PARAM_UV 3
#define PARAM_RADII 4

#define DOMAIN_HEMISPHERE 0
#define DOMAIN_SPHERE 1

// Log mappings (thesis 3.2.3), inverted per channel and clamped at zero.
#define MAP_IDENTITY 0
#define MAP_OFFSET 1
#define MAP_INVERTED 2

// Extended radius: $\tan(\theta/2)$ above the horizon, $2 - \tan((\pi-\theta)/2)$ below.
float theta_to_rho(float c, float s) {
    return c >= 0.0 ? s / (1.0 + c) : 2.0 - s / (1.0 - c);
}

// 1D radius map $|\pi(d)|$ (thesis eq. 3.5), extended below the horizon in the sphere domain.
float radius_forward(vec3 d, int domain) {
    float s = length(d.xy);
    if (domain == DOMAIN_HEMISPHERE) {
        // Below-horizon directions clamp onto the horizon, where $\rho = 1$.
        return d.z <= 0.0 ? 1.0 : min(s / (1.0 + d.z), 1.0);
    }
    return theta_to_rho(d.z, s) * 0.5;
}

float planar_radius(int param, float c, float s) {
    if (param == PARAM_PARABOLIC) return theta_to_rho(c, s);
    return c >= 0.0 ? s : 2.0 - s;  // hemispherical, mirrored below the horizon
}

// 2D parabolic / hemispherical map into the unit square.
vec2 planar_forward(int param, vec3 d, int domain) {
    float s = length(d.xy);
    // The azimuth is undefined at the poles, where r = 0 (or a single point) anyway.
    vec2 az = s > 1e-12 ? d.xy / s : vec2(1.0, 0.0);
    float r;
    float scale;
    if (domain == DOMAIN_HEMISPHERE) {
        float c = max(d.z, 0.0);
        float sc = d.z <= 0.0 ? 1.0 : s;
        r = min(planar_radius(param, c, sc), 1.0);
        scale = 1.0;
    } else {
        r = planar_radius(param, d.z, s);
        scale = 0.5;
    }
    return (az * r * scale + 1.0) * 0.5;
}

// Rusinkiewicz's difference vector: l in the frame whose pole is h,
// $d = R_y(-\theta_h) R_z(-\phi_h)\, l$, so $d_z = l \cdot h = \cos\theta_d$.
vec3 difference(vec3 l, vec3 h) {
    float sh = length(h.xy);
    // $\phi_h$ is undefined at the pole, where any choice is equivalent.
    vec2 cs = sh > 1e-12 ? h.xy / sh : vec2(1.0, 0.0);
    vec3 l1 = vec3(cs.x * l.x + cs.y * l.y, -cs.y * l.x + cs.x * l.y, l.z);
    return vec3(h.z * l1.x - sh * l1.z, l1.y, sh * l1.x + h.z * l1.z);
}

// Table coordinate of one factor's input.
vec2 table_coordinate(int input_kind, int param, int domain, vec3 l, vec3 h, vec3 v, vec2 uv) {
    if (input_kind == INPUT_UV) return clamp(uv, 0.0, 1.0);
    // $(\theta_h, \theta_d)$ through the radius map; $\theta_d \le \pi/2$ always.
    if (input_kind == INPUT_HALF_DIFFERENCE)
        return vec2(radius_forward(h, domain), radius_forward(difference(l, h), DOMAIN_HEMISPHERE));
    vec3 d = input_kind == INPUT_LIGHT ? l : (input_kind == INPUT_HALF ? h : (input_kind == INPUT_VIEW ? v : difference(l, h)));
    if (param == PARAM_RADIUS) return vec2(radius_forward(d, domain), 0.0);
    if (param == PARAM_UV) return clamp(d.xy, 0.0, 1.0);
    return planar_forward(param, d, domain);
}

// Node warp of a radius axis: the table is uniform in $s = t^{1/\gamma}$ (FactorSpec::warp).
float warp_forward(float t, float gamma) {
    return gamma == 1.0 ? t : pow(clamp(t, 0.0, 1.0), 1.0 / gamma);
}

// Node-based table coordinate t (node i at i/(M-1)) to a texture coordinate: node i is the
// centre of texel i, at (i + 0.5)/M, so GL_LINEAR filtering interpolates between nodes
// exactly as src/factor/table.rs does.
vec2 node_to_texel(vec2 t, vec2 m) {
    return (t * (m - 1.0) + 0.5) / m;
}
