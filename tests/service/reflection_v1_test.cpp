// grpc.reflection.v1 over the wire (generic tools ask for it first): it
// lists the server's services, answers a symbol with the file that defines
// it (and the files that one imports), and an unknown name with NOT_FOUND.
#include <gtest/gtest.h>

#include <google/protobuf/descriptor.pb.h>

#include "fake_engine.h"
#include "grpc/reflection/v1/reflection.grpc.pb.h"
#include "test_server.h"

namespace gistream::testing {
namespace reflection_v1_test {

namespace rpb = ::grpc::reflection::v1;

class ReflectionV1Test : public ::testing::Test {
 protected:
  // Sends `requests` on one stream and returns the responses in order.
  std::vector<rpb::ServerReflectionResponse> Ask(
      const std::vector<rpb::ServerReflectionRequest>& requests) {
    auto stub = rpb::ServerReflection::NewStub(server_.channel());
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    auto stream = stub->ServerReflectionInfo(&context);
    std::vector<rpb::ServerReflectionResponse> out;
    for (const auto& request : requests) {
      EXPECT_TRUE(stream->Write(request));
      rpb::ServerReflectionResponse response;
      EXPECT_TRUE(stream->Read(&response));
      out.push_back(response);
    }
    stream->WritesDone();
    EXPECT_TRUE(stream->Finish().ok());
    return out;
  }

  FakeEngine engine_{EngineOptions{}};
  TestServer server_{engine_};
};

TEST_F(ReflectionV1Test, ListsServicesAndDescribesSymbols) {
  rpb::ServerReflectionRequest list, symbol, unknown;
  list.set_list_services("*");
  symbol.set_file_containing_symbol("gistream.v1.Gistream");
  unknown.set_file_containing_symbol("no.such.Service");
  const auto responses = Ask({list, symbol, unknown});
  ASSERT_EQ(responses.size(), 3u);

  std::vector<std::string> names;
  for (const auto& s : responses[0].list_services_response().service()) names.push_back(s.name());
  for (const char* expected :
       {"gistream.v1.Gistream", "grpc.health.v1.Health", "grpc.reflection.v1.ServerReflection"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }

  const auto& files = responses[1].file_descriptor_response().file_descriptor_proto();
  ASSERT_GE(files.size(), 1);
  google::protobuf::FileDescriptorProto file;
  ASSERT_TRUE(file.ParseFromString(files[0]));
  EXPECT_EQ(file.name(), "gistream/v1/gistream.proto");
  ASSERT_GE(file.service_size(), 1);
  EXPECT_EQ(file.service(0).name(), "Gistream");
  EXPECT_EQ(responses[1].original_request().file_containing_symbol(), "gistream.v1.Gistream");

  EXPECT_EQ(responses[2].error_response().error_code(), int(grpc::StatusCode::NOT_FOUND));
}

}  // namespace reflection_v1_test
}  // namespace gistream::testing
