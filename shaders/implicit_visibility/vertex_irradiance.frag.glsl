#version 450 core
in vec3 vIrradiance;
layout(location = 0) out vec4 oIrradiance;
void main() { oIrradiance = vec4(vIrradiance, 1.0); }
