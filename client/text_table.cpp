#include "text_table.h"

#include <algorithm>
#include <cstdio>

#include "util/status.h"

namespace gistream::client {

TextTable::TextTable(std::vector<Column> columns) : columns_(std::move(columns)) {}

void TextTable::AddRow(std::vector<std::string> cells) {
  GS_CHECK(cells.size() <= columns_.size());
  cells.resize(columns_.size());
  rows_.push_back(std::move(cells));
}

std::string TextTable::Render(const std::string& indent) const {
  std::vector<size_t> widths(columns_.size());
  for (size_t c = 0; c < columns_.size(); ++c) {
    widths[c] = columns_[c].header.size();
    for (const auto& row : rows_) widths[c] = std::max(widths[c], row[c].size());
  }
  auto line = [&](const std::vector<std::string>& cells) {
    std::string out = indent;
    for (size_t c = 0; c < cells.size(); ++c) {
      if (c > 0) out += " | ";
      const std::string pad(widths[c] - cells[c].size(), ' ');
      const bool right = columns_[c].align == Align::kRight;
      // The last column is not padded on the right: no trailing blanks.
      const bool last = c + 1 == cells.size();
      out += right ? pad + cells[c] : cells[c] + (last ? "" : pad);
    }
    out += '\n';
    return out;
  };

  std::vector<std::string> headers;
  for (const auto& column : columns_) headers.push_back(column.header);
  std::string out = line(headers);
  out += indent;
  for (size_t c = 0; c < columns_.size(); ++c) {
    if (c > 0) out += "-+-";
    out += std::string(widths[c], '-');
  }
  out += '\n';
  for (const auto& row : rows_) out += line(row);
  return out;
}

std::string FormatFixed(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

}  // namespace gistream::client
