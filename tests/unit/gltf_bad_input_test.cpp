// The malformed corpus: containers, JSON, buffers, accessors, images and
// limits. Each case checks the status code and that the message names the
// offending field.
#include <gtest/gtest.h>

#include "encode/encode.h"
#include "gltf_test_util.h"
#include "scene/gltf/gltf_import.h"

namespace gistream {
namespace gltf_bad_input_test {

using testing::AddQuadMesh;
using testing::Bytes;
using testing::Import;
using testing::TestGltf;

TestGltf Quad() {
  TestGltf g;
  g.AddRoot({{"mesh", AddQuadMesh(&g)}});
  return g;
}

// ------------------------------------------------------------- containers

TEST(BadInput, TruncatedGlb) {
  std::vector<uint8_t> glb = Quad().ToGlb();
  glb.resize(glb.size() / 2);
  EXPECT_ERROR(Import(glb), kInvalidArgument, "glb.length: header says");
  glb.resize(10);
  EXPECT_ERROR(Import(glb), kInvalidArgument, "glb: truncated: 10 bytes");
}

TEST(BadInput, GlbWithBadMagic) {
  std::vector<uint8_t> glb = Quad().ToGlb();
  glb[3] = 'X';
  EXPECT_ERROR(Import(glb), kInvalidArgument, "neither a glb (magic \"glTF\") nor glTF JSON");
}

TEST(BadInput, GlbWithBadLength) {
  std::vector<uint8_t> glb = Quad().ToGlb();
  glb[8] += 4;  // header length beyond the data
  EXPECT_ERROR(Import(glb), kInvalidArgument, "(truncated)");
  glb[8] -= 8;  // shorter than the data
  EXPECT_ERROR(Import(glb), kInvalidArgument, "glb.length:");
}

TEST(BadInput, GlbChunks) {
  const std::vector<uint8_t> good = Quad().ToGlb();
  std::vector<uint8_t> glb = good;
  glb[12] = 0xff;  // JSON chunk length
  glb[13] = 0xff;
  EXPECT_ERROR(Import(glb), kInvalidArgument, "glb.chunks[0].length:");
  glb = good;
  glb[16] = 'X';  // JSON chunk type
  EXPECT_ERROR(Import(glb), kInvalidArgument, "glb.chunks[0].type");
  glb = good;
  glb[4] = 1;
  EXPECT_ERROR(Import(glb), kInvalidArgument, "glb.version: 1");
  // BIN chunk length past the end.
  const uint32_t json_length = good[12] | good[13] << 8 | good[14] << 16 | uint32_t(good[15]) << 24;
  glb = good;
  glb[20 + json_length + 1] += 1;
  EXPECT_ERROR(Import(glb), kInvalidArgument, "glb.chunks[1].length:");
}

TEST(BadInput, GlbBufferLargerThanBinChunk) {
  TestGltf g = Quad();
  nlohmann::json d = g.doc;
  d["buffers"] = {{{"byteLength", g.bin.size() + 100}}};
  EXPECT_ERROR(Import(testing::PackGlb(d.dump(), g.bin)), kInvalidArgument,
               "buffers[0].byteLength:");
}

TEST(BadInput, NotGltfAtAll) {
  EXPECT_ERROR(Import({}), kInvalidArgument, "scene: neither a glb");
  EXPECT_ERROR(Import(Bytes("BM6\x01")), kInvalidArgument, "42 4d 36 01");
}

// ------------------------------------------------------------------ JSON

TEST(BadInput, MalformedJson) {
  EXPECT_ERROR(Import(Bytes(R"({"asset": {"version": "2.0"}, "nodes": [{"name": )")),
               kInvalidArgument, "nodes[0].name: malformed JSON at byte");
  EXPECT_ERROR(Import(Bytes(R"({"asset": {"version": "2.0"}} trailing)")), kInvalidArgument,
               "malformed JSON");
}

TEST(BadInput, JsonNestedTooDeep) {
  std::string deep = R"({"asset": {"version": "2.0"}, "extras": )";
  for (int i = 0; i < 200; ++i) deep += "[";
  for (int i = 0; i < 200; ++i) deep += "]";
  deep += "}";
  EXPECT_ERROR(Import(Bytes(deep)), kInvalidArgument, "nested deeper than 64 levels");
}

TEST(BadInput, AssetVersion) {
  TestGltf g = Quad();
  g.doc["asset"]["version"] = "1.0";
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "asset.version: '1.0'");
  g.doc.erase("asset");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "asset: missing");
}

