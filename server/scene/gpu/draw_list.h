// One indirect draw list (issue 19): what GpuScene::Draw would issue for one
// or more views of a pass, as glMultiDrawElementsIndirect commands,
// one call per view instead of one draw (and one set of uniform changes)
// per item and per cluster node. Each draw carries a record (its model
// matrix and a pass-defined tag, e.g. the cube face it is drawn into) that
// the vertex shader reads as instanced attributes (scene_vertex.glsl's
// GS_DRAW_LIST path). Draws of the same index range in a view (the
// instances of an instanced mesh at the same proxy level or cluster node,
// a node drawn into several faces) become one instanced command: an
// instanced mesh is drawn instanced.
//
// A pass that samples material textures (sh_probes' probe cubes) adds its
// views with DrawTextures::kBind: a view's draws are then grouped by the
// textures they sample, one multi-draw per group with its textures bound,
// and the record's material index replaces uMaterial.
//
// Use: Clear, AddView per view (CPU only), Upload once, then Draw(view)
// with the pass's program bound; a pass adds all its views before it
// uploads (one upload per pass, or per batch). Lives on the render thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "gl/buffers.h"
#include "gl/handle.h"
#include "scene/gpu/gpu_scene.h"

namespace gistream {

// One draw's instanced attributes (shaders/common/scene_vertex.glsl's
// aDrawModel, aDrawInfo; GpuScene's vertex array reads them at this layout).
struct DrawRecord {
  glm::mat4 model;
  glm::ivec4 info;  // x: the pass's tag; y: the material (GpuScene::MaterialIndex); zw: unused
};
static_assert(sizeof(DrawRecord) == 80 && offsetof(DrawRecord, info) == sizeof(glm::mat4));

// How AddView records a draw's tag.
enum class DrawTags {
  kValue,    // one record, the tag as it is
  kEachBit,  // one record per set bit of the tag, its tag the bit's index
             // (a cube face mask: a draw per face the node may reach)
};

// Whether a view's draws bind their material textures.
enum class DrawTextures {
  kNone,  // depth passes: no textures, one multi-draw per view
  kBind,  // grouped by MaterialTextures, each group's bound before its multi-draw
};

// GL's DrawElementsIndirectCommand.
struct DrawCommand {
  uint32_t count = 0;
  uint32_t instance_count = 0;
  uint32_t first_index = 0;
  int32_t base_vertex = 0;
  uint32_t base_instance = 0;  // the first record of the command's instances
};
static_assert(sizeof(DrawCommand) == 20);

class DrawList {
 public:
  // Forgets the views (the GL buffers stay until the next Upload).
  void Clear();
  // Appends one view: the ranges GpuScene::Walk visits under `filter` and
  // `cluster_filter`, each recorded with the value `tag` holds when it is
  // visited (the filters may change it; e.g. the face mask), as `mode`
  // says. Returns the view's index for Draw.
  int AddView(const GpuScene& gpu, const SceneState& state, const DrawFilter* filter,
              const ClusterFilter* cluster_filter, const int& tag, DrawTags mode = DrawTags::kValue,
              DrawTextures textures = DrawTextures::kNone);
  // Writes every view's commands and records to new GL buffers (the old
  // ones are freed once the draws that read them are done); call once
  // after the views are added.
  void Upload();
  // Draws `view` with the bound program, which must read its vertices
  // through scene_vertex.glsl's GS_DRAW_LIST (with the material table
  // bound, and each group's textures for a kBind view).
  void Draw(const GpuScene& gpu, int view) const;

  // The most bytes (on the CPU, and again in GL buffers) a list of
  // `views` views of `gpu` may take when each range gets up to
  // `records_per_range` records (6 for a cube's faces): a view visits at
  // most one range per item, or per node of its cluster tree. For the
  // solvers' memory estimates.
  static uint64_t MaxBytes(const GpuScene& gpu, uint64_t views, int records_per_range);

  int views() const { return int(view_first_.size()); }
  // The commands of `view` (their count is the draws the view costs).
  std::vector<DrawCommand> Commands(int view) const;

 private:
  struct Entry {
    int group;            // index into the view's texture sets (0 without kBind)
    DrawCommand command;  // instance_count 1, base_instance unset
    DrawRecord record;
  };
  // A run of a view's commands drawn with one multi-draw.
  struct Group {
    size_t first;               // its first command
    bool bind;                  // bind `textures` first
    MaterialTextures textures;  // with `bind`
  };

  std::pair<size_t, size_t> Range(int view) const;       // its commands [first, end)
  std::pair<size_t, size_t> GroupRange(int view) const;  // its groups [first, end)

  std::vector<Entry> entries_;          // the view being added, then kept merged below
  std::vector<MaterialTextures> sets_;  // the view being added: its texture sets
  std::vector<DrawCommand> commands_;
  std::vector<DrawRecord> records_;
  std::vector<Group> groups_;
  std::vector<size_t> view_first_;        // per view, its first command
  std::vector<size_t> view_first_group_;  // per view, its first group
  gl::Buffer command_buffer_, record_buffer_;
};

}  // namespace gistream
