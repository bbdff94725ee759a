#include "http_server.h"

#include "gateway_metrics.h"
#include "util/log.h"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <list>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace gistream::web {

struct EmbeddedFile {
  const char* path;
  const char* data;
  std::size_t size;
};
extern const EmbeddedFile kEmbeddedFiles[];

namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

const char* ContentType(const std::string& path) {
  auto ends = [&](const char* ext) {
    const size_t n = std::strlen(ext);
    return path.size() >= n && path.compare(path.size() - n, n, ext) == 0;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  return "application/octet-stream";
}

// A request's headers must arrive within this (a client that opens a
// connection and sends nothing, or a byte a minute, is closed).
constexpr auto kHeaderTimeout = std::chrono::seconds(10);
// After an accept fails for want of descriptors (EMFILE, ENFILE), the next
// accept waits this long (having closed the oldest pending connection)
// instead of failing again at once: the loop had spun at 100 % CPU.
constexpr auto kAcceptBackOff = std::chrono::milliseconds(50);

}  // namespace

bool OriginAllowed(const std::string& origin, const std::string& host,
                   const std::vector<std::string>& allowed) {
  if (origin.empty()) return true;  // not a browser: browsers always send it
  if (allowed.empty()) return origin == "http://" + host || origin == "https://" + host;
  for (const std::string& a : allowed) {
    if (a == "*" || a == origin) return true;
  }
  return false;
}

namespace {

class HttpSession;

// Connections whose request has not arrived yet, oldest first (the I/O
// thread's alone). Over ViewerOptions::max_pending_connections, or when
// descriptors run out, the oldest is closed: a client holding many open
// without finishing a request (slowloris) loses its own oldest ones, and
// a new client, /healthz included, gets through.
class PendingConnections {
 public:
  using List = std::list<std::weak_ptr<HttpSession>>;
  List::iterator Add(std::weak_ptr<HttpSession> session) {
    pending_.push_back(std::move(session));
    return std::prev(pending_.end());
  }
  void Remove(List::iterator it) { pending_.erase(it); }
  size_t size() const { return pending_.size(); }
  // Closes the oldest pending connection; false when there is none.
  bool CloseOldest();
  uint64_t closed() const { return closed_; }

