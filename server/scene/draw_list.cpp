#include "scene/draw_list.h"

#include <algorithm>
#include <tuple>

namespace gistream {

void DrawList::Clear() {
  commands_.clear();
  records_.clear();
  view_first_.clear();
}

int DrawList::AddView(const GpuScene& gpu, const SceneState& state, const DrawFilter* filter,
                      const ClusterFilter* cluster_filter, const int& tag, DrawTags mode) {
  entries_.clear();
  gpu.Walk(
      state, filter, cluster_filter,
      [&](const DrawItem& item, const glm::mat4& model, const DrawLevel& range) {
        if (range.index_count == 0) return;
        const DrawCommand command{range.index_count, 1, range.first_index, item.base_vertex, 0};
        if (mode == DrawTags::kValue) {
          entries_.push_back({command, {model, glm::ivec4(tag, 0, 0, 0)}});
          return;
        }
        for (int bit = 0; bit < 31; ++bit) {
          if (tag & (1 << bit)) {
            entries_.push_back({command, {model, glm::ivec4(bit, 0, 0, 0)}});
          }
        }
      });
  // Equal ranges next to each other (stable: a view's order otherwise
  // kept), then one command per run, its instances' records consecutive.
  const auto key = [](const Entry& e) {
    return std::tie(e.command.first_index, e.command.count, e.command.base_vertex);
  };
  std::stable_sort(entries_.begin(), entries_.end(),
                   [&](const Entry& a, const Entry& b) { return key(a) < key(b); });
  view_first_.push_back(commands_.size());
  for (size_t i = 0; i < entries_.size(); ++i) {
    if (i > 0 && key(entries_[i]) == key(entries_[i - 1])) {
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
  const auto [first, end] = Range(view);
  if (end == first) return;
  const GLuint vao = gpu.vertex_array();
  glVertexArrayVertexBuffer(vao, GpuScene::kDrawRecordBufferBinding, record_buffer_.id(), 0,
                            sizeof(DrawRecord));
  for (GLuint a = GpuScene::kDrawModelAttrib; a <= GpuScene::kDrawTagAttrib; ++a) {
    glEnableVertexArrayAttrib(vao, a);
  }
  glBindVertexArray(vao);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, command_buffer_.id());
  glMultiDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT,
                              reinterpret_cast<const void*>(first * sizeof(DrawCommand)),
                              GLsizei(end - first), 0);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  glBindVertexArray(0);
  for (GLuint a = GpuScene::kDrawModelAttrib; a <= GpuScene::kDrawTagAttrib; ++a) {
    glDisableVertexArrayAttrib(vao, a);
  }
}

std::pair<size_t, size_t> DrawList::Range(int view) const {
  const size_t first = view_first_[size_t(view)];
  const size_t end =
      size_t(view) + 1 < view_first_.size() ? view_first_[size_t(view) + 1] : commands_.size();
  return {first, end};
}

std::vector<DrawCommand> DrawList::Commands(int view) const {
  const auto [first, end] = Range(view);
  return {commands_.begin() + ptrdiff_t(first), commands_.begin() + ptrdiff_t(end)};
}

}  // namespace gistream
