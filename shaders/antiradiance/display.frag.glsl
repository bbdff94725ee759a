#version 450 core
// display: L = L_emitted + albedo / pi * (E_direct + E_indirect). Direct
// light per pixel with the shared shadow maps; the indirect irradiance of
// the leaf elements is interpolated like the paper's splatting (Section
// 4.3): elements near the pixel with a similar normal, weighted by a
// smooth fall-off, re-normalized by the total weight.
#include "render/shade_surface.glsl"
#include "antiradiance/elements.glsl"
layout(std430, binding = 7) readonly buffer Grid { uint grid[]; };  // cell starts (cells + 1), leaf ids
uniform vec3 uGridMin;
uniform ivec3 uGridDims;
uniform float uGridCell;
in vec2 vUv;
out vec4 oRadiance;

vec3 IndirectIrradiance(vec3 p, vec3 n) {
  ivec3 c = clamp(ivec3(floor((p - uGridMin) / uGridCell)), ivec3(0), uGridDims - 1);
  int cells = uGridDims.x * uGridDims.y * uGridDims.z;
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int z = max(c.z - 1, 0); z <= min(c.z + 1, uGridDims.z - 1); ++z)
    for (int y = max(c.y - 1, 0); y <= min(c.y + 1, uGridDims.y - 1); ++y)
      for (int x = max(c.x - 1, 0); x <= min(c.x + 1, uGridDims.x - 1); ++x) {
        int cell = (z * uGridDims.y + y) * uGridDims.x + x;
        for (uint k = grid[cell]; k < grid[cell + 1]; ++k) {
          Element e = elements[grid[cells + 1 + int(k)]];
          float nd = dot(n, e.normal.xyz);
          if (nd < 0.7) continue;
          vec3 d = p - e.position_radius.xyz;
          float r2 = e.position_radius.w * e.position_radius.w;
          float t = 1.0 - dot(d, d) / r2;
          if (t <= 0.0) continue;
          float w = t * t * nd;
          sum += w * e.irradiance.rgb;
          weight += w;
        }
      }
  return weight > 0.0 ? sum / weight : vec3(0.0);
}

void main() {
  GSurface s;
  if (!ReadGBuffer(ivec2(gl_FragCoord.xy), s)) {
    oRadiance = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  oRadiance = vec4(ShadeSurface(s, IndirectIrradiance(s.position, s.normal)), 1.0);
}
