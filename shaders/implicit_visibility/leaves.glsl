// Leaf and node buffers of the implicit-visibility illumination (std430
// mirrors of server/solvers/implicit_visibility/illumination.cpp).
struct Leaf {
  vec4 position;  // xyz world (the disc's centre)
  vec4 normal;    // xyz unit, w the glossy slot (-1: a diffuse leaf; glossy.glsl)
  vec4 albedo;    // rgb linear diffuse albedo (a glossy leaf's white-sky albedo)
};