 private:
  List pending_;
  uint64_t closed_ = 0;
};

PendingConnections& Pending() {
  static PendingConnections pending;
  return pending;
}

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // `metrics_port`: a connection to --metrics-listen, which answers
  // /metrics alone (the viewers' port does not serve it).
  HttpSession(tcp::socket socket, const ViewerOptions& options, bool metrics_port)
      : stream_(std::move(socket)), options_(options), metrics_port_(metrics_port) {}
  ~HttpSession() { Unregister(); }
  void Start() {
    while (Pending().size() >= std::max<size_t>(options_.max_pending_connections, 1) &&
           Pending().CloseOldest()) {
    }
    slot_ = Pending().Add(weak_from_this());
    registered_ = true;
    stream_.expires_after(kHeaderTimeout);
    http::async_read(stream_, buffer_, request_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) {
                       self->Unregister();
                       if (!ec) self->OnRequest();
                     });
  }
  // Ends the connection now (PendingConnections::CloseOldest).
  void Close() {
    Unregister();
    beast::error_code ignored;
    stream_.socket().close(ignored);
  }

 private:
  void Unregister() {
    if (registered_) Pending().Remove(slot_);
    registered_ = false;
  }

  using Response = http::response<http::string_body>;

  void OnRequest() {
    stream_.expires_never();
    std::string target(request_.target());
    auto response = std::make_shared<Response>();
    response->version(request_.version());
    response->keep_alive(false);
    response->set(http::field::server, "gistream-web");
    response->set(http::field::cache_control, "no-store");
    response->result(http::status::not_found);
    response->set(http::field::content_type, "text/plain");
    response->body() = "not found\n";
    path_ = target.substr(0, target.find('?'));
    if (metrics_port_) {
      if (path_ == "/metrics") {
        response->result(http::status::ok);
        response->set(http::field::content_type, "text/plain; version=0.0.4");
        response->body() = Metrics().Text(LiveViewers(), options_.backend.get());
      }
      Send(response);
      return;
    }
    if (beast::websocket::is_upgrade(request_) && target.rfind("/ws", 0) == 0) {
      OnUpgrade(response);
      return;
    }
    if (path_ == "/healthz") {
      Health(*response);
    } else {
      const std::string name = path_ == "/" ? "index.html" : path_.substr(1);
      for (const EmbeddedFile* f = kEmbeddedFiles; f->path != nullptr; ++f) {
        if (name == f->path) {
          response->result(http::status::ok);
          response->set(http::field::content_type, ContentType(name));
          response->body().assign(f->data, f->size);
        }
      }
    }
    Send(response);
  }

  // A WebSocket upgrade on /ws: refused when the viewers are at their
  // limit, the page's origin is not allowed or a viewer token is missing
  // or unknown; else the socket becomes a viewer.
  void OnUpgrade(const std::shared_ptr<Response>& response) {
    const std::string origin(request_[http::field::origin]);
    if (LiveViewers() >= options_.max_viewers) {
      Metrics().UpgradeRefused(GatewayMetrics::Refusal::kViewers);
      response->result(http::status::service_unavailable);
      response->set(http::field::retry_after, "5");
      response->body() = "too many viewers (gistream-web --max-viewers " +
                         std::to_string(options_.max_viewers) + "); try again later\n";
      Send(response);
      return;
    }
    if (!OriginAllowed(origin, std::string(request_[http::field::host]),
                       options_.allowed_origins)) {
      Metrics().UpgradeRefused(GatewayMetrics::Refusal::kOrigin);
      // A page on another site must not drive sessions under this
      // gateway's token (cross-site WebSocket hijacking).
      Log(LogLevel::kWarning, "refused a WebSocket from origin '" + origin + "' (--allow-origin)");
      response->result(http::status::forbidden);
      response->body() = "origin not allowed: " + origin + " (gistream-web --allow-origin)\n";
      Send(response);
      return;
    }
    std::string who;
    if (options_.viewer_tokens) {
      const std::optional<std::string> token = ViewerToken(request_);
      const std::optional<TenantId> tenant =
          token ? options_.viewer_tokens->TenantOf(*token) : std::nullopt;
      if (!tenant) {
        // Logged without the token, at most once a second.
        Metrics().UpgradeRefused(GatewayMetrics::Refusal::kToken);
        LogRefusal("refused a WebSocket " + std::string(token ? "with an unknown" : "without a") +
                   " viewer token from " + Peer() + " (--viewer-tokens)");
        response->result(http::status::unauthorized);
        response->set(http::field::www_authenticate, "Bearer realm=\"gistream-web\"");
        response->body() =
            "a viewer token is required (open the page as /#token=TOKEN; gistream-web "
            "--viewer-tokens)\n";
        Send(response);
        return;
      }
      who = *tenant;
    }
    Metrics().RequestAnswered("/ws", 101);
    StartViewer(stream_.release_socket(), std::move(request_), options_, std::move(who));
  }

  // /healthz: whether browsers can be served now: the gateway answers, and
  // so does its gistreamd (a restarted, draining or unreachable backend is
  // 503, naming why).
  void Health(Response& response) const {
    const BackendHealth::State backend =
        options_.backend ? options_.backend->state() : BackendHealth::State{true, "unchecked"};
    if (backend.serving) {
      response.result(http::status::ok);
      response.body() = "ok\n";
    } else {
      response.result(http::status::service_unavailable);
      response.body() =
          "backend " + options_.backend->address() + " not serving: " + backend.detail + "\n";
    }
  }

  std::string Peer() {
    beast::error_code ec;
    const tcp::endpoint remote = stream_.socket().remote_endpoint(ec);
    return ec ? "?" : remote.address().to_string();
  }

  // A refusal's log line, at most one a second (a client retrying in a
  // loop must not flood the log); the ones left out are counted.
  static void LogRefusal(const std::string& line) {
    static std::chrono::steady_clock::time_point last{};
    static uint64_t suppressed = 0;
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::seconds(1)) {
      suppressed += 1;
      return;
    }
    last = now;
    Log(LogLevel::kWarning,
        line + (suppressed > 0 ? " (and " + std::to_string(suppressed) + " more since the last)"
                               : ""));
    suppressed = 0;
  }

  void Send(const std::shared_ptr<http::response<http::string_body>>& response) {
    Metrics().RequestAnswered(path_, response->result_int());
    response->prepare_payload();
    stream_.expires_after(kHeaderTimeout);  // a reader that never reads is closed too
    http::async_write(stream_, *response,
                      [self = shared_from_this(), response](beast::error_code, std::size_t) {
                        beast::error_code ignored;
                        self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
                      });
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
  const ViewerOptions& options_;
  const bool metrics_port_;
  std::string path_;  // the request's path, for the request counter
  PendingConnections::List::iterator slot_;
  bool registered_ = false;
};

