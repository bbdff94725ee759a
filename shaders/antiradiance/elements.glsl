// Leaf elements of the antiradiance hierarchy (std430 mirror of
// ElementGpu in server/solvers/antiradiance/antiradiance_solver.cpp).
#include "antiradiance/bindings.glsl"
struct Element {
  vec4 position_radius;  // xyz centre, w splat radius
  vec4 normal;           // xyz unit normal, w glossy slot (-1: Lambertian leaf)
  vec4 irradiance;       // rgb indirect irradiance E (W/m^2), >= 0
};
layout(std430, binding = AR_BINDING_ELEMENTS) readonly buffer Elements { Element elements[]; };
