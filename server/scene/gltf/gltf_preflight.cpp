#include "scene/gltf/gltf_preflight.h"

#include <absl/strings/str_join.h>

#include <cmath>
#include <cstring>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "encode/image_format.h"
#include "scene/gltf/gltf_util.h"
#include "scene/gltf/scene_files.h"

namespace gistream::gltf {
namespace {

using json = nlohmann::json;

constexpr uint32_t kGlbMagic = 0x46546c67;   // "glTF"
constexpr uint32_t kChunkJson = 0x4e4f534a;  // "JSON"
constexpr uint32_t kChunkBin = 0x004e4942;   // "BIN\0"
// Bounds on the JSON document, which is parsed into a DOM twice (here and in
// tinygltf) at ~100 bytes per value: 8M values allow ~50 values for each of
// 100k nodes plus meshes and accessors. Depth bounds tinygltf's recursive
// conversion of extras and extensions.
constexpr uint64_t kMaxJsonValues = 8'000'000;
constexpr size_t kMaxJsonDepth = 64;

// A file may require these (extensionsRequired): import applies them
// (gltf_extensions.cpp, README "glTF extensions").
const std::set<std::string, std::less<>> kUnderstoodExtensions = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_ior",
    "KHR_materials_specular", "KHR_texture_transform"};

uint32_t ReadU32(std::span<const uint8_t> bytes, size_t offset) {
  uint32_t v = 0;
  std::memcpy(&v, bytes.data() + offset, 4);  // glb is little-endian, as are our targets
  return v;
}

// A member that must be a non-negative integer when present.
absl::StatusOr<std::optional<uint64_t>> GetUnsigned(const json& object, const char* key,
                                                    const std::string& field) {
  const auto it = object.find(key);
  if (it == object.end()) return std::optional<uint64_t>();
  if (!it->is_number_unsigned()) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ".", key, ": ", it->dump(), " is not a non-negative integer"));
  }
  return std::optional<uint64_t>(it->get<uint64_t>());
}

// A SAX pass before the DOM is built: it bounds depth and size, and names
// the JSON path of a syntax error ("nodes[0].translation[0]: number
// overflow"), which the DOM parser cannot.
class JsonChecker : public nlohmann::json_sax<json> {
 public:
  absl::Status status() const { return status_; }

  bool null() override { return Value(); }
  bool boolean(bool) override { return Value(); }
  bool number_integer(number_integer_t) override { return Value(); }
  bool number_unsigned(number_unsigned_t) override { return Value(); }
  bool number_float(number_float_t, const string_t&) override { return Value(); }
  bool string(string_t&) override { return Value(); }
  bool binary(binary_t&) override { return Value(); }
  bool start_object(std::size_t) override { return Open(false); }
  bool start_array(std::size_t) override { return Open(true); }
  bool key(string_t& key) override {
    frames_.back().key = key;
    return true;
  }
  bool end_object() override { return Close(); }
  bool end_array() override { return Close(); }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& e) override {
    status_ = absl::InvalidArgumentError(
        absl::StrCat(Path(), ": malformed JSON at byte ", position, ": ", e.what()));
    return false;
  }

 private:
  struct Frame {
    bool array = false;
    uint64_t index = 0;
    std::string key;
  };

  std::string Path() const {
    std::string path;
    for (const Frame& f : frames_) {
      if (f.array) {
        absl::StrAppend(&path, "[", f.index, "]");
      } else if (!f.key.empty()) {
        absl::StrAppend(&path, path.empty() ? "" : ".", f.key);
      }
    }
    return path.empty() ? "scene JSON" : path;
  }

  bool Count() {
    if (++values_ <= kMaxJsonValues) return true;
    status_ = absl::ResourceExhaustedError(
        absl::StrCat("scene JSON: more than ", kMaxJsonValues, " values"));
    return false;
  }
  bool Value() {
    if (!Count()) return false;
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return true;
  }
  bool Open(bool array) {
    if (!Count()) return false;
    if (frames_.size() >= kMaxJsonDepth) {
      status_ = absl::InvalidArgumentError(
          absl::StrCat(Path(), ": JSON nested deeper than ", kMaxJsonDepth, " levels"));
      return false;
    }
    frames_.push_back(Frame{array, 0, {}});
    return true;
  }
  bool Close() {
    frames_.pop_back();
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return true;
  }

  std::vector<Frame> frames_;
  uint64_t values_ = 0;
  absl::Status status_;
};

