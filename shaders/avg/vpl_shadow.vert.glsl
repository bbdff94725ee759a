#version 450 core
// VPL shadow maps (paper Sec. III-C): every scene triangle drawn once per
// VPL with instancing; the instance picks the VPL.
#include "common/scene_vertex.glsl"
uniform int uFirstVpl = 0;  // a slice of the VPLs: instance i draws VPL uFirstVpl + i
flat out int vVpl;
void main() {
  gl_Position = WorldPosition();
  vVpl = uFirstVpl + gl_InstanceID;
}
