// gistream: the thin command-line client of gistreamd. Parses the command
// line, dispatches to one command, and turns its outcome into an exit code:
// 0 success, 1 error, 2 usage error, 130 interrupted.
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <absl/status/status.h>

#include "commands.h"
#include "connection.h"
#include "interrupt.h"
#include "options.h"
#include "usage.h"
#include "util/version.h"

namespace {

using namespace gistream::client;

constexpr int kExitError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitInterrupted = 130;

absl::Status Dispatch(const CommandLine& line) {
  const ConnectionOptions& connection = line.connection;
  switch (*line.command) {
    case Command::kSolvers: return RunSolvers(connection, std::get<SolversOptions>(line.options));
    case Command::kStatus: return RunStatus(connection, std::get<StatusOptions>(line.options));
    case Command::kRender: return RunRender(connection, std::get<RenderOptions>(line.options));
    case Command::kStream: return RunStream(connection, std::get<StreamOptions>(line.options));
    case Command::kScript: return RunScript(connection, std::get<ScriptOptions>(line.options));
    case Command::kEval: return RunEval(connection, std::get<EvalOptions>(line.options));
    case Command::kBench: return RunBench(connection, std::get<BenchOptions>(line.options));
    case Command::kHealth: return RunHealth(connection, std::get<HealthOptions>(line.options));
  }
  return absl::InternalError("unknown command");
}

}  // namespace

int main(int argc, char** argv) {
  // First, before gRPC starts threads: Ctrl-C goes to the watcher thread.
  InterruptWatcher interrupts;

  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 1 && args[0] == "--version") {
    std::cout << "gistream " << gistream::Version() << "\n";
    return 0;
  }
  const char* env_server = std::getenv("GISTREAM_SERVER");
  const auto line = ParseCommandLine(
      args, env_server != nullptr && *env_server != '\0' ? env_server : kDefaultServer);
  if (!line.ok()) {
    std::cerr << "gistream: " << line.status().message() << "\n"
              << "Run 'gistream --help' for usage.\n";
    return kExitUsage;
  }
  // $GISTREAM_TOKEN: a token out of the process list (ps shows --token).
  CommandLine command_line = *line;
  if (const char* token = std::getenv("GISTREAM_TOKEN");
      command_line.connection.token.empty() && token != nullptr) {
    command_line.connection.token = token;
  }
  if (const char* affinity = std::getenv("GISTREAM_AFFINITY");
      command_line.connection.affinity.empty() && affinity != nullptr && *affinity != '\0') {
    command_line.connection.affinity = affinity;
  }
  if (line->help) {
    std::cout << HelpText(line->command);
    return 0;
  }

  const absl::Status status = Dispatch(command_line);
  if (status.ok()) return 0;
  std::cout.flush();
  if (IsInterrupted(status)) {
    std::cerr << "gistream: " << status.message() << "\n";
    return kExitInterrupted;
  }
  if (IsRpcError(status)) {
    std::cerr << "error: " << absl::StatusCodeToString(status.code()) << ": " << status.message()
              << "\n";
  } else {
    std::cerr << "error: " << status.message() << "\n";
  }
  return kExitError;
}