TEST(BadInput, UnsupportedRequiredExtension) {
  TestGltf g = Quad();
  g.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "extensionsRequired[0]: \"KHR_draco_mesh_compression\" is not supported (supported: "
               "KHR_lights_punctual, KHR_materials_emissive_strength, KHR_materials_ior, "
               "KHR_materials_specular, KHR_texture_transform)");
  // Those import applies may be required.
  g.doc["extensionsRequired"] = {"KHR_texture_transform", "KHR_materials_ior"};
  EXPECT_TRUE(Import(g.ToGltf()).ok());
}

TEST(BadInput, NonFiniteNumberNamesItsField) {
  // JSON has no NaN; a number that overflows a double is the closest thing.
  TestGltf g = Quad();
  std::string text(reinterpret_cast<const char*>(g.ToGltf().data()), g.ToGltf().size());
  text.replace(text.find(R"("nodes":[{)"), 10, R"("nodes":[{"translation":[1e999,0,0],)");
  EXPECT_ERROR(Import(Bytes(text)), kInvalidArgument, "nodes[0].translation[0]: malformed JSON");
  EXPECT_ERROR(Import(Bytes(text)), kInvalidArgument, "number overflow");
}

TEST(BadInput, NumberBeyondFloatInNodeTranslation) {
  TestGltf g = Quad();
  g.doc["nodes"][0]["translation"] = {0, 1e300, 0};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "nodes[0].translation[1]: 1e+300 is out of range");
}

// ----------------------------------------------------- buffers and views

TEST(BadInput, AccessorCountOverrunsBufferView) {
  TestGltf g = Quad();
  g.doc["accessors"][0]["count"] = 1000;  // POSITION
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "accessors[0].count: 1000 elements of 12 bytes (stride 12) from byteOffset 0 "
               "overrun bufferViews[0] (byteLength 48)");
}

TEST(BadInput, AccessorOffsetOverrunsBufferView) {
  TestGltf g = Quad();
  g.doc["accessors"][0]["byteOffset"] = 40;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "accessors[0].count: 4 elements");
  g.doc["accessors"][0]["byteOffset"] = 48;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "accessors[0].byteOffset: 48 is past the end of bufferViews[0]");
}

TEST(BadInput, AccessorArithmeticOverflow) {
  TestGltf g = Quad();
  g.doc["accessors"][0]["count"] = 0x7fffffffffffffffull;
  g.doc["accessors"][0]["byteOffset"] = 4;
  // Caught by the triangle budget first (count / 3 triangles) ...
  EXPECT_ERROR(Import(g.ToGltf()), kResourceExhausted, "meshes:");
  // ... and by the range check when the budget would allow it.
  ImportOptions options;
  options.limits.max_triangles = UINT64_MAX / 4;
  EXPECT_ERROR(Import(g.ToGltf(), options), kInvalidArgument, "accessors[0].count:");
}

TEST(BadInput, BufferViewOverrunsBuffer) {
  TestGltf g = Quad();
  g.doc["bufferViews"][0]["byteLength"] = 100000;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "bufferViews[0].byteLength: 100000 bytes at byteOffset 0 overrun buffers[0]");
}

TEST(BadInput, StrideSmallerThanElement) {
  TestGltf g = Quad();
  g.doc["bufferViews"][0]["byteStride"] = 8;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "bufferViews[0].byteStride: 8");
}

