// A small CSV written by the tool, read back as rows of cells (an empty
// last cell kept), for tests that check its columns.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace bead::test {

inline std::vector<std::vector<std::string>> CsvRows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    rows.push_back(cells);
  }
  return rows;
}

}  // namespace bead::test
