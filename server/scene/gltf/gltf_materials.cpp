#include <cmath>
#include <initializer_list>
#include <map>
#include <utility>
#include <string>

#include <absl/strings/str_cat.h>
#include <absl/strings/str_join.h>

#include "scene/gltf/gltf_stages.h"
#include "scene/gltf/gltf_util.h"
#include "scene/gltf/image_decode.h"
#include "scene/magnitude_limits.h"
#include "scene/gltf/scene_files.h"

namespace gistream::gltf {
namespace {

// A number of a KHR_texture_transform object (the preflight typed it), or
// `fallback` when absent; finite and within +-1e6, else the field is named.
absl::StatusOr<double> TransformNumber(const tinygltf::Value& object, const char* key, int index,
                                       double fallback, const std::string& field) {
  if (!object.Has(key)) return fallback;
  const tinygltf::Value& v = index < 0 ? object.Get(key) : object.Get(key).Get(index);
  const double x = v.IsNumber() ? v.GetNumberAsDouble() : fallback;
  const std::string name =
      index < 0 ? absl::StrCat(field, ".", key) : absl::StrCat(field, ".", key, "[", index, "]");
  GS_RETURN_IF_ERROR(CheckNumber(name, x, -1e6, 1e6));
  return x;
}

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) (uv, 1), R's
// rows (cos, sin) and (-sin, cos): the extension's GLSL, mat3(cos, sin, 0,
// -sin, cos, 0, 0, 0, 1), read row by row. Read as GLSL's column-major
// constructor it turns the other way, which the Khronos test model
// (TextureTransformTest, assimp-testmodels' glTF2/textureTransform) marks
// red: "rotation applied in the opposite direction". The identity without
// the extension.
absl::StatusOr<UvTransform> ReadUvTransform(const tinygltf::TextureInfo& info,
                                            const std::string& field) {
  UvTransform out;
  const auto it = info.extensions.find("KHR_texture_transform");
  if (it == info.extensions.end() || !it->second.IsObject()) return out;
  const tinygltf::Value& t = it->second;
  const std::string f = field + ".extensions.KHR_texture_transform";
  GS_ASSIGN_OR_RETURN(const double ox, TransformNumber(t, "offset", 0, 0.0, f));
  GS_ASSIGN_OR_RETURN(const double oy, TransformNumber(t, "offset", 1, 0.0, f));
  GS_ASSIGN_OR_RETURN(const double rotation, TransformNumber(t, "rotation", -1, 0.0, f));
  GS_ASSIGN_OR_RETURN(const double sx, TransformNumber(t, "scale", 0, 1.0, f));
  GS_ASSIGN_OR_RETURN(const double sy, TransformNumber(t, "scale", 1, 1.0, f));
  const double c = std::cos(rotation), s = std::sin(rotation);
  out.u = glm::vec3(float(c * sx), float(s * sy), float(ox));
  out.v = glm::vec3(float(-s * sx), float(c * sy), float(oy));
  return out;
}

// One of a sampler's enums (glTF 2.0 5.26): `value` must be one of
// `allowed`; -1 (tinygltf's "absent") gives `absent`.
absl::StatusOr<int> SamplerEnum(int value, std::initializer_list<int> allowed, int absent,
                                const std::string& field) {
  if (value == -1) return absent;
  for (int a : allowed) {
    if (value == a) return value;
  }
  return absl::InvalidArgumentError(
      absl::StrCat(field, ": ", value, " is not one of ", absl::StrJoin(allowed, ", ")));
}

// The sampler texture `texture` names (glTF 2.0 5.26; repeat and the
// renderer's filters without one), its values checked.
absl::StatusOr<TextureSampler> ReadSampler(const tinygltf::Model& model, int texture) {
  TextureSampler out;
  const int index = model.textures[size_t(texture)].sampler;
  if (index == -1) return out;
  const std::string tex_field = Item("textures", size_t(texture)) + ".sampler";
  GS_RETURN_IF_ERROR(CheckIndex(tex_field, index, model.samplers.size(), "samplers"));
  const tinygltf::Sampler& in = model.samplers[size_t(index)];
  const std::string field = Item("samplers", size_t(index));
  using S = TextureSampler;
  const std::initializer_list<int> wraps = {S::kRepeat, S::kClampToEdge, S::kMirroredRepeat};
  GS_ASSIGN_OR_RETURN(out.wrap_s, SamplerEnum(in.wrapS, wraps, S::kRepeat, field + ".wrapS"));
  GS_ASSIGN_OR_RETURN(out.wrap_t, SamplerEnum(in.wrapT, wraps, S::kRepeat, field + ".wrapT"));
  GS_ASSIGN_OR_RETURN(out.mag_filter, SamplerEnum(in.magFilter, {S::kNearest, S::kLinear}, 0,
                                                  field + ".magFilter"));
  GS_ASSIGN_OR_RETURN(out.min_filter,
                      SamplerEnum(in.minFilter, {S::kNearest, S::kLinear, 9984, 9985, 9986, 9987},
                                  0, field + ".minFilter"));
  return out;
}

// Decodes each image at most once, in the order materials first use them.
class ImageLoader {
 public:
  ImageLoader(const tinygltf::Model& model, const ImportOptions& options, uint64_t* budget,
              std::vector<Image>* images, std::vector<std::string>* warnings)
      : model_(model), options_(options), budget_(budget), images_(images), warnings_(warnings) {}

