#version 450 core
// Stores distance to the light / far as depth, so lookups compare distances
// along any direction.
uniform vec3 uLightPos;
uniform float uFar;
in vec3 gWorld;
void main() { gl_FragDepth = clamp(length(gWorld - uLightPos) / uFar, 0.0, 1.0); }