absl::StatusOr<json> ParseJson(std::span<const uint8_t> text) {
  JsonChecker checker;
  if (!json::sax_parse(text.begin(), text.end(), &checker)) return checker.status();
  try {
    return json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {
    // The SAX pass accepted the text, so this is not expected.
    return absl::InvalidArgumentError(absl::StrCat("scene JSON: ", e.what()));
  }
}

absl::Status CheckAsset(const json& doc) {
  const auto asset = doc.find("asset");
  if (asset == doc.end() || !asset->is_object()) {
    return absl::InvalidArgumentError("asset: missing (every glTF has asset.version)");
  }
  const auto version = asset->find("version");
  if (version == asset->end() || !version->is_string()) {
    return absl::InvalidArgumentError("asset.version: missing");
  }
  const std::string v = version->get<std::string>();
  if (v.rfind("2.", 0) != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("asset.version: '", v, "' is not supported (glTF 2.x only)"));
  }
  return absl::OkStatus();
}

absl::Status CheckRequiredExtensions(const json& doc) {
  const auto required = doc.find("extensionsRequired");
  if (required == doc.end()) return absl::OkStatus();
  if (!required->is_array()) {
    return absl::InvalidArgumentError("extensionsRequired: not an array");
  }
  for (size_t i = 0; i < required->size(); ++i) {
    const json& name = (*required)[i];
    if (!name.is_string() || !kUnderstoodExtensions.contains(name.get<std::string>())) {
      return absl::InvalidArgumentError(absl::StrCat(
          Item("extensionsRequired", i), ": ", name.dump(),
          " is not supported (supported: ", absl::StrJoin(kUnderstoodExtensions, ", "), ")"));
    }
  }
  return absl::OkStatus();
}

const json* Array(const json& doc, const char* key) {
  const auto it = doc.find(key);
  return it != doc.end() && it->is_array() ? &*it : nullptr;
}

// Declared buffer sizes; tinygltf makes every buffer's data exactly this long.
absl::StatusOr<std::vector<uint64_t>> CheckBuffers(const json& doc, const Container& container,
                                                   const ImportOptions& options) {
  std::vector<uint64_t> sizes;
  const json* buffers = Array(doc, "buffers");
  if (buffers == nullptr) return sizes;
  for (size_t i = 0; i < buffers->size(); ++i) {
    const std::string field = Item("buffers", i);
    const json& buffer = (*buffers)[i];
    if (!buffer.is_object()) return absl::InvalidArgumentError(field + ": not an object");
    GS_ASSIGN_OR_RETURN(const std::optional<uint64_t> length,
                        GetUnsigned(buffer, "byteLength", field));
    if (!length) return absl::InvalidArgumentError(field + ".byteLength: missing");
    sizes.push_back(*length);
    const auto uri = buffer.find("uri");
    if (uri == buffer.end()) {
      if (!container.binary || i != 0) {
        return absl::InvalidArgumentError(
            field + ".uri: missing (only buffers[0] of a .glb may use the BIN chunk)");
      }
      if (*length > container.bin_size) {
        return absl::InvalidArgumentError(absl::StrCat(field, ".byteLength: ", *length,
                                                       " exceeds the glb BIN chunk (",
                                                       container.bin_size, " bytes)"));
      }
      continue;
    }
    if (!uri->is_string()) return absl::InvalidArgumentError(field + ".uri: not a string");
    const std::string& text = uri->get_ref<const std::string&>();
    if (text.rfind("data:", 0) == 0) continue;
    GS_ASSIGN_OR_RETURN(const std::filesystem::path path,
                        ResolveSceneUri(options.base_dir, text, field + ".uri"));
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      return absl::InvalidArgumentError(
          absl::StrCat(field, ".uri: '", text, "' does not exist in the scene directory"));
    }
  }
  return sizes;
}