  // Scene image index for the texture `info` names; -1 when none. `srgb`:
  // colour (sRGB-encoded) or data (linear, e.g. metallic-roughness); an image
  // used both ways is decoded once per way. `uv`: its KHR_texture_transform;
  // `sampler`: its texture's sampler.
  absl::StatusOr<int> Texture(const tinygltf::TextureInfo& info, const std::string& field,
                              UvTransform* uv, TextureSampler* sampler, bool srgb = true) {
    if (info.index == -1) return -1;
    GS_RETURN_IF_ERROR(
        CheckIndex(field + ".index", info.index, model_.textures.size(), "textures"));
    GS_ASSIGN_OR_RETURN(*uv, ReadUvTransform(info, field));
    GS_ASSIGN_OR_RETURN(*sampler, ReadSampler(model_, info.index));
    // The extension's texCoord overrides the textureInfo's.
    int tex_coord = info.texCoord;
    if (const auto it = info.extensions.find("KHR_texture_transform");
        it != info.extensions.end() && it->second.IsObject() && it->second.Has("texCoord") &&
        it->second.Get("texCoord").IsInt()) {
      tex_coord = it->second.Get("texCoord").GetNumberAsInt();
    }
    if (tex_coord != 0) {
      // Only the first texture coordinate set reaches the GPU: the material
      // renders with its factors alone there, and the client is told.
      warnings_->push_back(absl::StrCat(field, ".texCoord: ", tex_coord,
                                        ": only TEXCOORD_0 is read; the texture is ignored (the "
                                        "material renders with its factors)"));
      return -1;
    }
    const int source = model_.textures[size_t(info.index)].source;
    const auto known = decoded_.find({source, srgb});
    if (known != decoded_.end()) return known->second;
    GS_ASSIGN_OR_RETURN(Image image, Decode(source));
    image.srgb = srgb;
    const int index = static_cast<int>(images_->size());
    images_->push_back(std::move(image));
    decoded_[{source, srgb}] = index;
    return index;
  }

 private:
  absl::StatusOr<Image> Decode(int source) {
    const tinygltf::Image& in = model_.images[size_t(source)];
    const std::string field = Item("images", source);
    std::vector<uint8_t> file;
    std::span<const uint8_t> bytes;
    if (in.bufferView >= 0) {
      GS_RETURN_IF_ERROR(CheckIndex(field + ".bufferView", in.bufferView, model_.bufferViews.size(),
                                    "bufferViews"));
      // ValidateBufferViews has checked the view against its buffer.
      const tinygltf::BufferView& view = model_.bufferViews[size_t(in.bufferView)];
      bytes = std::span<const uint8_t>(model_.buffers[size_t(view.buffer)].data)
                  .subspan(view.byteOffset, view.byteLength);
    } else if (!in.uri.empty()) {
      GS_ASSIGN_OR_RETURN(const std::filesystem::path path,
                          ResolveSceneUri(options_.base_dir, in.uri, field + ".uri"));
      GS_ASSIGN_OR_RETURN(file, ReadFileLimited(path, *budget_, field + ".uri"));
      *budget_ -= file.size();
      if (options_.memory != nullptr) {
        GS_RETURN_IF_ERROR(options_.memory->Reserve(
            file.size(), absl::StrCat(field, ".uri: ", file.size(), " bytes read")));
      }
      bytes = file;
    } else {
      bytes = in.image;  // a data: URI, decoded by tinygltf
    }
    GS_ASSIGN_OR_RETURN(Image image, DecodeImage(bytes, ImageKind::kTexture, options_.limits, field,
                                                 options_.memory));
    image.name = in.name;
    const uint64_t pixels = uint64_t(image.width) * uint64_t(image.height);
    if (pixels > options_.limits.max_total_image_pixels - total_pixels_) {
      return absl::ResourceExhaustedError(
          absl::StrCat(field, ": decoded images exceed the limit of ",
                       options_.limits.max_total_image_pixels, " pixels per scene"));
    }
    total_pixels_ += pixels;
    return image;
  }

