// Column-aligned plain-text tables for terminal output:
//
//   stage       | runs | CPU median
//   ------------+------+-----------
//   shadow_maps |   30 |       0.12
#pragma once

#include <string>
#include <vector>

namespace gistream::client {

class TextTable {
 public:
  enum class Align { kLeft, kRight };

  struct Column {
    std::string header;
    Align align = Align::kLeft;
  };

  explicit TextTable(std::vector<Column> columns);

  // Missing cells print empty; extra cells are an error in our code.
  void AddRow(std::vector<std::string> cells);

  // Every line ends with '\n'; `indent` is prepended to each.
  std::string Render(const std::string& indent = "") const;

 private:
  std::vector<Column> columns_;
  std::vector<std::vector<std::string>> rows_;
};

// "12.35" (fixed, `digits` decimals); the way every millisecond value prints.
std::string FormatFixed(double value, int digits = 2);

}  // namespace gistream::client