// tinygltf 2.7 silently drops a primitive without attributes, which would
// shift the indices our messages use.
absl::Status CheckPrimitives(const json& doc) {
  const json* meshes = Array(doc, "meshes");
  if (meshes == nullptr) return absl::OkStatus();
  for (size_t m = 0; m < meshes->size(); ++m) {
    const json& mesh = (*meshes)[m];
    if (!mesh.is_object()) return absl::InvalidArgumentError(Item("meshes", m) + ": not an object");
    const json* primitives = Array(mesh, "primitives");
    if (primitives == nullptr) continue;
    for (size_t p = 0; p < primitives->size(); ++p) {
      const json& primitive = (*primitives)[p];
      if (!primitive.is_object() || !primitive.contains("attributes") ||
          !primitive.at("attributes").is_object()) {
        return absl::InvalidArgumentError(
            absl::StrCat(Item("meshes", m), ".", Item("primitives", p), ".attributes: missing"));
      }
    }
  }
  return absl::OkStatus();
}

// tinygltf 2.7 hands &buffer.data[view.byteOffset] with view.byteLength to
// the image loader without checking either, so image views are checked here.
absl::Status CheckImageViews(const json& doc, const std::vector<uint64_t>& buffer_sizes) {
  const json* images = Array(doc, "images");
  if (images == nullptr) return absl::OkStatus();
  const json* views = Array(doc, "bufferViews");
  const size_t view_count = views ? views->size() : 0;
  for (size_t i = 0; i < images->size(); ++i) {
    const std::string field = Item("images", i);
    if (!(*images)[i].is_object()) return absl::InvalidArgumentError(field + ": not an object");
    GS_ASSIGN_OR_RETURN(const std::optional<uint64_t> view_index,
                        GetUnsigned((*images)[i], "bufferView", field));
    if (!view_index) continue;
    GS_RETURN_IF_ERROR(CheckIndex(field + ".bufferView", static_cast<int64_t>(*view_index),
                                  view_count, "bufferViews"));
    const std::string view_field = Item("bufferViews", *view_index);
    const json& view = (*views)[*view_index];
    if (!view.is_object()) return absl::InvalidArgumentError(view_field + ": not an object");
    GS_ASSIGN_OR_RETURN(const std::optional<uint64_t> buffer,
                        GetUnsigned(view, "buffer", view_field));
    GS_ASSIGN_OR_RETURN(const std::optional<uint64_t> offset,
                        GetUnsigned(view, "byteOffset", view_field));
    GS_ASSIGN_OR_RETURN(const std::optional<uint64_t> length,
                        GetUnsigned(view, "byteLength", view_field));
    if (!buffer || !length) {
      return absl::InvalidArgumentError(view_field + ": buffer and byteLength are required");
    }
    GS_RETURN_IF_ERROR(CheckIndex(view_field + ".buffer", static_cast<int64_t>(*buffer),
                                  buffer_sizes.size(), "buffers"));
    uint64_t end = 0;
    if (!MulAdd(1, offset.value_or(0), *length, &end) || end > buffer_sizes[*buffer]) {
      return absl::InvalidArgumentError(absl::StrCat(
          view_field, ".byteLength: ", *length, " bytes at byteOffset ", offset.value_or(0),
          " overrun ", Item("buffers", *buffer), " (byteLength ", buffer_sizes[*buffer], ")"));
    }
  }
  return absl::OkStatus();
}

// ---- JSON types of the members gistream reads.
//
// tinygltf 2.7 reads a member of the wrong type as absent (a string where
// a number belongs, "scene": "x"), casts 2^32-1 to the int -1 ("no mesh")
// and a negative byteOffset to a huge size_t: the server would render
// something other than the file. Every member that gistream reads is
// checked here, before tinygltf sees the document, and named by its JSON
// path.

enum class Kind {
  kIndex,   // integer in [0, 2^31 - 1] (tinygltf stores int)
  kUint,    // integer in [0, 2^32] (byte offsets and lengths: a scene is < 4 GiB)
  kCount,   // any non-negative integer (counts; the budgets bound them later)
  kInt,     // any integer that fits an int (enums: componentType, mode, target)
  kNumber,  // finite number that fits a float
  kString,
  kBool,
  kObject,
  kNumbers,  // array of `count` kNumber
  kIndices,  // array of kIndex
};

struct Member {
  const char* key;
  Kind kind;
  size_t count = 0;  // kNumbers
};

constexpr uint64_t kMaxIndex = 2147483647;
constexpr uint64_t kMaxUint = 4294967296;

absl::Status TypeError(const std::string& path, const json& value, const char* expected) {
  std::string shown = value.dump();
  if (shown.size() > 40) shown = shown.substr(0, 40) + "...";
  return absl::InvalidArgumentError(absl::StrCat(path, ": ", shown, " is not ", expected));
}

