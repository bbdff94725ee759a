// A throw-away CA with a server (localhost, 127.0.0.1) and a client
// certificate, made once per test binary by scripts/dev_certs.sh (openssl).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace gistream::testing {

struct TestCerts {
  std::string ca, server_cert, server_key, client_cert, client_key;  // PEM
};

inline std::string ReadPemFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline const TestCerts& Certs() {
  static const TestCerts certs = [] {
    char dir_template[] = "/tmp/gistream-certs-XXXXXX";
    const char* dir = mkdtemp(dir_template);
    EXPECT_NE(dir, nullptr);
    const std::string command = std::string(GISTREAM_SOURCE_DIR "/scripts/dev_certs.sh ") + dir;
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    const std::filesystem::path d(dir);
    TestCerts c{ReadPemFile(d / "ca.crt"), ReadPemFile(d / "server.crt"),
                ReadPemFile(d / "server.key"), ReadPemFile(d / "client.crt"),
                ReadPemFile(d / "client.key")};
    std::filesystem::remove_all(d);
    EXPECT_NE(c.server_cert.find("BEGIN CERTIFICATE"), std::string::npos);
    return c;
  }();
  return certs;
}

}  // namespace gistream::testing
