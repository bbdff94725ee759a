#include "service/reflection_v1.h"

#include <set>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

namespace gistream::service {
namespace {

namespace reflection_pb = grpc::reflection::v1;
using google::protobuf::DescriptorPool;
using google::protobuf::FileDescriptor;

// The file, then its dependencies depth first, each once.
void AddFile(const FileDescriptor* file, std::set<std::string>& seen,
             reflection_pb::FileDescriptorResponse& out) {
  if (file == nullptr || !seen.insert(file->name()).second) return;
  google::protobuf::FileDescriptorProto proto;
  file->CopyTo(&proto);
  out.add_file_descriptor_proto(proto.SerializeAsString());
  for (int i = 0; i < file->dependency_count(); ++i) AddFile(file->dependency(i), seen, out);
}

void Error(reflection_pb::ServerReflectionResponse& response, grpc::StatusCode code,
           std::string message) {
  response.mutable_error_response()->set_error_code(int(code));
  response.mutable_error_response()->set_error_message(std::move(message));
}

}  // namespace

reflection_pb::ServerReflectionResponse ReflectionV1::Answer(
    const reflection_pb::ServerReflectionRequest& request) const {
  reflection_pb::ServerReflectionResponse response;
  response.set_valid_host(request.host());
  *response.mutable_original_request() = request;
  const DescriptorPool* pool = DescriptorPool::generated_pool();
  std::set<std::string> seen;
  switch (request.message_request_case()) {
    case reflection_pb::ServerReflectionRequest::kListServices:
      for (const std::string& name : services_) {
        response.mutable_list_services_response()->add_service()->set_name(name);
      }
      break;
    case reflection_pb::ServerReflectionRequest::kFileByFilename: {
      const FileDescriptor* file = pool->FindFileByName(request.file_by_filename());
      if (file == nullptr) {
        Error(response, grpc::StatusCode::NOT_FOUND, "file not found");
      } else {
        AddFile(file, seen, *response.mutable_file_descriptor_response());
      }
      break;
    }
    case reflection_pb::ServerReflectionRequest::kFileContainingSymbol: {
      const FileDescriptor* file = pool->FindFileContainingSymbol(request.file_containing_symbol());
      if (file == nullptr) {
        Error(response, grpc::StatusCode::NOT_FOUND, "symbol not found");
      } else {
        AddFile(file, seen, *response.mutable_file_descriptor_response());
      }
      break;
    }
    case reflection_pb::ServerReflectionRequest::kFileContainingExtension: {
      const auto* type =
          pool->FindMessageTypeByName(request.file_containing_extension().containing_type());
      const auto* extension =
          type ? pool->FindExtensionByNumber(type,
                                             request.file_containing_extension().extension_number())
               : nullptr;
      if (extension == nullptr) {
        Error(response, grpc::StatusCode::NOT_FOUND, "extension not found");
      } else {
        AddFile(extension->file(), seen, *response.mutable_file_descriptor_response());
      }
      break;
    }
    case reflection_pb::ServerReflectionRequest::kAllExtensionNumbersOfType: {
      const auto* type = pool->FindMessageTypeByName(request.all_extension_numbers_of_type());
      if (type == nullptr) {
        Error(response, grpc::StatusCode::NOT_FOUND, "type not found");
        break;
      }
      std::vector<const google::protobuf::FieldDescriptor*> extensions;
      pool->FindAllExtensions(type, &extensions);
      auto* numbers = response.mutable_all_extension_numbers_response();
      numbers->set_base_type_name(type->full_name());
      for (const auto* e : extensions) numbers->add_extension_number(e->number());
      break;
    }
    case reflection_pb::ServerReflectionRequest::MESSAGE_REQUEST_NOT_SET:
    default: Error(response, grpc::StatusCode::INVALID_ARGUMENT, "message_request: not set"); break;
  }
  return response;
}

grpc::Status ReflectionV1::ServerReflectionInfo(
    grpc::ServerContext* /*context*/,
    grpc::ServerReaderWriter<reflection_pb::ServerReflectionResponse,
                             reflection_pb::ServerReflectionRequest>* stream) {
  reflection_pb::ServerReflectionRequest request;
  while (stream->Read(&request)) {
    if (!stream->Write(Answer(request))) break;
  }
  return grpc::Status::OK;
}

}  // namespace gistream::service
