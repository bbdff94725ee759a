#include "scene/gltf_preflight.h"

#include <cstring>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "encode/image_format.h"
#include "scene/gltf_util.h"
#include "scene/scene_files.h"

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

const std::set<std::string, std::less<>> kUnderstoodExtensions = {
    "KHR_lights_punctual", "KHR_materials_emissive_strength"};

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
          " is not supported (supported: KHR_lights_punctual, KHR_materials_emissive_strength)"));
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
  GS_RETURN_IF_ERROR(CheckPrimitives(doc));
  GS_ASSIGN_OR_RETURN(const std::vector<uint64_t> buffer_sizes,
                      CheckBuffers(doc, container, options));
  return CheckImageViews(doc, buffer_sizes);
}

}  // namespace gistream::gltf