absl::Status CheckValue(const std::string& path, const json& v, Kind kind, size_t count) {
  switch (kind) {
    case Kind::kIndex:
      if (!v.is_number_integer() ||
          (v.is_number_unsigned() ? v.get<uint64_t>() > kMaxIndex : v.get<int64_t>() < 0)) {
        return TypeError(path, v, "an index (an integer in [0, 2147483647])");
      }
      return absl::OkStatus();
    case Kind::kUint:
      if (!v.is_number_integer() ||
          (v.is_number_unsigned() ? v.get<uint64_t>() > kMaxUint : v.get<int64_t>() < 0)) {
        return TypeError(path, v, "an integer in [0, 4294967296]");
      }
      return absl::OkStatus();
    case Kind::kCount:
      if (!v.is_number_unsigned()) return TypeError(path, v, "a non-negative integer");
      return absl::OkStatus();
    case Kind::kInt:
      if (!v.is_number_integer() ||
          (v.is_number_unsigned() ? v.get<uint64_t>() > kMaxIndex
                                  : v.get<int64_t>() < -int64_t(kMaxIndex) - 1)) {
        return TypeError(path, v, "a 32-bit integer");
      }
      return absl::OkStatus();
    case Kind::kNumber:
      if (!v.is_number()) return TypeError(path, v, "a number");
      if (!(std::abs(v.get<double>()) <= kMaxFloat)) {
        return absl::InvalidArgumentError(
            absl::StrCat(path, ": ", v.dump(), " is out of range for a float"));
      }
      return absl::OkStatus();
    case Kind::kString: return v.is_string() ? absl::OkStatus() : TypeError(path, v, "a string");
    case Kind::kBool: return v.is_boolean() ? absl::OkStatus() : TypeError(path, v, "a boolean");
    case Kind::kObject: return v.is_object() ? absl::OkStatus() : TypeError(path, v, "an object");
    case Kind::kNumbers:
      if (!v.is_array()) return TypeError(path, v, "an array of numbers");
      if (v.size() != count) {
        return absl::InvalidArgumentError(
            absl::StrCat(path, ": ", v.size(), " values, expected ", count));
      }
      for (size_t i = 0; i < v.size(); ++i) {
        GS_RETURN_IF_ERROR(CheckValue(absl::StrCat(path, "[", i, "]"), v[i], Kind::kNumber, 0));
      }
      return absl::OkStatus();
    case Kind::kIndices:
      if (!v.is_array()) return TypeError(path, v, "an array of indices");
      for (size_t i = 0; i < v.size(); ++i) {
        GS_RETURN_IF_ERROR(CheckValue(absl::StrCat(path, "[", i, "]"), v[i], Kind::kIndex, 0));
      }
      return absl::OkStatus();
  }
  return absl::OkStatus();
}

// Checks the listed members of `object` (when present); `object` itself
// must be an object.
absl::Status CheckMembers(const std::string& path, const json& object,
                          std::initializer_list<Member> members) {
  if (!object.is_object()) return TypeError(path, object, "an object");
  for (const Member& m : members) {
    const auto it = object.find(m.key);
    if (it == object.end()) continue;
    GS_RETURN_IF_ERROR(CheckValue(absl::StrCat(path, ".", m.key), *it, m.kind, m.count));
  }
  return absl::OkStatus();
}

// `doc[key]`, when present, must be an array; `check` runs on each element.
template <typename F>
absl::Status ForEach(const std::string& path, const json& parent, const char* key, F check) {
  const auto it = parent.find(key);
  if (it == parent.end()) return absl::OkStatus();
  const std::string field = path.empty() ? key : absl::StrCat(path, ".", key);
  if (!it->is_array()) return TypeError(field, *it, "an array");
  for (size_t i = 0; i < it->size(); ++i) {
    GS_RETURN_IF_ERROR(check(absl::StrCat(field, "[", i, "]"), (*it)[i]));
  }
  return absl::OkStatus();
}

// An object member that, when present, must be an object checked by `check`.
template <typename F>
absl::Status IfObject(const std::string& path, const json& parent, const char* key, F check) {
  const auto it = parent.find(key);
  if (it == parent.end()) return absl::OkStatus();
  const std::string field = path.empty() ? key : absl::StrCat(path, ".", key);
  if (!it->is_object()) return TypeError(field, *it, "an object");
  return check(field, *it);
}

