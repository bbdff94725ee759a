// Transport security and bearer tokens at the gRPC boundary, against
// FakeEngine: TLS and mutual TLS round trips with certificates made for the
// test, plaintext refused off loopback, UNAUTHENTICATED for a missing or
// unknown token before the request body is parsed, however malformed or
// large (over TLS, loopback and --insecure), health open without a token
// and on its own plaintext port.
#include <absl/strings/match.h>
#include <gtest/gtest.h>
#include <grpcpp/generic/generic_stub.h>

#include "fake_engine.h"
#include "test_certs.h"
#include "test_server.h"

namespace gistream::testing {
namespace auth_test {

using namespace std::chrono_literals;
using ::grpc::health::v1::HealthCheckRequest;
using ::grpc::health::v1::HealthCheckResponse;

constexpr const char* kAliceToken = "alice-token-0123456789";
constexpr const char* kBobToken = "bob-token-abcdefghijkl";

std::shared_ptr<const AuthTokens> Tokens() {
  absl::StatusOr<AuthTokens> tokens =
      AuthTokens::Parse(absl::StrCat(kAliceToken, " alice scenes=2\n", kBobToken, " bob\n"));
  EXPECT_TRUE(tokens.ok()) << tokens.status();
  return std::make_shared<const AuthTokens>(*std::move(tokens));
}

class AuthTest : public ::testing::Test {
 protected:
  // Starts a server on 127.0.0.1 (or `listen`) with `options`.
  void Start(service::ServerOptions options, const std::string& listen = "127.0.0.1:0") {
    options.listen = listen;
    auto server = service::GistreamServer::Start(engine_, options);
    ASSERT_TRUE(server.ok()) << server.status();
    server_ = *std::move(server);
  }
  std::string Target() const { return absl::StrCat("localhost:", server_->port()); }

  std::shared_ptr<grpc::Channel> TlsChannel(bool client_cert) const {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = Certs().ca;
    if (client_cert) {
      ssl.pem_private_key = Certs().client_key;
      ssl.pem_cert_chain = Certs().client_cert;
    }
    return grpc::CreateChannel(Target(), grpc::SslCredentials(ssl));
  }
  std::shared_ptr<grpc::Channel> PlainChannel() const {
    return grpc::CreateChannel(Target(), grpc::InsecureChannelCredentials());
  }

  // ListSolvers with `token` ("" sends no authorization header).
  static grpc::Status Call(const std::shared_ptr<grpc::Channel>& channel,
                           const std::string& header = "") {
    grpc::ClientContext context;
    SetDeadline(&context, 10s);
    if (!header.empty()) context.AddMetadata("authorization", header);
    pb::ListSolversRequest request;
    pb::ListSolversResponse response;
    return pb::Gistream::NewStub(channel)->ListSolvers(&context, request, &response);
  }

  static HealthCheckResponse::ServingStatus Health(const std::shared_ptr<grpc::Channel>& channel) {
    grpc::ClientContext context;
    SetDeadline(&context, 10s);
    HealthCheckRequest request;
    HealthCheckResponse response;
    const grpc::Status status =
        ::grpc::health::v1::Health::NewStub(channel)->Check(&context, request, &response);
    EXPECT_TRUE(status.ok()) << status.error_code() << ": " << status.error_message();
    return response.status();
  }