bool PendingConnections::CloseOldest() {
  while (!pending_.empty()) {
    std::shared_ptr<HttpSession> oldest = pending_.front().lock();
    if (!oldest) {
      pending_.pop_front();  // (a session unregisters as it ends; defensive)
      continue;
    }
    closed_ += 1;
    oldest->Close();  // unregisters it
    return true;
  }
  return false;
}

void Accept(tcp::acceptor& acceptor, net::steady_timer& back_off, const ViewerOptions& options,
            bool metrics_port) {
  acceptor.async_accept(
      [&acceptor, &back_off, &options, metrics_port](beast::error_code ec, tcp::socket socket) {
        if (!ec) {
          std::make_shared<HttpSession>(std::move(socket), options, metrics_port)->Start();
          Accept(acceptor, back_off, options, metrics_port);
          return;
        }
        if (ec == boost::system::errc::too_many_files_open ||
            ec == boost::system::errc::too_many_files_open_in_system) {
          // Out of descriptors: free the oldest pending connection's and try
          // again shortly rather than spinning on the same error.
          const bool freed = Pending().CloseOldest();
          static uint64_t logged = 0;
          if (logged++ % 1000 == 0) {
            Log(LogLevel::kWarning,
                "accept: " + ec.message() + " (" +
                    (freed ? "closed the oldest pending connection" : "none pending") +
                    "; backing off)");
          }
          back_off.expires_after(kAcceptBackOff);
          back_off.async_wait([&acceptor, &back_off, &options, metrics_port](beast::error_code) {
            Accept(acceptor, back_off, options, metrics_port);
          });
          return;
        }
        Accept(acceptor, back_off, options, metrics_port);
      });
}

// Binds and listens on `address` ("HOST:PORT", port 0 picks one) for the
// flag `flag`; 0, else the exit code after printing why.
int Listen(tcp::acceptor& acceptor, const std::string& address, const char* flag) {
  const size_t colon = address.rfind(':');
  if (colon == std::string::npos) {
    std::cerr << "error: " << flag << ": expected HOST:PORT, got '" << address << "'\n";
    return 2;
  }
  beast::error_code ec;
  const auto host = net::ip::make_address(address.substr(0, colon), ec);
  if (ec) {
    std::cerr << "error: " << flag << ": " << ec.message() << "\n";
    return 2;
  }
  const std::string port_text = address.substr(colon + 1);
  char* end = nullptr;
  const long port = std::strtol(port_text.c_str(), &end, 10);
  if (port_text.empty() || *end != '\0' || port < 0 || port > 65535) {
    std::cerr << "error: " << flag << ": port '" << port_text << "' is not 0..65535\n";
    return 2;
  }
  const tcp::endpoint endpoint(host, uint16_t(port));
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    std::cerr << "error: " << flag << " " << address << ": " << ec.message() << "\n";
    return 1;
  }
  return 0;
}

std::string Bound(const tcp::acceptor& acceptor) {
  const tcp::endpoint bound = acceptor.local_endpoint();
  return bound.address().to_string() + ":" + std::to_string(bound.port());
}

}  // namespace

int Serve(const std::string& address, const ViewerOptions& options,
          const std::function<void(const std::string&)>& on_listening) {
  net::io_context io{1};
  tcp::acceptor acceptor(io), metrics(io);
  if (const int rc = Listen(acceptor, address, "--listen"); rc != 0) return rc;
  if (!options.metrics_listen.empty()) {
    if (const int rc = Listen(metrics, options.metrics_listen, "--metrics-listen"); rc != 0) {
      return rc;
    }
  }
  on_listening(Bound(acceptor));
  net::steady_timer back_off(io), metrics_back_off(io);
  Accept(acceptor, back_off, options, false);
  if (metrics.is_open()) {
    const std::string bound = Bound(metrics);
    std::cout << "metrics on http://" << bound << "/metrics" << std::endl;
    Log(LogLevel::kInfo, "metrics on http://" + bound + "/metrics");
    Accept(metrics, metrics_back_off, options, true);
  }
  io.run();
  return 0;
}

}  // namespace gistream::web