// KHR_texture_transform (any textureInfo's extensions), typed as the
// Khronos validator types it, though gistream does not apply it.
absl::Status CheckTextureTransform(const std::string& p, const json& v) {
  return CheckMembers(p, v,
                      {{"offset", Kind::kNumbers, 2},
                       {"rotation", Kind::kNumber},
                       {"scale", Kind::kNumbers, 2},
                       {"texCoord", Kind::kIndex}});
}

absl::Status CheckTextureInfoExtensions(const std::string& p, const json& v) {
  return IfObject(p, v, "KHR_texture_transform", CheckTextureTransform);
}

// A textureInfo: `index` is required (glTF 2.0 5.22), `extra` names the
// member a normal or occlusion textureInfo adds (scale, strength).
absl::Status CheckTextureInfoWith(const std::string& path, const json& info, const char* extra) {
  GS_RETURN_IF_ERROR(
      CheckMembers(path, info, {{"index", Kind::kIndex}, {"texCoord", Kind::kIndex}}));
  if (extra != nullptr) GS_RETURN_IF_ERROR(CheckMembers(path, info, {{extra, Kind::kNumber}}));
  if (!info.contains("index")) {
    return absl::InvalidArgumentError(absl::StrCat(path, ".index: missing (required)"));
  }
  return IfObject(path, info, "extensions", CheckTextureInfoExtensions);
}

absl::Status CheckTextureInfo(const std::string& path, const json& info) {
  return CheckTextureInfoWith(path, info, nullptr);
}
absl::Status CheckNormalTextureInfo(const std::string& path, const json& info) {
  return CheckTextureInfoWith(path, info, "scale");
}
absl::Status CheckOcclusionTextureInfo(const std::string& path, const json& info) {
  return CheckTextureInfoWith(path, info, "strength");
}

absl::Status CheckNumberValue(const std::string& p, const json& v) {
  return CheckValue(p, v, Kind::kNumber, 0);
}

absl::Status CheckMorphTarget(const std::string& p, const json& v) {
  if (!v.is_object()) return TypeError(p, v, "an object");
  for (const auto& [name, accessor] : v.items()) {
    GS_RETURN_IF_ERROR(CheckValue(absl::StrCat(p, ".", name), accessor, Kind::kIndex, 0));
  }
  return absl::OkStatus();
}

absl::Status CheckScene(const std::string& p, const json& v) {
  return CheckMembers(p, v, {{"nodes", Kind::kIndices}, {"name", Kind::kString}});
}

absl::Status CheckNodeLight(const std::string& p, const json& v) {
  return CheckMembers(p, v, {{"light", Kind::kIndex}});
}

absl::Status CheckNodeExtensions(const std::string& p, const json& v) {
  return IfObject(p, v, "KHR_lights_punctual", CheckNodeLight);
}

absl::Status CheckNode(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v,
                                  {{"mesh", Kind::kIndex},
                                   {"camera", Kind::kIndex},
                                   {"skin", Kind::kIndex},
                                   {"children", Kind::kIndices},
                                   {"translation", Kind::kNumbers, 3},
                                   {"rotation", Kind::kNumbers, 4},
                                   {"scale", Kind::kNumbers, 3},
                                   {"matrix", Kind::kNumbers, 16},
                                   {"name", Kind::kString}}));
  GS_RETURN_IF_ERROR(ForEach(p, v, "weights", CheckNumberValue));
  return IfObject(p, v, "extensions", CheckNodeExtensions);
}

absl::Status CheckPrimitive(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v,
                                  {{"attributes", Kind::kObject},
                                   {"indices", Kind::kIndex},
                                   {"material", Kind::kIndex},
                                   {"mode", Kind::kInt}}));
  const auto attributes = v.find("attributes");
  if (attributes == v.end()) return absl::OkStatus();
  for (const auto& [name, accessor] : attributes->items()) {
    GS_RETURN_IF_ERROR(
        CheckValue(absl::StrCat(p, ".attributes.", name), accessor, Kind::kIndex, 0));
  }
  return ForEach(p, v, "targets", CheckMorphTarget);
}

