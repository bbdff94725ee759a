#version 450 core
// Depth = distance to the VPL / far, exact per fragment (the paraboloid
// projection is not linear, so interpolated depth would be wrong).
in vec3 gLocal;
flat in float gFar;
void main() { gl_FragDepth = clamp(length(gLocal) / gFar, 0.0, 1.0); }
