// glTF animations (glTF 2.0 3.11 "Animations") as scene data: every
// channel's target and every sampler's accessors validated, outputs
// decoded to floats. scene/state/animation.h samples them.
#include <algorithm>
#include <string>

#include "scene/gltf/gltf_accessors.h"
#include "scene/gltf/gltf_stages.h"
#include "scene/gltf/gltf_util.h"
#include "scene/magnitude_limits.h"

namespace gistream::gltf {
namespace {

const AccessorSpec kTimes{TINYGLTF_TYPE_SCALAR, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};
const AccessorSpec kVec3{TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};
// Rotations and weights may be normalized integers (glTF 2.0 3.11).
const AccessorSpec kRotation{TINYGLTF_TYPE_VEC4,
                             {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                             true};
const AccessorSpec kWeights{TINYGLTF_TYPE_SCALAR, kRotation.component_types, true};

absl::StatusOr<AnimationPath> ParsePath(const std::string& path, const std::string& field) {
  if (path == "translation") return AnimationPath::kTranslation;
  if (path == "rotation") return AnimationPath::kRotation;
  if (path == "scale") return AnimationPath::kScale;
  if (path == "weights") return AnimationPath::kWeights;
  return absl::InvalidArgumentError(absl::StrCat(
      field, ": '", path.substr(0, 40), "' is not translation, rotation, scale or weights"));
}

absl::StatusOr<Interpolation> ParseInterpolation(const std::string& name,
                                                 const std::string& field) {
  if (name == "LINEAR") return Interpolation::kLinear;
  if (name == "STEP") return Interpolation::kStep;
  if (name == "CUBICSPLINE") return Interpolation::kCubicSpline;
  return absl::InvalidArgumentError(
      absl::StrCat(field, ": '", name.substr(0, 40), "' is not LINEAR, STEP or CUBICSPLINE"));
}

absl::Status ReadTimes(const tinygltf::Model& model, int input, const std::string& field,
                       AnimationSampler* out) {
  GS_ASSIGN_OR_RETURN(const AccessorData d, ValidateAccessor(model, input, kTimes, field));
  GS_ASSIGN_OR_RETURN(out->times, ReadFloatComponents(d));
  if (out->times[0] < 0.0f) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": the first key time ", out->times[0], " is negative"));
  }
  for (size_t k = 1; k < out->times.size(); ++k) {
    if (!(out->times[k] > out->times[k - 1])) {
      return absl::InvalidArgumentError(absl::StrCat(field, ": key ", k, " at ", out->times[k],
                                                     " s is not after key ", k - 1, " at ",
                                                     out->times[k - 1], " s"));
    }
  }
  if (out->interpolation == Interpolation::kCubicSpline && out->times.size() < 2) {
    return absl::InvalidArgumentError(field + ": CUBICSPLINE needs at least two keys");
  }
  return absl::OkStatus();
}

// Checks the values (not the tangents) of every key against the magnitude
// limits; rotations are renormalised (CheckUnitQuaternion).
absl::Status CheckValues(AnimationPath path, const std::string& field, AnimationSampler* s) {
  const size_t per_key = s->interpolation == Interpolation::kCubicSpline ? 3 : 1;
  const size_t offset = s->interpolation == Interpolation::kCubicSpline ? 1 : 0;
  const size_t c = size_t(s->components);
  for (size_t k = 0; k < s->times.size(); ++k) {
    float* v = s->values.data() + (k * per_key + offset) * c;
    const std::string key = absl::StrCat(field, " key ", k);
    switch (path) {
      case AnimationPath::kTranslation:
        GS_RETURN_IF_ERROR(CheckPosition(key, {v[0], v[1], v[2]}));
        break;
      case AnimationPath::kScale: GS_RETURN_IF_ERROR(CheckScale(key, {v[0], v[1], v[2]})); break;
      case AnimationPath::kRotation: {
        GS_ASSIGN_OR_RETURN(const glm::quat q,
                            CheckUnitQuaternion(key, glm::quat(v[3], v[0], v[1], v[2])));
        v[0] = q.x, v[1] = q.y, v[2] = q.z, v[3] = q.w;
        break;
      }
      case AnimationPath::kWeights: break;  // any finite weight
    }
  }
  return absl::OkStatus();
}

absl::Status ReadValues(const tinygltf::Model& model, int output, AnimationPath path,
                        size_t weight_count, const std::string& field, AnimationSampler* out) {
  const AccessorSpec& spec = path == AnimationPath::kRotation  ? kRotation
                             : path == AnimationPath::kWeights ? kWeights
                                                               : kVec3;
  GS_ASSIGN_OR_RETURN(const AccessorData d, ValidateAccessor(model, output, spec, field));
  out->components = path == AnimationPath::kWeights ? int(weight_count) : d.components;
  const uint64_t per_key = out->interpolation == Interpolation::kCubicSpline ? 3 : 1;
  const uint64_t elements_per_key = path == AnimationPath::kWeights ? weight_count : 1;
  const uint64_t expected = out->times.size() * per_key * elements_per_key;
  if (d.count != expected) {
    return absl::InvalidArgumentError(absl::StrCat(
        field, ": ", d.count, " elements, expected ", expected, " (", out->times.size(), " keys",
        per_key == 3 ? " x 3 for CUBICSPLINE" : "",
        path == AnimationPath::kWeights ? absl::StrCat(" x ", weight_count, " morph targets") : "",
        ")"));
  }
  GS_ASSIGN_OR_RETURN(out->values, ReadFloatComponents(d));
  return CheckValues(path, field, out);
}