absl::Status CheckMesh(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v, {{"name", Kind::kString}}));
  GS_RETURN_IF_ERROR(ForEach(p, v, "weights", CheckNumberValue));
  return ForEach(p, v, "primitives", CheckPrimitive);
}

absl::Status CheckSkin(const std::string& p, const json& v) {
  return CheckMembers(p, v,
                      {{"joints", Kind::kIndices},
                       {"inverseBindMatrices", Kind::kIndex},
                       {"skeleton", Kind::kIndex},
                       {"name", Kind::kString}});
}

// tinygltf drops a channel without a target node (and with it the numbering
// our messages use), so every channel must name its sampler and node.
absl::Status CheckChannelTarget(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v, {{"node", Kind::kIndex}, {"path", Kind::kString}}));
  if (!v.contains("node")) return absl::InvalidArgumentError(p + ".node: missing");
  if (!v.contains("path")) return absl::InvalidArgumentError(p + ".path: missing");
  return absl::OkStatus();
}

absl::Status CheckChannel(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v, {{"sampler", Kind::kIndex}, {"target", Kind::kObject}}));
  if (!v.contains("sampler")) return absl::InvalidArgumentError(p + ".sampler: missing");
  if (!v.contains("target")) return absl::InvalidArgumentError(p + ".target: missing");
  return CheckChannelTarget(p + ".target", v["target"]);
}

absl::Status CheckAnimationSampler(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(
      p, v, {{"input", Kind::kIndex}, {"output", Kind::kIndex}, {"interpolation", Kind::kString}}));
  if (!v.contains("input")) return absl::InvalidArgumentError(p + ".input: missing");
  if (!v.contains("output")) return absl::InvalidArgumentError(p + ".output: missing");
  return absl::OkStatus();
}

absl::Status CheckAnimation(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v, {{"name", Kind::kString}}));
  GS_RETURN_IF_ERROR(ForEach(p, v, "channels", CheckChannel));
  return ForEach(p, v, "samplers", CheckAnimationSampler);
}

absl::Status CheckAccessor(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v,
                                  {{"bufferView", Kind::kIndex},
                                   {"byteOffset", Kind::kUint},
                                   {"componentType", Kind::kInt},
                                   {"count", Kind::kCount},
                                   {"type", Kind::kString},
                                   {"normalized", Kind::kBool},
                                   {"sparse", Kind::kObject}}));
  GS_RETURN_IF_ERROR(ForEach(p, v, "min", CheckNumberValue));
  return ForEach(p, v, "max", CheckNumberValue);
}

absl::Status CheckBufferView(const std::string& p, const json& v) {
  return CheckMembers(p, v,
                      {{"buffer", Kind::kIndex},
                       {"byteOffset", Kind::kUint},
                       {"byteLength", Kind::kUint},
                       {"byteStride", Kind::kUint},
                       {"target", Kind::kInt}});
}

absl::Status CheckBuffer(const std::string& p, const json& v) {
  return CheckMembers(p, v, {{"byteLength", Kind::kUint}, {"uri", Kind::kString}});
}

absl::Status CheckPbr(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v,
                                  {{"baseColorFactor", Kind::kNumbers, 4},
                                   {"metallicFactor", Kind::kNumber},
                                   {"roughnessFactor", Kind::kNumber}}));
  GS_RETURN_IF_ERROR(IfObject(p, v, "baseColorTexture", CheckTextureInfo));
  return IfObject(p, v, "metallicRoughnessTexture", CheckTextureInfo);
}

absl::Status CheckEmissiveStrength(const std::string& p, const json& v) {
  return CheckMembers(p, v, {{"emissiveStrength", Kind::kNumber}});
}

absl::Status CheckMaterialExtensions(const std::string& p, const json& v) {
  return IfObject(p, v, "KHR_materials_emissive_strength", CheckEmissiveStrength);
}

absl::Status CheckMaterial(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v,
                                  {{"name", Kind::kString},
                                   {"emissiveFactor", Kind::kNumbers, 3},
                                   {"doubleSided", Kind::kBool},
                                   {"alphaMode", Kind::kString},
                                   {"alphaCutoff", Kind::kNumber}}));
  GS_RETURN_IF_ERROR(IfObject(p, v, "emissiveTexture", CheckTextureInfo));
  GS_RETURN_IF_ERROR(IfObject(p, v, "normalTexture", CheckNormalTextureInfo));
  GS_RETURN_IF_ERROR(IfObject(p, v, "occlusionTexture", CheckOcclusionTextureInfo));
  GS_RETURN_IF_ERROR(IfObject(p, v, "pbrMetallicRoughness", CheckPbr));
  return IfObject(p, v, "extensions", CheckMaterialExtensions);
}

