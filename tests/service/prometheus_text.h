// Test helpers for the metrics endpoint: a plain-socket HTTP/1.0 GET (no
// HTTP library, as a scraper on another machine would see the server) and a
// parser of the Prometheus text exposition format into samples.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace gistream::testing {

struct HttpResponse {
  int status = 0;  // 0: no connection or no status line
  std::string body;
};

// GET http://127.0.0.1:port/path (with `headers`, each "Name: value\r\n");
// reads until the server closes.
inline HttpResponse HttpGet(int port, const std::string& path, const std::string& headers = "") {
  HttpResponse out;
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return out;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) {
    ::close(fd);
    return out;
  }
  timeval timeout{20, 0};  // a hung server fails the test instead of hanging it
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
  const std::string request = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n" + headers + "\r\n";
  if (::send(fd, request.data(), request.size(), 0) != static_cast<ssize_t>(request.size())) {
    ::close(fd);
    return out;
  }
  std::string response;
  char buffer[8192];
  for (ssize_t n; (n = ::recv(fd, buffer, sizeof(buffer), 0)) > 0;) response.append(buffer, n);
  ::close(fd);
  // "HTTP/1.1 200 OK\r\n...headers...\r\n\r\nbody"
  const size_t space = response.find(' ');
  const size_t header_end = response.find("\r\n\r\n");
  if (space == std::string::npos || header_end == std::string::npos) return out;
  out.status = std::atoi(response.c_str() + space + 1);
  out.body = response.substr(header_end + 4);
  return out;
}

struct Sample {
  std::string name;
  std::map<std::string, std::string> labels;
  double value = 0.0;
};

// One sample per non-comment line: name{k="v",...} value [timestamp].
// Returns nothing if a line does not parse.
inline std::optional<std::vector<Sample>> ParsePrometheusText(const std::string& text) {
  std::vector<Sample> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    Sample s;
    size_t i = 0;
    while (i < line.size() && line[i] != '{' && line[i] != ' ') ++i;
    s.name = line.substr(0, i);
    if (s.name.empty()) return std::nullopt;
    if (i < line.size() && line[i] == '{') {
      ++i;
      while (i < line.size() && line[i] != '}') {
        const size_t eq = line.find("=\"", i);
        if (eq == std::string::npos) return std::nullopt;
        const std::string key = line.substr(i, eq - i);
        std::string value;
        size_t j = eq + 2;
        for (; j < line.size() && line[j] != '"'; ++j) {
          if (line[j] == '\\' && j + 1 < line.size()) ++j;  // \" \\ \n
          value += line[j];
        }
        if (j >= line.size()) return std::nullopt;
        s.labels[key] = value;
        i = j + 1;
        if (i < line.size() && line[i] == ',') ++i;
      }
      if (i >= line.size()) return std::nullopt;
      ++i;  // '}'
    }
    std::istringstream rest(line.substr(i));
    std::string number;
    if (!(rest >> number)) return std::nullopt;
    char* end = nullptr;
    s.value = std::strtod(number.c_str(), &end);  // also "NaN", "+Inf"
    if (end == number.c_str()) return std::nullopt;
    out.push_back(std::move(s));
  }
  return out;
}

// Sum of the samples called `name` whose labels include every pair of `match`.
inline double Sum(const std::vector<Sample>& samples, const std::string& name,
                  const std::map<std::string, std::string>& match = {}) {
  double total = 0.0;
  for (const Sample& s : samples) {
    if (s.name != name) continue;
    bool ok = true;
    for (const auto& [k, v] : match) {
      auto it = s.labels.find(k);
      ok = ok && it != s.labels.end() && it->second == v;
    }
    if (ok) total += s.value;
  }
  return total;
}

// Whether any sample is called `name` with labels including `match`.
inline bool Has(const std::vector<Sample>& samples, const std::string& name,
                const std::map<std::string, std::string>& match = {}) {
  for (const Sample& s : samples) {
    if (s.name != name) continue;
    bool ok = true;
    for (const auto& [k, v] : match) {
      auto it = s.labels.find(k);
      ok = ok && it != s.labels.end() && it->second == v;
    }
    if (ok) return true;
  }
  return false;
}

}  // namespace gistream::testing
