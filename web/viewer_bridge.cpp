#include <atomic>
#include "viewer_bridge.h"

#include "gateway_metrics.h"
#include "resumable_session.h"
#include "scene_loader.h"
#include "util/log.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <map>
#include <iostream>
#include <mutex>
#include <thread>
#include <vector>

#include <absl/strings/escaping.h>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <grpcpp/grpcpp.h>
#include <nlohmann/json.hpp>

namespace gistream::web {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
using json = nlohmann::json;

// The subprotocols an upgrade request offers (Sec-WebSocket-Protocol,
// comma-separated), trimmed.
std::vector<std::string_view> OfferedSubprotocols(const http::request<http::string_body>& request) {
  const beast::string_view header = request[http::field::sec_websocket_protocol];
  const std::string_view offered(header.data(), header.size());
  std::vector<std::string_view> out;
  for (size_t begin = 0; begin < offered.size();) {
    const size_t end = std::min(offered.find(',', begin), offered.size());
    std::string_view protocol = offered.substr(begin, end - begin);
    while (!protocol.empty() && protocol.front() == ' ') protocol.remove_prefix(1);
    while (!protocol.empty() && protocol.back() == ' ') protocol.remove_suffix(1);
    if (!protocol.empty()) out.push_back(protocol);
    begin = end + 1;
  }
  return out;
}

json Vec(const v1::Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

void SetVec(const json& j, v1::Vec3* out) {
  out->set_x(j.at(0).get<float>());
  out->set_y(j.at(1).get<float>());
  out->set_z(j.at(2).get<float>());
}

// The browser's JSON message as a SessionRequest; throws on malformed input.
v1::SessionRequest RequestFromJson(const json& m) {
  v1::SessionRequest request;
  const std::string type = m.at("type").get<std::string>();
  if (type == "key_frame") {
    request.mutable_request_frame()->set_key_frame(true);
    return request;
  }
  v1::Update* u = request.mutable_update();
  u->set_seq(m.value("seq", uint64_t(0)));
  if (type == "camera") {
    v1::LookAt* look = u->mutable_camera()->mutable_look_at();
    SetVec(m.at("eye"), look->mutable_eye());
    SetVec(m.at("target"), look->mutable_target());
  } else if (type == "light") {
    u->mutable_light()->set_light(m.at("light").get<uint32_t>());
    u->mutable_light()->set_intensity(m.at("intensity").get<float>());
  } else if (type == "material") {
    // What the page moved, and only that: its emission slider sends
    // emissive_strength (the colour stays the scene's); `emissive` sets
    // the colour alone.
    u->mutable_material()->set_material(m.at("material").get<uint32_t>());
    if (m.contains("emissive")) SetVec(m.at("emissive"), u->mutable_material()->mutable_emissive());
    if (m.contains("emissive_strength")) {
      u->mutable_material()->set_emissive_strength(m.at("emissive_strength").get<float>());
    }
  } else {
    throw std::invalid_argument("unknown message type '" + type + "'");
  }
  return request;
}

bool PageMaySet(const ViewerOptions& options, const std::string& param) {
  return !options.page_params_limited ||
         std::find(options.page_params.begin(), options.page_params.end(), param) !=
             options.page_params.end();
}

json SolversJson(const v1::ListSolversResponse& list, const ViewerOptions& options) {
  json out = json::array();
  for (const v1::SolverInfo& s : list.solvers()) {
    json params = json::array();
    for (const v1::ParamSpec& p : s.params()) {
      if (!PageMaySet(options, p.name())) continue;  // the page shows what it may set
      params.push_back(
          {{"name", p.name()},
           {"type", v1::ParamType_Name(p.type())},
           {"default", p.default_value()},
           {"min", p.min()},
           {"max", p.max()},
           {"choices", std::vector<std::string>(p.choices().begin(), p.choices().end())},
           {"description", p.description()}});
    }
    out.push_back({{"name", s.name()}, {"description", s.description()}, {"params", params}});
  }
  return out;
}

json SceneJson(const ViewerOptions& options) {
  const v1::LoadSceneResponse& scene = options.scene;
  const v1::SessionConfig& config = options.config;
  const std::vector<std::string>& names = options.scene_names;
  const std::string& name = options.scene_name;
  json lights = json::array(), materials = json::array();
  for (const v1::LightInfo& l : scene.lights()) {
    lights.push_back({{"id", l.id()}, {"name", l.name()}, {"intensity", l.intensity()}});
  }
  for (const v1::MaterialInfo& m : scene.materials()) {
    if (m.emissive().x() + m.emissive().y() + m.emissive().z() <= 0.0f) continue;
    materials.push_back({{"id", m.id()},
                         {"name", m.name()},
                         {"emissive", Vec(m.emissive())},
                         {"emissive_strength", m.emissive_strength()}});
  }
  json out = {{"type", "scene"},
              {"scene_id", scene.scene_id()},
              {"solver", config.solver()},
              {"width", config.width()},
              {"height", config.height()},
              {"format", config.encoding().format() == v1::IMAGE_FORMAT_H264 ? "h264" : "jpeg"},
              {"bounds", {{"min", Vec(scene.bounds().min())}, {"max", Vec(scene.bounds().max())}}},
              {"lights", lights},
              {"materials", materials},
              {"solvers", SolversJson(options.solvers, options)},
              {"scenes", names},
              {"scene_name", name},
              {"ignored_extensions", std::vector<std::string>(scene.ignored_extensions().begin(),
                                                              scene.ignored_extensions().end())},
              // Shown under the picture: ignored extensions, no light at all.
              {"warnings", client::SceneWarnings(scene)},
              {"params",
               std::map<std::string, std::string>(config.params().begin(), config.params().end())}};
  if (scene.cameras_size() > 0) {
    out["camera"] = {{"position", Vec(scene.cameras(0).position())},
                     {"yfov_degrees", scene.cameras(0).yfov() * 57.29578f}};
  }
  return out;
}

std::string FrameMessage(const v1::Frame& f) {
  json timings = json::array();
  for (const v1::StageTiming& t : f.timings()) {
    timings.push_back({t.name(), t.cpu_ms(), t.gpu_ms(), t.skipped()});
  }
  // What the picture has converged to (issue 27), for the overlay: the
  // stats of those names the frame carries.
  json convergence = json::object();
  for (const char* name :
       {"refine_samples", "refine_target", "refine_carry", "refine_reproject", "update_complete",
        "at_rest", "ms_since_camera_change", "ms_since_scene_change", "gi_versions_behind",
        "residual", "spp_total"}) {
    const auto it = f.stats().find(name);
    if (it != f.stats().end()) convergence[name] = it->second;
  }
  const std::string header = json{
      {"frame", f.frame_number()},
      {"seq", f.last_update_seq()},
      {"width", f.width()},
      {"height", f.height()},
      {"format", f.format() == v1::IMAGE_FORMAT_H264 ? "h264" : "jpeg"},
      {"key_frame", f.key_frame()},
      {"unchanged", f.unchanged()},
      {"total_ms", f.total_ms()},
      {"dropped", f.dropped_frames()},
      {"convergence", convergence},
      {"timings", timings}}.dump();
  std::string out(4, '\0');
  const uint32_t n = uint32_t(header.size());
  for (int i = 0; i < 4; ++i) out[size_t(i)] = char((n >> (8 * i)) & 0xff);
  out += header;
  out += f.image();
  return out;
}

// The gRPC side, shared by the WebSocket session and the thread reading
// events (which outlives neither: it holds a reference).
struct Link {
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientReaderWriter<v1::SessionRequest, v1::SessionEvent>> stream;
  std::mutex write_mutex;  // one write at a time (the reader thread sends the config)
  bool replayed = false;   // config and the page's changes sent (ChangeLog::mutex)
  bool Write(const v1::SessionRequest& r) {
    std::lock_guard lock(write_mutex);
    return stream->Write(r);
  }
};

// The page's changes to the scene (lights, materials, camera), compacted as
// a moving client's are (client/resumable_session.h): sent again after the
// config of every session the viewer opens, so a backend that restarted or
// a server the balancer moved the viewer to shows what the page had set.
// A new scene from the picker starts it afresh.
struct ChangeLog {
  std::mutex mutex;
  std::vector<std::pair<std::string, v1::SessionRequest>> entries;
  void Add(const v1::SessionRequest& request) {
    if (!request.has_update()) return;
    const std::string key = client::UpdateTargetKey(request.update());
    if (!key.empty()) {
      std::erase_if(entries, [&](const auto& entry) { return entry.first == key; });
    }
    entries.emplace_back(key, request);
  }
};

std::atomic<size_t> live_viewers{0};

class Viewer : public std::enable_shared_from_this<Viewer> {
 public:
  Viewer(tcp::socket socket, const ViewerOptions& options, bool h264, std::string who)
      : ws_(std::move(socket)),
        options_(options),
        h264_(h264),
        who_(std::move(who)),
        link_(std::make_shared<Link>()) {
    options_.config.mutable_encoding()->set_format(h264 ? v1::IMAGE_FORMAT_H264
                                                        : v1::IMAGE_FORMAT_JPEG);
    live_viewers.fetch_add(1);
  }
  ~Viewer() {
    link_->context.TryCancel();
    live_viewers.fetch_sub(1);
    if (!peer_.empty()) Log(LogLevel::kInfo, "viewer " + peer_ + " closed");
  }

  void Start(http::request<http::string_body> request) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    // A page that offers subprotocols gets "gistream" selected (a browser
    // fails a connection whose answer selects none of those it offered).
    const std::vector<std::string_view> offered = OfferedSubprotocols(request);
    if (std::find(offered.begin(), offered.end(), kSubprotocol) != offered.end()) {
      ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& response) {
        response.set(http::field::sec_websocket_protocol, kSubprotocol);
      }));
    }
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      if (!ec) self->OnAccepted();
    });
  }

 private:
  struct Outgoing {
    std::string data;
    bool binary = false;
    bool frame = false;
  };

  void OnAccepted() {
    beast::error_code ec;
    const auto remote = beast::get_lowest_layer(ws_).socket().remote_endpoint(ec);
    peer_ = ec ? "?" : remote.address().to_string() + ":" + std::to_string(remote.port());
    Log(LogLevel::kInfo, "viewer " + peer_ + " opened (" + (h264_ ? "h264" : "jpeg") + ", " +
                             (who_.empty() ? "" : who_ + ", ") +
                             std::to_string(live_viewers.load()) + " live)");
    Metrics().ViewerOpened(h264_);
    SendScene();
    StartLink();
    Read();
  }

  // Opens the gRPC session for the current config (closing the previous
  // one: the picker changed the solver). Messages of an older link are
  // ignored.
  void StartLink() {
    if (link_->stream) link_->context.TryCancel();
    link_ = std::make_shared<Link>();
    link_->stream = options_.stub->Session(&link_->context);
    awaiting_key_ = false;
    // Events are read on their own thread (the gRPC sync API blocks) and
    // handed to this session's executor.
    std::weak_ptr<Viewer> weak = weak_from_this();
    std::thread([weak, link = link_, config = options_.config, changes = changes_,
                 executor = ws_.get_executor()] {
      v1::SessionRequest first;
      *first.mutable_config() = config;
      {
        // Under the log's lock: a change the page sends meanwhile is either
        // in this replay or written after it.
        std::lock_guard lock(changes->mutex);
        link->Write(first);
        for (const auto& [key, request] : changes->entries) link->Write(request);
        link->replayed = true;
      }
      v1::SessionEvent event;
      while (link->stream->Read(&event)) {
        std::string message;
        bool binary = false, key = false, has_image = false;
        uint64_t seq = 0;
        if (event.has_frame()) {
          message = FrameMessage(event.frame());
          seq = event.frame().last_update_seq();
          binary = true;
          key = event.frame().key_frame();
          has_image = !event.frame().image().empty();
        } else if (event.has_rejected()) {
          message = json{{"type", "rejected"},
                         {"seq", event.rejected().seq()},
                         {"message", event.rejected().message()}}
                        .dump();
        } else if (event.has_opened()) {
          message = json{{"type", "opened"}, {"session_id", event.opened().session_id()}}.dump();
        } else if (event.has_draining()) {
          // The server shuts down: open the session again now (behind a
          // balancer it lands on another server; the scene is reloaded
          // there by name and the page's changes replayed).
          net::post(executor, [weak, link] {
            auto self = weak.lock();
            if (!self || self->link_ != link) return;
            Metrics().SessionReopened(GatewayMetrics::Reopen::kDraining);
            self->Send(
                json{{"type", "error"}, {"message", "the server is draining: moving the session"}}
                    .dump(),
                false, false);
            self->StartLink();
          });
          continue;
        } else {
          continue;
        }
        net::post(executor, [weak, link, message = std::move(message), binary, key, has_image,
                             seq]() mutable {
          auto self = weak.lock();
          if (self && self->link_ == link) {
            self->OnServerMessage(std::move(message), binary, key, has_image, seq);
          }
        });
      }
      const grpc::Status status = link->stream->Finish();
      net::post(executor, [weak, link, text = status.error_message(), code = status.error_code()] {
        if (auto self = weak.lock(); self && self->link_ == link) self->OnLinkClosed(code, text);
      });
    }).detach();
  }

  // The session ended. After a backend restart the scene id is unknown
  // (NOT_FOUND): the scene is loaded again by name and a new session
  // opened (the page's changes replayed); while the backend is unreachable
  // or drains (UNAVAILABLE, CANCELLED) the session is reopened every
  // second, up to kMaxReconnects times. The page is told each step.
  void OnLinkClosed(grpc::StatusCode code, const std::string& text) {
    if (page_gone_) return;
    Send(json{{"type", "closed"}, {"code", int(code)}, {"message", text}}.dump(), false, false);
    Log(code == grpc::StatusCode::CANCELLED ? LogLevel::kDebug : LogLevel::kWarning,
        "viewer " + peer_ + ": session ended: " + std::to_string(int(code)) + " " + text);
    if (code == grpc::StatusCode::NOT_FOUND && reloads_ == 0) {
      reloads_ += 1;
      Metrics().SessionReopened(GatewayMetrics::Reopen::kSceneLost);
      Send(json{{"type", "error"},
                {"message", "the server lost scene " + options_.scene_name +
                                " (it restarted?): loading it again"}}
               .dump(),
           false, false);
      LoadScene(options_.scene_name);
      return;
    }
    // CANCELLED: a server shutting down cancels the calls it will not
    // serve (the gateway's own cancels replace the link, which is then no
    // longer current and does not get here).
    if ((code == grpc::StatusCode::UNAVAILABLE || code == grpc::StatusCode::CANCELLED) &&
        reconnects_ < kMaxReconnects) {
      reconnects_ += 1;
      Metrics().SessionReopened(GatewayMetrics::Reopen::kUnavailable);
      Send(json{{"type", "error"},
                {"message", "server unavailable: reconnecting (" + std::to_string(reconnects_) +
                                " of " + std::to_string(kMaxReconnects) + ")"}}
               .dump(),
           false, false);
      retry_.expires_after(std::chrono::seconds(1));
      retry_.async_wait([weak = weak_from_this(), link = link_](beast::error_code ec) {
        auto self = weak.lock();
        if (!ec && self && self->link_ == link) self->StartLink();
      });
    }
  }

  void OnServerMessage(std::string message, bool binary, bool key, bool has_image, uint64_t seq) {
    if (binary) reconnects_ = reloads_ = 0;  // frames flow again
    if (!binary) {
      Send(std::move(message), false, false);
      return;
    }
    // The updates this frame is the first to show.
    const auto now = std::chrono::steady_clock::now();
    while (!forwarded_.empty() && forwarded_.front().first <= seq) {
      Metrics().UpdateAnswered(
          std::chrono::duration<double>(now - forwarded_.front().second).count());
      forwarded_.pop_front();
    }
    // A browser behind by two frames loses the queued ones. Delta frames
    // after a lost H.264 frame cannot be decoded: drop them until a key
    // frame, which is asked for.
    size_t queued_frames = 0;
    for (size_t i = writing_ ? 1 : 0; i < queue_.size(); ++i) queued_frames += queue_[i].frame;
    if (queued_frames >= 2) {
      Metrics().FramesDropped(queued_frames);
      std::deque<Outgoing> kept;
      for (size_t i = 0; i < queue_.size(); ++i) {
        if ((i == 0 && writing_) || !queue_[i].frame) kept.push_back(std::move(queue_[i]));
      }
      queue_ = std::move(kept);
      if (h264_ && !awaiting_key_) {
        awaiting_key_ = true;
        v1::SessionRequest r;
        r.mutable_request_frame()->set_key_frame(true);
        link_->Write(r);
      }
    }
    if (h264_ && awaiting_key_ && has_image && !key) {
      Metrics().FramesDropped(1);
      return;
    }
    if (key && has_image) awaiting_key_ = false;
    Send(std::move(message), true, true);
  }

  void SendScene() { Send(SceneJson(options_).dump(), false, false); }

  // The scene picker: LoadScene on a thread of its own (a first load may
  // take a while; the gateway's other browsers go on), then the scene's
  // description and a new session on it.
  void LoadScene(const std::string& name) {
    if (std::find(options_.scene_names.begin(), options_.scene_names.end(), name) ==
        options_.scene_names.end()) {
      Send(json{{"type", "error"}, {"message", "scene: \"" + name + "\" is not offered"}}.dump(),
           false, false);
      return;
    }
    std::weak_ptr<Viewer> weak = weak_from_this();
    std::thread([weak, stub = options_.stub, name, executor = ws_.get_executor()] {
      v1::LoadSceneRequest request;
      request.set_name(name);
      v1::LoadSceneResponse response;
      grpc::ClientContext context;
      context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(120));
      const grpc::Status status = stub->LoadScene(&context, request, &response);
      net::post(executor, [weak, name, status, response = std::move(response)]() mutable {
        auto self = weak.lock();
        if (!self) return;
        if (!status.ok()) {
          self->Send(
              json{{"type", "error"}, {"message", "scene " + name + ": " + status.error_message()}}
                  .dump(),
              false, false);
          return;
        }
        self->options_.scene = std::move(response);
        self->options_.scene_name = name;
        self->options_.config.set_scene_id(self->options_.scene.scene_id());
        self->SendScene();
        self->StartLink();
      });
    }).detach();
  }

  void Read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) {
        self->page_gone_ = true;  // no reconnects for a page that left
        self->link_->context.TryCancel();
        return;
      }
      self->OnRead();
    });
  }

  void OnRead() {
    const std::string text = beast::buffers_to_string(buffer_.data());
    buffer_.consume(buffer_.size());
    try {
      if (!TakeMessageToken()) {
        Read();
        return;
      }
      const json message = json::parse(text);
      if (message.at("type") == "config") {
        ApplyConfig(message);
      } else if (message.at("type") == "scene") {
        {
          std::lock_guard lock(changes_->mutex);  // another scene: its own changes
          changes_->entries.clear();
        }
        LoadScene(message.at("name").get<std::string>());
      } else {
        const v1::SessionRequest request = RequestFromJson(message);
        if (request.has_update() && request.update().seq() > 0) {
          // Timed to the first frame that shows it (a page's seqs rise).
          if (forwarded_.size() >= kMaxForwarded) forwarded_.pop_front();
          forwarded_.emplace_back(request.update().seq(), std::chrono::steady_clock::now());
        }
        std::lock_guard lock(changes_->mutex);
        changes_->Add(request);
        if (link_->replayed) link_->Write(request);
      }
    } catch (const std::exception& e) {
      Send(json{{"type", "error"}, {"message", std::string("bad message: ") + e.what()}}.dump(),
           false, false);
    }
    Read();
  }

  // A page's solver picker: the solver must be one the gateway offers and
  // each parameter one the page may set (ViewerOptions); the gateway's own
  // --param values stay for the rest.
  void ApplyConfig(const json& message) {
    const std::string solver = message.at("solver").get<std::string>();
    const auto& offered = options_.solvers.solvers();
    if (std::none_of(offered.begin(), offered.end(),
                     [&](const v1::SolverInfo& s) { return s.name() == solver; })) {
      throw std::invalid_argument("solver '" + solver + "' is not offered by this gateway");
    }
    v1::SessionConfig config = options_.config;
    config.set_solver(solver);
    config.clear_params();
    for (const auto& [k, v] : gateway_params_) (*config.mutable_params())[k] = v;
    if (const auto params = message.find("params"); params != message.end()) {
      for (const auto& [k, v] : params->items()) {
        if (!PageMaySet(options_, k)) {
          throw std::invalid_argument("params." + k + ": not settable from this page");
        }
        (*config.mutable_params())[k] = v.get<std::string>();
      }
    }
    options_.config = std::move(config);
    StartLink();
  }

  // The page's message budget (a token bucket): false drops the message,
  // and the page is told at most once a second.
  bool TakeMessageToken() {
    const auto now = std::chrono::steady_clock::now();
    const double rate = options_.max_messages_per_second;
    tokens_ = std::min(2.0 * rate,
                       tokens_ + rate * std::chrono::duration<double>(now - refilled_).count());
    refilled_ = now;
    if (tokens_ >= 1.0) {
      tokens_ -= 1.0;
      return true;
    }
    dropped_ += 1;
    Metrics().MessageDropped();
    if (now - last_drop_notice_ >= std::chrono::seconds(1)) {
      last_drop_notice_ = now;
      Send(json{{"type", "error"},
                {"message", "too many messages: " + std::to_string(dropped_) +
                                " dropped (at most " + std::to_string(int(rate)) + " a second)"}}
               .dump(),
           false, false);
    }
    return false;
  }

  void Send(std::string data, bool binary, bool frame) {
    queue_.push_back({std::move(data), binary, frame});
    if (!writing_) WriteNext();
  }

  void WriteNext() {
    if (queue_.empty()) {
      writing_ = false;
      return;
    }
    writing_ = true;
    ws_.binary(queue_.front().binary);
    ws_.async_write(net::buffer(queue_.front().data),
                    [self = shared_from_this()](beast::error_code ec, std::size_t bytes) {
                      if (!ec && self->queue_.front().frame) Metrics().FrameSent(bytes);
                      self->queue_.pop_front();
                      if (ec) {
                        self->page_gone_ = true;
                        self->link_->context.TryCancel();
                        self->queue_.clear();
                        self->writing_ = false;
                        return;
                      }
                      self->WriteNext();
                    });
  }

  websocket::stream<beast::tcp_stream> ws_;
  ViewerOptions options_;
  const bool h264_;
  const std::string who_;  // the viewer token's name ("" without viewer tokens)
  std::shared_ptr<Link> link_;
  beast::flat_buffer buffer_;
  std::deque<Outgoing> queue_;
  bool writing_ = false;
  bool awaiting_key_ = false;
  // The gateway's --param values, kept under every page's choice.
  const std::map<std::string, std::string> gateway_params_{options_.config.params().begin(),
                                                           options_.config.params().end()};
  double tokens_ = 2.0 * options_.max_messages_per_second;
  std::chrono::steady_clock::time_point refilled_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_drop_notice_{};
  uint64_t dropped_ = 0;
  std::string peer_;  // the browser's address, for log lines
  static constexpr int kMaxReconnects = 60;
  int reconnects_ = 0, reloads_ = 0;
  bool page_gone_ = false;  // its WebSocket failed: the link was cancelled for good
  std::shared_ptr<ChangeLog> changes_ = std::make_shared<ChangeLog>();
  net::steady_timer retry_{ws_.get_executor()};
  // Updates forwarded and not yet shown by a frame: (seq, when), oldest
  // first, for gistream_web_update_to_frame_seconds.
  static constexpr size_t kMaxForwarded = 256;
  std::deque<std::pair<uint64_t, std::chrono::steady_clock::time_point>> forwarded_;
};

}  // namespace

size_t LiveViewers() { return live_viewers.load(); }

std::optional<std::string> ViewerToken(const http::request<http::string_body>& request) {
  const beast::string_view authorization_header = request[http::field::authorization];
  const std::string_view authorization(authorization_header.data(), authorization_header.size());
  if (authorization.substr(0, 7) == "Bearer ") return std::string(authorization.substr(7));
  constexpr std::string_view prefix = kTokenSubprotocolPrefix;
  for (const std::string_view protocol : OfferedSubprotocols(request)) {
    if (protocol.substr(0, prefix.size()) != prefix) continue;
    const std::string_view encoded = protocol.substr(prefix.size());
    std::string token;
    if (!absl::WebSafeBase64Unescape(absl::string_view(encoded.data(), encoded.size()), &token)) {
      return std::nullopt;
    }
    return token;
  }
  return std::nullopt;
}

void StartViewer(tcp::socket socket, http::request<http::string_body> request,
                 const ViewerOptions& options, std::string who) {
  const std::string target(request.target());
  const bool h264 = target.find("format=h264") != std::string::npos;
  std::make_shared<Viewer>(std::move(socket), options, h264, std::move(who))
      ->Start(std::move(request));
}

}  // namespace gistream::web
