#version 450 core
// VPL shadow maps (paper Sec. III-C): every scene triangle drawn once per
// VPL with instancing; the instance picks the VPL.
#include "common/scene.glsl"
layout(location = 0) in vec3 aPosition;
flat out int vVpl;
void main() {
  gl_Position = uModel * vec4(aPosition, 1.0);
  vVpl = gl_InstanceID;
}