TEST(BadInput, MissingBuffer) {
  TestGltf g = Quad();
  g.doc["bufferViews"][1]["buffer"] = 5;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "bufferViews[1].buffer: 5 is out of range (1 buffers)");
  TestGltf h = Quad();
  nlohmann::json d = h.doc;
  d["buffers"] = {{{"byteLength", h.bin.size()}}};  // no uri in a .gltf
  EXPECT_ERROR(Import(Bytes(d.dump())), kInvalidArgument, "buffers[0].uri: missing");
}

TEST(BadInput, BadDataUri) {
  TestGltf g = Quad();
  nlohmann::json d = g.doc;
  d["buffers"] = {
      {{"byteLength", g.bin.size()}, {"uri", "data:application/octet-stream;base64,AAAA"}}};
  EXPECT_ERROR(Import(Bytes(d.dump())), kInvalidArgument, "scene: malformed glTF");
}

TEST(BadInput, IndexOutOfRange) {
  TestGltf g;
  const int pos = g.AddVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int idx = g.AddIndices16({0, 1, 7});
  g.AddRoot({{"mesh", g.AddMesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}})}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].indices (accessors[1]): index 7 at position 2 is out of "
               "range (3 vertices)");
}

TEST(BadInput, IndicesNotWholeTriangles) {
  TestGltf g;
  const int pos = g.AddVec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int idx = g.AddIndices16({0, 1, 2, 0});
  g.AddRoot({{"mesh", g.AddMesh({{"attributes", {{"POSITION", pos}}}, {"indices", idx}})}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "meshes[0].primitives[0].indices: 4 indices");
}

TEST(BadInput, AccessorIndexOutOfRange) {
  TestGltf g = Quad();
  g.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 42;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.NORMAL: 42 is out of range (3 accessors)");
}

TEST(BadInput, WrongAccessorTypes) {
  TestGltf g = Quad();
  g.doc["accessors"][0]["type"] = "VEC2";
  EXPECT_ERROR(
      Import(g.ToGltf()), kInvalidArgument,
      "accessors[0].type: VEC2 but meshes[0].primitives[0].attributes.POSITION needs VEC3");
  g = Quad();
  g.doc["accessors"][2]["componentType"] = 5126;  // float indices
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "accessors[2].componentType: 5126 (FLOAT)");
}

TEST(BadInput, PrimitiveWithoutAttributes) {
  TestGltf g = Quad();
  g.doc["meshes"][0]["primitives"].push_back({{"indices", 2}});
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "meshes[0].primitives[1].attributes: missing");
}

TEST(BadInput, EmptyDataUriImage) {
  TestGltf g = Quad();
  g.doc["images"] = {{{"uri", "data:image/png;base64,"}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "scene: malformed glTF");
}

TEST(BadInput, MissingPosition) {
  TestGltf g = Quad();
  g.doc["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.POSITION: missing");
}

TEST(BadInput, NormalCountMismatch) {
  TestGltf g = Quad();
  g.doc["accessors"][1]["count"] = 3;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].attributes.NORMAL: 3 elements but POSITION has 4");
}

TEST(BadInput, SparseAccessor) {
  TestGltf g = Quad();
  g.doc["accessors"][0]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", 2}, {"componentType", 5123}}},
                                     {"values", {{"bufferView", 0}}}};
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "accessors[0].sparse: sparse accessors");
}

TEST(BadInput, UnknownPrimitiveModesAreRefused) {
  TestGltf g = Quad();
  g.doc["meshes"][0]["primitives"][0]["mode"] = 9;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "meshes[0].primitives[0].mode: 9");
}

TEST(BadInput, MaterialOutOfRange) {
  TestGltf g = Quad();
  g.doc["meshes"][0]["primitives"][0]["material"] = 3;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "meshes[0].primitives[0].material: 3 is out of range (0 materials)");
}

