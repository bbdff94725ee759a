// gistream render: LoadScene, one unary Render, write the image.
#include <iostream>

#include <absl/strings/str_cat.h>

#include "commands.h"
#include "connection.h"
#include "file_io.h"
#include "frame_report.h"
#include "progress_line.h"
#include "scene_loader.h"

namespace gistream::client {

absl::Status RunRender(const ConnectionOptions& connection_options, const RenderOptions& options) {
  GS_ASSIGN_OR_RETURN(v1::LoadSceneRequest load, BuildLoadSceneRequest(options.scene));
  ProgressLine progress;
  progress.Wait(absl::StrCat("loading scene ", options.scene.scene));
  // A draining server's refusal is tried again (scene_loader.h), as long
  // as a stream's move would.
  GS_ASSIGN_OR_RETURN(
      ConnectedScene loaded,
      ConnectAndLoad(connection_options, load, options.scene.keep_scene, kLoadRetryForS));
  Connection& connection = *loaded.connection;
  const std::unique_ptr<LoadedScene>& scene = loaded.scene;
  for (const std::string& warning : SceneWarnings(scene->info())) {
    progress.Done();
    std::cerr << "warning: " << warning << std::endl;
  }

  v1::RenderRequest request;
  request.set_scene_id(scene->id());
  request.set_solver(options.solver.solver);
  request.mutable_params()->insert(options.solver.params.begin(), options.solver.params.end());
  request.set_width(options.view.width);
  request.set_height(options.view.height);
  *request.mutable_encoding() = options.view.encoding;
  request.set_refine_samples(options.view.refine_samples);
  if (options.view.camera.ByteSizeLong() > 0) *request.mutable_camera() = options.view.camera;

  v1::Frame frame;
  progress.Wait(absl::StrCat("rendering (",
                             options.solver.solver.empty() ? "direct" : options.solver.solver, ", ",
                             options.view.width, "x", options.view.height, ")"));
  GS_RETURN_IF_ERROR(connection.Call(&v1::Gistream::Stub::Render, request, &frame));
  progress.Done();
  if (frame.image().empty()) {
    return absl::InternalError(
        absl::StrCat("frame ", frame.frame_number(), " arrived without image bytes"));
  }
  GS_RETURN_IF_ERROR(WriteFile(options.out, frame.image()));
  std::cout << FormatFrameReport(frame, options.out.string());
  return absl::OkStatus();
}

}  // namespace gistream::client
