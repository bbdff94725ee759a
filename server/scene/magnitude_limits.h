// Magnitude limits on scene values: finiteness is not enough, because a
// finite value can still overflow a float once a solver multiplies it
// (1e20 m positions abort Embree, emissive_strength 3e38 renders +Inf).
// glTF import, update validation and the scene state all enforce these, so
// no accepted value, nor any product of accepted values, leaves the range
// every solver was written for. README "Limits" and the proto repeat them.
//
// Why these values: float's largest value is 3.4e38. With every world
// coordinate within 1e6 m, squared distances stay below 4e12 and areas
// below 4e12 m^2; with every source's radiance (or intensity) within 1e10,
// the largest flux sum a solver forms (radiance x pi x area x 4e6
// triangles, the triangle limit) stays below 1e31, seven orders of
// magnitude under overflow and room for Monte Carlo weights; a radiance of
// 1e10 times the largest exposure gain (2^30) is 1e19. What geometry alone
// can still blow up (1/r^2 at r -> 0) the solvers clamp, and every frame
// is checked finite before it is encoded. The limits themselves are
// generous: 1e6 m is 1000 km
// (the design asks for millimetres to kilometres) and the sun's luminance
// is 1.6e9 nits.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene/scene.h"
#include "util/status.h"

namespace gistream {

// Largest |x|, |y| or |z| of any position: vertices (local and world),
// node translations, light and camera positions. Metres.
inline constexpr float kMaxCoordinate = 1e6f;
// Per-axis |scale| of a node, local and world: beyond [1e-6, 1e6] the
// inverse-transpose normal matrix (1 / scale) loses all precision, and
// 1e6 x 1e6 m already reaches the coordinate limit.
inline constexpr float kMinScale = 1e-6f;
inline constexpr float kMaxScale = 1e6f;
// Largest source strength after every multiplier: light colour x intensity
// (candela or lux), emissive factor x emissive strength (nits), environment
// pixel x environment intensity (nits). See the argument above.
inline constexpr float kMaxRadiance = 1e10f;
// A quaternion whose length is within this of 1 is renormalised (exporters
// write 6-7 digits); farther from unit length it is a mistake, not
// rounding, and is rejected.
inline constexpr float kQuaternionTolerance = 1e-2f;
// Vertical field of view: below 0.1 degrees the projection's 1/tan(fov/2)
// (1146) leaves too little depth precision to rasterise; 179 degrees is the
// widest a perspective projection stays finite with margin.
inline constexpr float kMinYfovDegrees = 0.1f;
inline constexpr float kMaxYfovDegrees = 179.0f;
// Environment pixels below -kNegativeRadianceTolerance are rejected: a
// negative radiance is a broken map. Filtered HDR captures carry tiny
// negative ringing, which is clamped to 0.
inline constexpr float kNegativeRadianceTolerance = 1e-3f;
// Animation updates: a seek within +-1e6 s keeps float key times exact to
// about 0.06 s; a playback rate beyond +-1000 is not an animation any more.
inline constexpr float kMaxAnimationTime = 1e6f;
inline constexpr float kMaxAnimationSpeed = 1e3f;
// A morph weight beyond +-100 scales a target's deltas (held to
// kMaxCoordinate) past anything an exporter writes (glTF weights are
// usually in [0, 1]).
inline constexpr float kMaxMorphWeight = 100.0f;

// `field: v is out of range [lo, hi]` for a value outside [lo, hi] or NaN.
absl::Status CheckMagnitude(const std::string& field, double v, double lo, double hi);
// Each |component| <= kMaxCoordinate, naming "field.x" etc.
absl::Status CheckPosition(const std::string& field, const glm::vec3& p);
// kMinScale <= |s| <= kMaxScale per axis, naming "field.x" etc.
absl::Status CheckScale(const std::string& field, const glm::vec3& s);
// A unit quaternion within kQuaternionTolerance, returned normalised;
// INVALID_ARGUMENT naming `field` for a zero, non-finite or far-from-unit one.
absl::StatusOr<glm::quat> CheckUnitQuaternion(const std::string& field, const glm::quat& q);

// World-space checks of a whole scene with edited `nodes` (same hierarchy
// as scene.nodes) and their world matrices: every node's world scale and
// position, and every mesh's transformed bounds, within the limits above.
// Messages start with `prefix` and name the node ("nodes[4]").
absl::Status CheckWorldExtent(const Scene& scene, const std::vector<Node>& nodes,
                              const std::vector<glm::mat4>& world, const std::string& prefix);

// Largest emitted radiance of a material (max component of factor x strength).
float MaxEmission(const Material& m);
// Largest component of a light's colour x intensity.
float MaxLightStrength(const Light& l);
// Largest channel of an environment image (0 for an empty one).
float MaxPixel(const Image& image);

}  // namespace gistream