TEST(BadInput, MeshOutOfRange) {
  TestGltf g = Quad();
  g.doc["nodes"][0]["mesh"] = 2;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "nodes[0].mesh: 2 is out of range (1 meshes)");
}

// ---------------------------------------------------------------- images

TestGltf TexturedQuad(const std::vector<uint8_t>& image, const std::string& mime) {
  TestGltf g;
  const int view = g.AddView(image.data(), image.size());
  g.doc["images"] = {{{"bufferView", view}, {"mimeType", mime}}};
  g.doc["textures"] = {{{"source", 0}}};
  const int mat = g.AddMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, mat)}});
  return g;
}

TEST(BadInput, MissingImage) {
  TestGltf g = TexturedQuad(testing::PngHeaderOnly(1, 1), "image/png");
  g.doc["textures"][0]["source"] = 3;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "textures[0].source: 3 is out of range (1 images)");
  g.doc["textures"][0].erase("source");
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "textures[0].source: missing");
}

TEST(BadInput, TextureIndexOutOfRange) {
  TestGltf g = TexturedQuad(testing::PngHeaderOnly(1, 1), "image/png");
  g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 4;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument,
               "materials[0].pbrMetallicRoughness.baseColorTexture.index: 4 is out of range");
}

TEST(BadInput, HugeImageHeaderIsRefusedBeforeDecoding) {
  const TestGltf g = TexturedQuad(testing::PngHeaderOnly(100000, 100000), "image/png");
  EXPECT_ERROR(Import(g.ToGltf()), kResourceExhausted,
               "images[0]: 100000x100000 pixels exceed the limit");
}

TEST(BadInput, DisguisedImage) {
  // A BMP body labelled image/png.
  std::vector<uint8_t> bmp = {'B', 'M', 70, 0, 0, 0, 0, 0, 0, 0, 54, 0, 0, 0, 40, 0, 0, 0};
  bmp.resize(70, 0);
  EXPECT_ERROR(Import(TexturedQuad(bmp, "image/png").ToGltf()), kInvalidArgument,
               "images[0]: not a PNG or JPEG image (data starts with 42 4d");
  // A Targa header has no magic at all.
  std::vector<uint8_t> tga = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 32, 8, 1, 2, 3, 4};
  EXPECT_ERROR(Import(TexturedQuad(tga, "image/png").ToGltf()), kInvalidArgument,
               "images[0]: not a PNG or JPEG image");
}

TEST(BadInput, CorruptPng) {
  std::vector<uint8_t> png = testing::PngHeaderOnly(4, 4);  // IDAT holds no pixels
  EXPECT_ERROR(Import(TexturedQuad(png, "image/png").ToGltf()), kInvalidArgument,
               "images[0]: corrupt png image");
}

TEST(BadInput, ImageBufferViewOverrunsBuffer) {
  // tinygltf itself would read past the buffer here; the pre-flight refuses.
  TestGltf g = TexturedQuad(testing::PngHeaderOnly(1, 1), "image/png");
  g.doc["bufferViews"][0]["byteOffset"] = 1u << 30;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "bufferViews[0].byteLength:");
  g.doc["images"][0]["bufferView"] = 99;
  EXPECT_ERROR(Import(g.ToGltf()), kInvalidArgument, "images[0].bufferView: 99 is out of range");
}

// ---------------------------------------------------------------- limits

TEST(BadInput, TooManyTriangles) {
  ImportOptions options;
  options.limits.max_triangles = 1;
  EXPECT_ERROR(Import(Quad().ToGltf(), options), kResourceExhausted,
               "meshes: 2 triangles (over all node instances) exceed the limit of 1");
}

TEST(BadInput, TooManyTrianglesOverInstances) {
  TestGltf g = Quad();
  for (int i = 0; i < 3; ++i) g.AddRoot({{"mesh", 0}});  // 4 instances of 2 triangles
  ImportOptions options;
  options.limits.max_triangles = 7;
  EXPECT_ERROR(Import(g.ToGltf(), options), kResourceExhausted, "meshes: 8 triangles");
  options.limits.max_triangles = 8;
  EXPECT_TRUE(Import(g.ToGltf(), options).ok());
}