absl::StatusOr<Animation> ReadAnimation(const tinygltf::Model& model, size_t a,
                                        const Scene& scene) {
  const tinygltf::Animation& in = model.animations[a];
  const std::string field = Item("animations", a);
  Animation out;
  out.name = in.name;
  if (in.channels.empty()) {
    return absl::InvalidArgumentError(field + ".channels: empty (an animation needs a channel)");
  }
  out.samplers.resize(in.samplers.size());
  for (size_t s = 0; s < in.samplers.size(); ++s) {
    const std::string sampler_field = absl::StrCat(field, ".", Item("samplers", s));
    GS_ASSIGN_OR_RETURN(
        out.samplers[s].interpolation,
        ParseInterpolation(in.samplers[s].interpolation, sampler_field + ".interpolation"));
    GS_RETURN_IF_ERROR(
        ReadTimes(model, in.samplers[s].input, sampler_field + ".input", &out.samplers[s]));
  }
  // The first channel using a sampler fixes its output's meaning.
  std::vector<int> sampler_user(in.samplers.size(), -1);
  std::vector<AnimationPath> sampler_path(in.samplers.size());
  std::vector<size_t> sampler_weights(in.samplers.size(), 0);
  for (size_t c = 0; c < in.channels.size(); ++c) {
    const tinygltf::AnimationChannel& ch = in.channels[c];
    const std::string channel_field = absl::StrCat(field, ".", Item("channels", c));
    AnimationChannel channel;
    GS_RETURN_IF_ERROR(
        CheckIndex(channel_field + ".sampler", ch.sampler, in.samplers.size(), "samplers"));
    GS_RETURN_IF_ERROR(
        CheckIndex(channel_field + ".target.node", ch.target_node, scene.nodes.size(), "nodes"));
    GS_ASSIGN_OR_RETURN(channel.path, ParsePath(ch.target_path, channel_field + ".target.path"));
    channel.sampler = ch.sampler;
    channel.node = ch.target_node;
    size_t weights = 0;
    if (channel.path == AnimationPath::kWeights) {
      const Node& node = scene.nodes[size_t(channel.node)];
      if (node.mesh >= 0) weights = scene.meshes[size_t(node.mesh)].weights.size();
      if (weights == 0) {
        return absl::InvalidArgumentError(absl::StrCat(channel_field, ".target: weights of ",
                                                       Item("nodes", channel.node),
                                                       ", which has no mesh with morph targets"));
      }
    }
    for (size_t e = 0; e < c; ++e) {
      const AnimationChannel& other = out.channels[e];
      if (other.node == channel.node && other.path == channel.path) {
        return absl::InvalidArgumentError(absl::StrCat(
            channel_field, ".target: ", Item("nodes", channel.node), " ", ch.target_path,
            " is already animated by ", field, ".", Item("channels", e)));
      }
    }
    const size_t s = size_t(channel.sampler);
    if (sampler_user[s] < 0) {
      sampler_user[s] = int(c);
      sampler_path[s] = channel.path;
      sampler_weights[s] = weights;
      GS_RETURN_IF_ERROR(ReadValues(model, in.samplers[s].output, channel.path, weights,
                                    absl::StrCat(field, ".", Item("samplers", s), ".output"),
                                    &out.samplers[s]));
    } else if (sampler_path[s] != channel.path || sampler_weights[s] != weights) {
      return absl::InvalidArgumentError(absl::StrCat(
          channel_field, ".sampler: ", Item("samplers", s), " also drives ", field, ".",
          Item("channels", sampler_user[s]), ", whose target needs different output"));
    }
    out.channels.push_back(channel);
  }
  bool first = true;
  for (const AnimationSampler& s : out.samplers) {
    if (s.values.empty()) continue;  // unused by any channel
    out.start = first ? s.times.front() : std::min(out.start, s.times.front());
    out.end = first ? s.times.back() : std::max(out.end, s.times.back());
    first = false;
  }
  return out;
}

}  // namespace

absl::StatusOr<std::vector<Animation>> ImportAnimations(const tinygltf::Model& model,
                                                        const Scene& scene) {
  std::vector<Animation> animations;
  animations.reserve(model.animations.size());
  for (size_t a = 0; a < model.animations.size(); ++a) {
    GS_ASSIGN_OR_RETURN(Animation animation, ReadAnimation(model, a, scene));
    animations.push_back(std::move(animation));
  }
  return animations;
}

}  // namespace gistream::gltf