absl::Status CheckTexture(const std::string& p, const json& v) {
  return CheckMembers(p, v, {{"source", Kind::kIndex}, {"sampler", Kind::kIndex}});
}

absl::Status CheckSampler(const std::string& p, const json& v) {
  return CheckMembers(p, v,
                      {{"magFilter", Kind::kInt},
                       {"minFilter", Kind::kInt},
                       {"wrapS", Kind::kInt},
                       {"wrapT", Kind::kInt},
                       {"name", Kind::kString}});
}

absl::Status CheckImage(const std::string& p, const json& v) {
  return CheckMembers(p, v,
                      {{"uri", Kind::kString},
                       {"bufferView", Kind::kIndex},
                       {"mimeType", Kind::kString},
                       {"name", Kind::kString}});
}

absl::Status CheckPerspective(const std::string& p, const json& v) {
  return CheckMembers(p, v,
                      {{"yfov", Kind::kNumber},
                       {"znear", Kind::kNumber},
                       {"zfar", Kind::kNumber},
                       {"aspectRatio", Kind::kNumber}});
}

absl::Status CheckCamera(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v, {{"type", Kind::kString}, {"name", Kind::kString}}));
  return IfObject(p, v, "perspective", CheckPerspective);
}

absl::Status CheckSpot(const std::string& p, const json& v) {
  return CheckMembers(p, v, {{"innerConeAngle", Kind::kNumber}, {"outerConeAngle", Kind::kNumber}});
}

absl::Status CheckLight(const std::string& p, const json& v) {
  GS_RETURN_IF_ERROR(CheckMembers(p, v,
                                  {{"type", Kind::kString},
                                   {"name", Kind::kString},
                                   {"color", Kind::kNumbers, 3},
                                   {"intensity", Kind::kNumber},
                                   {"range", Kind::kNumber}}));
  return IfObject(p, v, "spot", CheckSpot);
}

absl::Status CheckLightsExtension(const std::string& p, const json& v) {
  return ForEach(p, v, "lights", CheckLight);
}

absl::Status CheckRootExtensions(const std::string& p, const json& v) {
  return IfObject(p, v, "KHR_lights_punctual", CheckLightsExtension);
}

absl::Status CheckTypes(const json& doc) {
  if (const auto scene = doc.find("scene"); scene != doc.end()) {
    GS_RETURN_IF_ERROR(CheckValue("scene", *scene, Kind::kIndex, 0));
  }
  GS_RETURN_IF_ERROR(ForEach("", doc, "scenes", CheckScene));
  GS_RETURN_IF_ERROR(ForEach("", doc, "nodes", CheckNode));
  GS_RETURN_IF_ERROR(ForEach("", doc, "meshes", CheckMesh));
  GS_RETURN_IF_ERROR(ForEach("", doc, "accessors", CheckAccessor));
  GS_RETURN_IF_ERROR(ForEach("", doc, "bufferViews", CheckBufferView));
  GS_RETURN_IF_ERROR(ForEach("", doc, "buffers", CheckBuffer));
  GS_RETURN_IF_ERROR(ForEach("", doc, "materials", CheckMaterial));
  GS_RETURN_IF_ERROR(ForEach("", doc, "textures", CheckTexture));
  GS_RETURN_IF_ERROR(ForEach("", doc, "samplers", CheckSampler));
  GS_RETURN_IF_ERROR(ForEach("", doc, "images", CheckImage));
  GS_RETURN_IF_ERROR(ForEach("", doc, "cameras", CheckCamera));
  GS_RETURN_IF_ERROR(ForEach("", doc, "skins", CheckSkin));
  GS_RETURN_IF_ERROR(ForEach("", doc, "animations", CheckAnimation));
  return IfObject("", doc, "extensions", CheckRootExtensions);
}

}  // namespace

