// The client's scene script parser (client/script.*, the JSON that
// `gistream stream --script` and the demo read): any text parses or answers
// a status; a parsed script's curves are evaluated at every frame without
// crashing or undefined behaviour.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "script.h"

using namespace gistream::client;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<Script> script = ParseScript(text, "fuzz.json");
  if (!script.ok()) {
    FUZZ_CHECK(!script.status().message().empty());
    return 0;
  }
  // Every curve evaluates at every frame (UBSan watches the arithmetic).
  const int frames = std::min(script->frames, 64);
  auto eval = [&](const auto& curve) {
    if (curve.empty()) return;
    for (int f = 0; f < frames; ++f) (void)curve.At(f);
  };
  for (const Track& track : script->tracks) {
    if (const auto* t = std::get_if<CameraPathTrack>(&track.spec)) {
      eval(t->eye), eval(t->target), eval(t->yfov_degrees);
    } else if (const auto* n = std::get_if<NodePathTrack>(&track.spec)) {
      eval(n->translation), eval(n->rotation), eval(n->scale);
    } else if (const auto* l = std::get_if<LightTrack>(&track.spec)) {
      eval(l->intensity), eval(l->color), eval(l->position), eval(l->direction);
    } else if (const auto* m = std::get_if<MaterialTrack>(&track.spec)) {
      eval(m->base_color), eval(m->emissive), eval(m->emissive_strength);
    } else if (const auto* e = std::get_if<EnvironmentTrack>(&track.spec)) {
      eval(e->rotation), eval(e->intensity);
    }
  }
  return 0;
}
