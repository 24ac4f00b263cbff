// Equirectangular environment lookups. The convention (row 0 at the zenith +y, the centre
// column looking along -z, u growing toward +x) and its CPU twin are in
// src/images/env.rs; the texture is uploaded row 0 first, so texture t equals v.
//
// Uniforms: u_env (RGBA32F, mip-mapped, REPEAT in s so filtering wraps across the seam,
// CLAMP_TO_EDGE in t), u_env_turn (rotation about +y in turns, degrees / 360),
// u_env_size (level-0 texels, W x H).

uniform sampler2D u_env;
uniform float u_env_turn;
uniform vec2 u_env_size;

const float ENV_PI = 3.14159265358979;

// $u = \mathrm{atan2}(d_x, -d_z)/2\pi + 1/2 + \alpha/2\pi$, $v = \arccos(d_y)/\pi$.
vec2 env_uv(vec3 d) {
    // atan(0, 0) is undefined; at the poles every u is the same point anyway.
    float u = abs(d.x) + abs(d.z) > 1e-12 ? atan(d.x, -d.z) / (2.0 * ENV_PI) + 0.5 : 0.5;
    float v = acos(clamp(d.y, -1.0, 1.0)) / ENV_PI;
    return vec2(u + u_env_turn, v);
}

// Radiance arriving from world direction d, averaged over a footprint of 2^lod texels.
vec3 env_radiance(vec3 d, float lod) {
    return textureLod(u_env, env_uv(d), lod).rgb;
}

// Solid angle of a level-0 texel seen in direction d: $(2\pi/W)(\pi/H)\sin\theta$.
float env_texel_solid_angle(vec3 d) {
    float sin_theta = sqrt(max(1.0 - d.y * d.y, 0.0));
    // At the poles a texel row still covers a sliver; 1e-3 keeps the log finite.
    return 2.0 * ENV_PI * ENV_PI / (u_env_size.x * u_env_size.y) * max(sin_theta, 1e-3);
}