  // The gistream.v1 token checks every transport must make.
  void ExpectTokensChecked(const std::shared_ptr<grpc::Channel>& channel) {
    const grpc::Status none = Call(channel);
    EXPECT_EQ(none.error_code(), grpc::StatusCode::UNAUTHENTICATED) << none.error_message();
    EXPECT_TRUE(absl::StrContains(none.error_message(), "authorization: missing"))
        << none.error_message();
    const grpc::Status wrong = Call(channel, "Bearer not-a-listed-token-at-all");
    EXPECT_EQ(wrong.error_code(), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_TRUE(absl::StrContains(wrong.error_message(), "unknown token")) << wrong.error_message();
    EXPECT_FALSE(absl::StrContains(wrong.error_message(), "not-a-listed")) << "echoes the token";
    const grpc::Status basic = Call(channel, absl::StrCat("Basic ", kAliceToken));
    EXPECT_EQ(basic.error_code(), grpc::StatusCode::UNAUTHENTICATED);
    const grpc::Status good = Call(channel, absl::StrCat("Bearer ", kAliceToken));
    EXPECT_TRUE(good.ok()) << good.error_message();
    EXPECT_EQ(Health(channel), HealthCheckResponse::SERVING);  // no token needed

    // A Session without a token ends before its first message is read.
    grpc::ClientContext context;
    SetDeadline(&context, 10s);
    auto stream = pb::Gistream::NewStub(channel)->Session(&context);
    stream->Write(ConfigRequest("x", 16, 16, true));
    stream->WritesDone();
    pb::SessionEvent event;
    EXPECT_FALSE(stream->Read(&event));
    EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }

  // Bytes that are no LoadSceneRequest, sent to LoadScene: the status says
  // whether the body was parsed before the token was checked.
  static grpc::Status SendGarbage(
      const std::shared_ptr<grpc::Channel>& channel, const std::string& header,
      const std::string& junk = "\xff\xff\xff\xff\xff\xff\xff\xff\x0f") {
    grpc::GenericStub stub(channel);
    grpc::ClientContext context;
    SetDeadline(&context, 10s);
    if (!header.empty()) context.AddMetadata("authorization", header);
    grpc::Slice slice(junk);
    grpc::ByteBuffer request(&slice, 1);
    grpc::ByteBuffer response;
    std::mutex mutex;
    std::condition_variable cv;
    bool done = false;
    grpc::Status result;
    stub.UnaryCall(&context, "/gistream.v1.Gistream/LoadScene", grpc::StubOptions(), &request,
                   &response, [&](grpc::Status status) {
                     std::lock_guard lock(mutex);
                     result = status;
                     done = true;
                     cv.notify_all();
                   });
    std::unique_lock lock(mutex);
    cv.wait(lock, [&] { return done; });
    return result;
  }

  FakeEngine engine_;
  std::unique_ptr<service::GistreamServer> server_;
};

TEST_F(AuthTest, TlsRoundTripAndNoPlaintext) {
  service::ServerOptions options;
  options.tls = {Certs().server_cert, Certs().server_key, ""};
  Start(options);
  const grpc::Status tls = Call(TlsChannel(/*client_cert=*/false));
  EXPECT_TRUE(tls.ok()) << tls.error_code() << ": " << tls.error_message();
  EXPECT_EQ(Call(PlainChannel()).error_code(), grpc::StatusCode::UNAVAILABLE);
}

TEST_F(AuthTest, MutualTlsNeedsAClientCertificateFromTheCa) {
  service::ServerOptions options;
  options.tls = {Certs().server_cert, Certs().server_key, Certs().ca};
  Start(options);
  const grpc::Status with_cert = Call(TlsChannel(/*client_cert=*/true));
  EXPECT_TRUE(with_cert.ok()) << with_cert.error_code() << ": " << with_cert.error_message();
  EXPECT_EQ(Call(TlsChannel(/*client_cert=*/false)).error_code(), grpc::StatusCode::UNAVAILABLE);
}

TEST_F(AuthTest, TokensOverTls) {
  service::ServerOptions options;
  options.tls = {Certs().server_cert, Certs().server_key, ""};
  options.service.tokens = Tokens();
  Start(options);
  ExpectTokensChecked(TlsChannel(false));
}

TEST_F(AuthTest, TokensOverLoopbackPlaintext) {
  service::ServerOptions options;
  options.service.tokens = Tokens();
  Start(options);
  ExpectTokensChecked(PlainChannel());
}

TEST_F(AuthTest, TokensOverInsecureListener) {
  service::ServerOptions options;
  options.service.tokens = Tokens();
  options.allow_insecure = true;
  Start(options, "0.0.0.0:0");
  ExpectTokensChecked(PlainChannel());
}

TEST_F(AuthTest, UnknownCallerIsRejectedBeforeTheBodyIsParsed) {
  service::ServerOptions options;
  options.service.tokens = Tokens();
  options.max_receive_message_bytes = 1 << 20;
  enum class Listener { kTls, kLoopback, kInsecure };
  for (Listener listener : {Listener::kTls, Listener::kLoopback, Listener::kInsecure}) {
    SCOPED_TRACE(listener == Listener::kTls        ? "TLS"
                 : listener == Listener::kLoopback ? "loopback"
                                                   : "--insecure on 0.0.0.0");
    options.tls = listener == Listener::kTls
                      ? service::TlsFiles{Certs().server_cert, Certs().server_key, ""}
                      : service::TlsFiles{};
    options.allow_insecure = listener == Listener::kInsecure;
    Start(options, listener == Listener::kInsecure ? "0.0.0.0:0" : "127.0.0.1:0");
    const auto channel = listener == Listener::kTls ? TlsChannel(false) : PlainChannel();
    EXPECT_EQ(SendGarbage(channel, "").error_code(), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_EQ(SendGarbage(channel, "Bearer unknown-token-0123456789").error_code(),
              grpc::StatusCode::UNAUTHENTICATED);
    // A body over the message limit: refused for its token, not its size.
    const std::string large(2 << 20, '\x01');
    EXPECT_EQ(SendGarbage(channel, "", large).error_code(), grpc::StatusCode::UNAUTHENTICATED);
    const grpc::Status too_large =
        SendGarbage(channel, absl::StrCat("Bearer ", kAliceToken), large);
    EXPECT_EQ(too_large.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED)
        << too_large.error_message();
    // With a token the same bytes reach the parser, which refuses them.
    const grpc::Status parsed = SendGarbage(channel, absl::StrCat("Bearer ", kAliceToken));
    EXPECT_NE(parsed.error_code(), grpc::StatusCode::UNAUTHENTICATED);
    EXPECT_NE(parsed.error_code(), grpc::StatusCode::OK);
    // Health stays open without a token on every listener.
    EXPECT_EQ(Health(channel), HealthCheckResponse::SERVING);
    server_.reset();
  }
}

TEST_F(AuthTest, HealthListenerServesHealthAloneInPlaintext) {
  service::ServerOptions options;
  options.tls = {Certs().server_cert, Certs().server_key, ""};
  options.service.tokens = Tokens();
  options.health_listen = "127.0.0.1:0";
  Start(options);
  ASSERT_GT(server_->health_port(), 0);
  const auto health = grpc::CreateChannel(absl::StrCat("127.0.0.1:", server_->health_port()),
                                          grpc::InsecureChannelCredentials());
  EXPECT_EQ(Health(health), HealthCheckResponse::SERVING);
  const grpc::Status gistream = Call(health, absl::StrCat("Bearer ", kAliceToken));
  EXPECT_EQ(gistream.error_code(), grpc::StatusCode::UNIMPLEMENTED) << gistream.error_message();
  server_->SetNotServing();
  EXPECT_EQ(Health(health), HealthCheckResponse::NOT_SERVING);
}

TEST_F(AuthTest, PlaintextOnlyOnLoopbackOrWhenAskedFor) {
  service::ServerOptions options;
  options.listen = "0.0.0.0:0";
  auto refused = service::GistreamServer::Start(engine_, options);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_TRUE(absl::StrContains(refused.status().message(), "--tls-cert")) << refused.status();
  options.allow_insecure = true;
  auto allowed = service::GistreamServer::Start(engine_, options);
  EXPECT_TRUE(allowed.ok()) << allowed.status();
  EXPECT_TRUE(service::IsLoopbackAddress("127.0.0.1:50051"));
  EXPECT_TRUE(service::IsLoopbackAddress("[::1]:50051"));
  EXPECT_TRUE(service::IsLoopbackAddress("localhost:0"));
  EXPECT_FALSE(service::IsLoopbackAddress("0.0.0.0:50051"));
  EXPECT_FALSE(service::IsLoopbackAddress("[::]:50051"));
  EXPECT_FALSE(service::IsLoopbackAddress(":50051"));
}

}  // namespace auth_test
}  // namespace gistream::testing
