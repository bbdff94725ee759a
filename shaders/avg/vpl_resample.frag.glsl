#version 450 core
// A VPL's paraboloid map from its distance cube (issue 19): each texel
// takes the cube's depth (distance / the VPL's far) in the direction of the
// texel's centre, the inverse of ParaboloidUv (Brabec et al. 2002):
// uv = d.xy / (1 + d.z)  <=>  d = (2 uv, 1 - |uv|^2) / (1 + |uv|^2).
// Texels outside the unit disc see below the horizon: left as cleared.
#include "avg/vpl.glsl"
uniform samplerCubeArray uCubes;  // depth as a value (no comparison)
uniform int uResolution;
flat in int vVpl;
flat in int vCube;
void main() {
  vec2 uv = gl_FragCoord.xy / float(uResolution) * 2.0 - 1.0;
  float r2 = dot(uv, uv);
  if (r2 > 1.0) discard;
  vec3 local = vec3(2.0 * uv, 1.0 - r2) / (1.0 + r2);
  vec3 n = vpls[vVpl].normal_layer.xyz, t, b;
  VplBasis(n, t, b);
  gl_FragDepth = texture(uCubes, vec4(t * local.x + b * local.y + n * local.z, float(vCube))).r;
}
