// gistream solvers
#include <iostream>

#include <google/protobuf/util/json_util.h>

#include "commands.h"
#include "connection.h"
#include "solver_list.h"

namespace gistream::client {

absl::Status RunSolvers(const ConnectionOptions& connection_options,
                        const SolversOptions& options) {
  Connection connection(connection_options);
  v1::ListSolversResponse response;
  GS_RETURN_IF_ERROR(
      connection.Call(&v1::Gistream::Stub::ListSolvers, v1::ListSolversRequest(), &response));
  if (options.json) {
    google::protobuf::util::JsonPrintOptions json_options;
    json_options.add_whitespace = true;
    json_options.always_print_primitive_fields = true;
    json_options.preserve_proto_field_names = true;
    std::string json;
    if (!google::protobuf::util::MessageToJsonString(response, &json, json_options).ok()) {
      return absl::InternalError("cannot print the solver list as JSON");
    }
    std::cout << json << "\n";
  } else {
    std::cout << FormatSolverList(response);
  }
  return absl::OkStatus();
}

}  // namespace gistream::client
