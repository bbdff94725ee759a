#version 450 core
// VPL shadow maps (paper Sec. III-C): every scene triangle drawn once per
// VPL with instancing; the instance picks the VPL.
#include "common/scene.glsl"
layout(location = 0) in vec3 aPosition;
uniform int uFirstVpl = 0;  // a slice of the VPLs: instance i draws VPL uFirstVpl + i
flat out int vVpl;
void main() {
  gl_Position = uModel * vec4(aPosition, 1.0);
  vVpl = uFirstVpl + gl_InstanceID;
}