TEST(BadInput, TooManyVertices) {
  // Primitives that share one vertex accessor but use few of its vertices:
  // the triangle budget alone would not bound the memory they take.
  TestGltf g = Quad();
  g.doc["accessors"][2]["count"] = 3;  // one triangle of the four vertices
  g.doc["meshes"][0]["primitives"].push_back(g.doc["meshes"][0]["primitives"][0]);
  ImportOptions options;
  options.limits.max_triangles = 2;
  EXPECT_ERROR(Import(g.ToGltf(), options), kResourceExhausted,
               "meshes: 8 vertices exceed the limit of 6");
}

TEST(BadInput, TooManyNodes) {
  TestGltf g = Quad();
  for (int i = 0; i < 10; ++i) g.AddRoot({});
  ImportOptions options;
  options.limits.max_nodes = 10;
  EXPECT_ERROR(Import(g.ToGltf(), options), kResourceExhausted,
               "nodes: 11 nodes exceed the limit of 10");
}

TEST(BadInput, TooManyDrawItemsOverInstances) {
  // Three primitives in one mesh, instanced by four nodes: 12 draws (a
  // frame's cost, issue 30), whatever the triangles.
  TestGltf g = Quad();
  for (int i = 0; i < 2; ++i) {
    g.doc["meshes"][0]["primitives"].push_back(g.doc["meshes"][0]["primitives"][0]);
  }
  for (int i = 0; i < 3; ++i) g.AddRoot({{"mesh", 0}});
  ImportOptions options;
  options.limits.max_draw_items = 11;
  EXPECT_ERROR(Import(g.ToGltf(), options), kResourceExhausted,
               "meshes: 12 primitives drawn (primitives x the nodes instancing their mesh) "
               "exceed the limit of 11 (--max-draw-items)");
  options.limits.max_draw_items = 12;
  EXPECT_TRUE(Import(g.ToGltf(), options).ok());
}

TEST(BadInput, TooManyMaterials) {
  TestGltf g = Quad();
  for (int i = 0; i < 5; ++i) g.AddMaterial({{"name", "m"}});
  ImportOptions options;
  options.limits.max_materials = 4;
  // Refused before the document is parsed (the preflight), naming the figure.
  EXPECT_ERROR(Import(g.ToGltf(), options), kResourceExhausted,
               "materials: 5 materials exceed the limit of 4 (--max-materials)");
  options.limits.max_materials = 5;
  EXPECT_TRUE(Import(g.ToGltf(), options).ok());
}

TEST(BadInput, SceneTooLarge) {
  ImportOptions options;
  options.limits.max_scene_bytes = 100;
  EXPECT_ERROR(Import(Quad().ToGltf(), options), kResourceExhausted,
               "bytes exceed the limit of 100");
}

TEST(BadInput, TooManyImagePixelsPerScene) {
  TestGltf g;
  const std::vector<uint8_t> rgba(16 * 16 * 4, 7);
  // Two distinct images of 256 pixels each.
  for (int i = 0; i < 2; ++i) {
    std::vector<uint8_t> px = rgba;
    px[0] = uint8_t(i);
    const std::string png = *EncodePng(px, 16, 16);
    g.doc["images"].push_back({{"bufferView", g.AddView(png.data(), png.size())}});
    g.doc["textures"].push_back({{"source", i}});
    g.AddMaterial({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", i}}}}}});
  }
  g.AddRoot({{"mesh", AddQuadMesh(&g, true, 1)}});
  ImportOptions options;
  options.limits.max_total_image_pixels = 300;
  EXPECT_ERROR(Import(g.ToGltf(), options), kResourceExhausted,
               "images[1]: decoded images exceed the limit of 300 pixels");
}

}  // namespace gltf_bad_input_test
}  // namespace gistream
