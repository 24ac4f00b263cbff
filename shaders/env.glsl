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

// Solid angle of a level-0 texel at the equator, $(2\pi/W)(\pi/H)$: the footprint that
// filtered importance sampling compares a sample's solid angle with. Not the texel's true
// solid angle $\propto \sin\theta$: near the poles that is tiny, the level it picks huge,
// and a box-filtered mip level is as tall there as anywhere, so a sample near the zenith
// would read the average of a whole cap of the sky (seen as a dark or bright blotch on
// the tops of objects). The equator's footprint keeps the blur in $\theta$ right
// everywhere; near the poles the azimuth is filtered less than ideal, over a sliver of
// solid angle.
float env_texel_solid_angle() {
    return 2.0 * ENV_PI * ENV_PI / (u_env_size.x * u_env_size.y);
}