absl::StatusOr<Container> SplitContainer(std::span<const uint8_t> bytes) {
  Container c;
  if (bytes.size() < 4 || ReadU32(bytes, 0) != kGlbMagic) {
    // Not a glb: it must be JSON text, which starts with '{' (after
    // whitespace or a UTF-8 byte order mark).
    size_t i = 0;
    if (bytes.size() >= 3 && std::memcmp(bytes.data(), "\xef\xbb\xbf", 3) == 0) i = 3;
    while (i < bytes.size() && std::strchr(" \t\r\n", bytes[i]) != nullptr && bytes[i] != 0) ++i;
    if (i == bytes.size() || bytes[i] != '{') {
      return absl::InvalidArgumentError(
          absl::StrCat("scene: neither a glb (magic \"glTF\") nor glTF JSON (data starts with ",
                       HexPrefix(bytes), ")"));
    }
    c.json = bytes;
    return c;
  }
  c.binary = true;
  if (bytes.size() < 20) {
    return absl::InvalidArgumentError(absl::StrCat("glb: truncated: ", bytes.size(),
                                                   " bytes, the header and first chunk header "
                                                   "need 20"));
  }
  const uint32_t version = ReadU32(bytes, 4);
  const uint32_t length = ReadU32(bytes, 8);
  if (version != 2) {
    return absl::InvalidArgumentError(
        absl::StrCat("glb.version: ", version, " is not supported (only 2)"));
  }
  if (length != bytes.size()) {
    return absl::InvalidArgumentError(absl::StrCat("glb.length: header says ", length,
                                                   " bytes but the data has ", bytes.size(),
                                                   length > bytes.size() ? " (truncated)" : ""));
  }
  const uint64_t json_length = ReadU32(bytes, 12);
  if (ReadU32(bytes, 16) != kChunkJson) {
    return absl::InvalidArgumentError("glb.chunks[0].type: the first chunk is not JSON");
  }
  if (json_length == 0 || 20 + json_length > length) {
    return absl::InvalidArgumentError(absl::StrCat("glb.chunks[0].length: ", json_length,
                                                   " bytes do not fit in the ", length - 20,
                                                   " bytes after the header"));
  }
  c.json = bytes.subspan(20, json_length);
  const uint64_t rest = length - 20 - json_length;
  if (rest == 0) return c;
  if (rest < 12) {
    return absl::InvalidArgumentError(
        absl::StrCat("glb.chunks[1]: ", rest, " trailing bytes are too few for a chunk"));
  }
  const uint64_t bin_offset = 20 + json_length;
  const uint64_t bin_length = ReadU32(bytes, bin_offset);
  if (ReadU32(bytes, bin_offset + 4) != kChunkBin) {
    return absl::InvalidArgumentError("glb.chunks[1].type: the second chunk is not BIN");
  }
  if (bin_length < 4 || bin_length % 4 != 0 || bin_length > rest - 8) {
    return absl::InvalidArgumentError(absl::StrCat("glb.chunks[1].length: ", bin_length,
                                                   " is not a multiple of 4 that fits in the ",
                                                   rest - 8, " bytes left"));
  }
  c.bin_size = bin_length;
  return c;
}

absl::Status PreflightJson(const Container& container, const ImportOptions& options) {
  GS_ASSIGN_OR_RETURN(const json doc, ParseJson(container.json));
  if (!doc.is_object()) {
    return absl::InvalidArgumentError("scene JSON: the top level is not an object");
  }
  GS_RETURN_IF_ERROR(CheckAsset(doc));
  GS_RETURN_IF_ERROR(CheckRequiredExtensions(doc));
  if (const json* nodes = Array(doc, "nodes");
      nodes != nullptr && nodes->size() > options.limits.max_nodes) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "nodes: ", nodes->size(), " nodes exceed the limit of ", options.limits.max_nodes));
  }
  if (const json* materials = Array(doc, "materials");
      materials != nullptr && materials->size() > options.limits.max_materials) {
    return absl::ResourceExhaustedError(
        absl::StrCat("materials: ", materials->size(), " materials exceed the limit of ",
                     options.limits.max_materials, " (--max-materials)"));
  }
  GS_RETURN_IF_ERROR(CheckTypes(doc));
  GS_RETURN_IF_ERROR(CheckPrimitives(doc));
  GS_ASSIGN_OR_RETURN(const std::vector<uint64_t> buffer_sizes,
                      CheckBuffers(doc, container, options));
  return CheckImageViews(doc, buffer_sizes);
}

}  // namespace gistream::gltf
