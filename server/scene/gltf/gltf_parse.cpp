#include "scene/gltf/gltf_parse.h"

#include <filesystem>
#include <string>
#include <vector>

#include "scene/gltf/scene_files.h"
#include "util/log.h"

namespace gistream::gltf {
namespace {

struct FsContext {
  std::filesystem::path base_dir;
  uint64_t* budget;
  absl::Status error;  // the first refusal, reported instead of tinygltf's text
};

// tinygltf passes the URI already percent-decoded (possibly prefixed "./").
bool FileExists(const std::string& path, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  const absl::StatusOr<std::filesystem::path> resolved =
      ResolveScenePath(ctx->base_dir, path, "buffers[].uri");
  if (!resolved.ok()) {
    if (ctx->error.ok()) ctx->error = resolved.status();
    return false;
  }
  std::error_code ec;
  return std::filesystem::is_regular_file(*resolved, ec);
}

std::string ExpandFilePath(const std::string& path, void*) { return path; }

bool ReadWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  const absl::StatusOr<std::filesystem::path> resolved =
      ResolveScenePath(ctx->base_dir, path, "buffers[].uri");
  absl::StatusOr<std::vector<uint8_t>> bytes =
      resolved.ok() ? ReadFileLimited(*resolved, *ctx->budget, "buffers[].uri")
                    : absl::StatusOr<std::vector<uint8_t>>(resolved.status());
  if (!bytes.ok()) {
    if (ctx->error.ok()) ctx->error = bytes.status();
    if (err != nullptr) *err += std::string(bytes.status().message());
    return false;
  }
  *ctx->budget -= bytes->size();
  *out = std::move(*bytes);
  return true;
}

bool RefuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err != nullptr) *err += "writing files is disabled";
  return false;
}

// Keeps data: URI images encoded for DecodeImage. Buffer-view images are
// read later from the validated view: `bytes` is not touched for them.
bool KeepEncodedImage(tinygltf::Image* image, int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0) return true;
  image->image.assign(bytes, bytes + size);
  return true;
}

}  // namespace

absl::StatusOr<tinygltf::Model> ParseModel(std::span<const uint8_t> bytes,
                                           const Container& container, const ImportOptions& options,
                                           uint64_t* budget) {
  FsContext ctx{options.base_dir, budget, absl::OkStatus()};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&FileExists, &ExpandFilePath, &ReadWholeFile, &RefuseWrite, &ctx});
  loader.SetImageLoader(&KeepEncodedImage, nullptr);

  tinygltf::Model model;
  std::string err;
  std::string warn;
  bool ok = false;
  try {
    // An empty base_dir: our callbacks resolve against options.base_dir.
    if (container.binary) {
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                       static_cast<unsigned int>(bytes.size()), "");
    } else {
      ok = loader.LoadASCIIFromString(&model, &err, &warn,
                                      reinterpret_cast<const char*>(container.json.data()),
                                      static_cast<unsigned int>(container.json.size()), "");
    }
  } catch (const std::exception& e) {
    // tinygltf 2.7 throws from std::vector::at on some empty inputs.
    return absl::InvalidArgumentError(absl::StrCat("scene: malformed glTF: ", e.what()));
  }
  if (!ctx.error.ok()) return ctx.error;
  if (!ok) {
    while (!err.empty() && err.back() == '\n') err.pop_back();
    return absl::InvalidArgumentError(absl::StrCat("scene: malformed glTF: ", err));
  }
  if (!warn.empty()) Log(LogLevel::kDebug, absl::StrCat("tinygltf: ", warn));
  return model;
}

}  // namespace gistream::gltf