  const tinygltf::Model& model_;
  const ImportOptions& options_;
  uint64_t* budget_;
  std::vector<Image>* images_;
  std::vector<std::string>* warnings_;
  std::map<std::pair<int, bool>, int> decoded_;  // (glTF image, srgb) -> scene image
  uint64_t total_pixels_ = 0;
};

absl::StatusOr<float> EmissiveStrength(const tinygltf::Material& in, const std::string& field) {
  const auto ext = in.extensions.find("KHR_materials_emissive_strength");
  if (ext == in.extensions.end()) return 1.0f;
  const std::string strength_field =
      field + ".extensions.KHR_materials_emissive_strength.emissiveStrength";
  if (!ext->second.IsObject()) return absl::InvalidArgumentError(strength_field + ": missing");
  const tinygltf::Value& value = ext->second.Get("emissiveStrength");
  if (!value.IsNumber()) {
    if (!ext->second.Has("emissiveStrength")) return 1.0f;  // the extension's default
    return absl::InvalidArgumentError(strength_field + ": not a number");
  }
  const double strength = value.GetNumberAsDouble();
  GS_RETURN_IF_ERROR(CheckNumber(strength_field, strength, 0.0, kMaxRadiance));
  return static_cast<float>(strength);
}

absl::StatusOr<Material> ReadMaterial(const tinygltf::Material& in, const std::string& field,
                                      ImageLoader* images) {
  Material out;
  out.name = in.name;
  const tinygltf::PbrMetallicRoughness& pbr = in.pbrMetallicRoughness;
  const std::string pbr_field = field + ".pbrMetallicRoughness";
  if (pbr.baseColorFactor.size() != 4) {
    return absl::InvalidArgumentError(absl::StrCat(
        pbr_field, ".baseColorFactor: ", pbr.baseColorFactor.size(), " values, expected 4"));
  }
  // Albedo above 1 would create energy.
  GS_RETURN_IF_ERROR(CheckRange(pbr_field + ".baseColorFactor", pbr.baseColorFactor, 0.0, 1.0));
  out.base_color_factor = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1],
                                    pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
  GS_ASSIGN_OR_RETURN(out.base_color_texture,
                      images->Texture(pbr.baseColorTexture, pbr_field + ".baseColorTexture",
                                      &out.base_color_uv, &out.base_color_sampler));
  GS_RETURN_IF_ERROR(CheckNumber(pbr_field + ".metallicFactor", pbr.metallicFactor, 0.0, 1.0));
  GS_RETURN_IF_ERROR(CheckNumber(pbr_field + ".roughnessFactor", pbr.roughnessFactor, 0.0, 1.0));
  out.metallic_factor = static_cast<float>(pbr.metallicFactor);
  out.roughness_factor = static_cast<float>(pbr.roughnessFactor);
  GS_ASSIGN_OR_RETURN(
      out.metallic_roughness_texture,
      images->Texture(pbr.metallicRoughnessTexture, pbr_field + ".metallicRoughnessTexture",
                      &out.metallic_roughness_uv, &out.metallic_roughness_sampler,
                      /*srgb=*/false));
  const DielectricFresnel fresnel = ClassifyDielectricSpecular(in);
  out.specular_f0 = fresnel.f0;
  out.specular_f90 = fresnel.f90;
  if (fresnel.kind == DielectricSpecular::kNone) {
    // KHR_materials_specular without a specular layer on a non-metal
    // (exporters write diffuse walls so, with ior 1): Lambertian, which the
    // BRDF is exactly at metallic 0 and roughness 1 (brdf.glsl); the
    // texture's roughness would take that away, its metallic is 0 anyway.
    out.roughness_factor = 1.0f;
    out.metallic_roughness_texture = -1;
  }

  if (!in.emissiveFactor.empty()) {
    if (in.emissiveFactor.size() != 3) {
      return absl::InvalidArgumentError(absl::StrCat(
          field, ".emissiveFactor: ", in.emissiveFactor.size(), " values, expected 3"));
    }
    GS_RETURN_IF_ERROR(CheckRange(field + ".emissiveFactor", in.emissiveFactor, 0.0, 1.0));
    out.emissive_factor =
        glm::vec3(in.emissiveFactor[0], in.emissiveFactor[1], in.emissiveFactor[2]);
  }
  GS_ASSIGN_OR_RETURN(out.emissive_strength, EmissiveStrength(in, field));
  GS_ASSIGN_OR_RETURN(out.emissive_texture,
                      images->Texture(in.emissiveTexture, field + ".emissiveTexture",
                                      &out.emissive_uv, &out.emissive_sampler));
  out.double_sided = in.doubleSided;
  return out;
}

}  // namespace

absl::Status ImportMaterials(const tinygltf::Model& model, const ImportOptions& options,
                             uint64_t* budget, Scene* scene) {
  // Every texture must name an image and a valid sampler, used or not.
  for (size_t t = 0; t < model.textures.size(); ++t) {
    const int source = model.textures[t].source;
    const std::string field = Item("textures", t) + ".source";
    if (source == -1) return absl::InvalidArgumentError(field + ": missing (no image)");
    GS_RETURN_IF_ERROR(CheckIndex(field, source, model.images.size(), "images"));
    GS_RETURN_IF_ERROR(ReadSampler(model, int(t)).status());  // and a valid sampler
  }
  ImageLoader images(model, options, budget, &scene->images, &scene->import_warnings);
  for (size_t m = 0; m < model.materials.size(); ++m) {
    GS_ASSIGN_OR_RETURN(Material material,
                        ReadMaterial(model.materials[m], Item("materials", m), &images));
    scene->materials.push_back(std::move(material));
  }
  return absl::OkStatus();
}

}  // namespace gistream::gltf
