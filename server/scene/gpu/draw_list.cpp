#include "scene/gpu/draw_list.h"

#include <algorithm>
#include <tuple>

namespace gistream {

void DrawList::Clear() {
  commands_.clear();
  records_.clear();
  groups_.clear();
  view_first_.clear();
  view_first_group_.clear();
}

int DrawList::AddView(const GpuScene& gpu, const SceneState& state, const DrawFilter* filter,
                      const ClusterFilter* cluster_filter, const int& tag, DrawTags mode,
                      DrawTextures textures) {
  entries_.clear();
  sets_.clear();
  const bool bind = textures == DrawTextures::kBind;
  const DrawItem* current = nullptr;  // the item whose group and material are known
  int group = 0, material = 0;
  gpu.Walk(
      state, filter, cluster_filter,
      [&](const DrawItem& item, const glm::mat4& model, const DrawLevel& range) {
        if (range.index_count == 0) return;
        if (current != &item) {
          current = &item;
          material = GpuScene::MaterialIndex(state, item);
          if (bind) {
            const MaterialTextures set = gpu.TexturesOf(state, item);
            const auto it = std::find(sets_.begin(), sets_.end(), set);
            group = int(it - sets_.begin());
            if (it == sets_.end()) sets_.push_back(set);
          }
        }
        const DrawCommand command{range.index_count, 1, range.first_index, item.base_vertex, 0};
        if (mode == DrawTags::kValue) {
          entries_.push_back({group, command, {model, glm::ivec4(tag, material, 0, 0)}});
          return;
        }
        for (int bit = 0; bit < 31; ++bit) {
          if (tag & (1 << bit)) {
            entries_.push_back({group, command, {model, glm::ivec4(bit, material, 0, 0)}});
          }
        }
      });
  // Groups in the order first drawn, equal ranges next to each other
  // within a group (stable: a view's order otherwise kept), then one
  // command per run, its instances' records consecutive.
  const auto range = [](const Entry& e) {
    return std::tie(e.command.first_index, e.command.count, e.command.base_vertex);
  };
  const auto key = [&](const Entry& e) { return std::tuple_cat(std::tie(e.group), range(e)); };
  std::stable_sort(entries_.begin(), entries_.end(),
                   [&](const Entry& a, const Entry& b) { return key(a) < key(b); });
  view_first_.push_back(commands_.size());
  view_first_group_.push_back(groups_.size());
  for (size_t i = 0; i < entries_.size(); ++i) {
    const bool new_group = i == 0 || entries_[i].group != entries_[i - 1].group;
    if (new_group) {
      groups_.push_back(
          {commands_.size(), bind, bind ? sets_[size_t(entries_[i].group)] : MaterialTextures{}});
    }
    if (!new_group && range(entries_[i]) == range(entries_[i - 1])) {
      ++commands_.back().instance_count;
    } else {
      commands_.push_back(entries_[i].command);
      commands_.back().base_instance = uint32_t(records_.size());
    }
    records_.push_back(entries_[i].record);
  }
  return views() - 1;
}

void DrawList::Upload() {
  // New buffers, never a write into ones that queued draws still read
  // (which a driver must wait for or copy); the old ones are freed when
  // those draws are done.
  command_buffer_ = gl::StorageBuffer(commands_);
  record_buffer_ = gl::StorageBuffer(records_);
}

void DrawList::Draw(const GpuScene& gpu, int view) const {
  const auto [first_group, end_group] = GroupRange(view);
  if (end_group == first_group) return;
  const size_t end = Range(view).second;
  const GLuint vao = gpu.vertex_array();
  glVertexArrayVertexBuffer(vao, GpuScene::kDrawRecordBufferBinding, record_buffer_.id(), 0,
                            sizeof(DrawRecord));
  for (GLuint a = GpuScene::kDrawModelAttrib; a <= GpuScene::kDrawTagAttrib; ++a) {
    glEnableVertexArrayAttrib(vao, a);
  }
  glBindVertexArray(vao);
  gpu.BindMaterials();
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, command_buffer_.id());
  for (size_t g = first_group; g < end_group; ++g) {
    const Group& group = groups_[g];
    const size_t group_end = g + 1 < end_group ? groups_[g + 1].first : end;
    if (group.bind) GpuScene::BindTextures(group.textures);
    glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                                reinterpret_cast<const void*>(group.first * sizeof(DrawCommand)),
                                GLsizei(group_end - group.first), 0);
  }
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glBindVertexArray(0);
  GpuScene::UnbindSamplers();
  for (GLuint a = GpuScene::kDrawModelAttrib; a <= GpuScene::kDrawTagAttrib; ++a) {
    glDisableVertexArrayAttrib(vao, a);
  }
}

uint64_t DrawList::MaxBytes(const GpuScene& gpu, uint64_t views, int records_per_range) {
  uint64_t ranges = 0;
  for (const DrawItem& d : gpu.draws()) ranges += uint64_t(std::max(d.cluster_count, 1));
  // A command per record at most.
  return views * ranges * uint64_t(std::max(records_per_range, 1)) *
         (sizeof(DrawRecord) + sizeof(DrawCommand));
}

std::pair<size_t, size_t> DrawList::Range(int view) const {
  const size_t first = view_first_[size_t(view)];
  const size_t end =
      size_t(view) + 1 < view_first_.size() ? view_first_[size_t(view) + 1] : commands_.size();
  return {first, end};
}

std::pair<size_t, size_t> DrawList::GroupRange(int view) const {
  const size_t first = view_first_group_[size_t(view)];
  const size_t end = size_t(view) + 1 < view_first_group_.size()
                         ? view_first_group_[size_t(view) + 1]
                         : groups_.size();
  return {first, end};
}

std::vector<DrawCommand> DrawList::Commands(int view) const {
  const auto [first, end] = Range(view);
  return {commands_.begin() + ptrdiff_t(first), commands_.begin() + ptrdiff_t(end)};
}

}  // namespace gistream
