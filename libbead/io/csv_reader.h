// CsvReader: line-by-line reading of the simple comma-separated forms of
// docs/data-formats.md (no quoting needed: all fields are numbers).
// Every parse error names the file, line and column.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace bead {

class CsvReader {
 public:
  explicit CsvReader(const std::string& path);

  // Reads the header and checks it starts with `required` (in order);
  // returns the header's columns.
  std::vector<std::string> Header(const std::vector<std::string>& required, const std::string& form);
  // Next data row; false at the end. Blank lines are skipped.
  bool Next();

  std::size_t columns() const { return fields_.size(); }
  std::size_t line() const { return line_; }
  const std::string& path() const { return path_; }
  std::string_view Field(std::size_t i) const;
  bool Empty(std::size_t i) const { return Field(i).empty(); }
  double Double(std::size_t i, const char* name) const;
  // A coordinate: an empty field means no point (NaN).
  float Coordinate(std::size_t i, const char* name) const;
  int64_t Int64(std::size_t i, const char* name) const;
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  void Split();

  std::string path_;
  std::ifstream in_;
  std::string text_;
  std::vector<std::string_view> fields_;
  std::size_t line_ = 0;
};

// Shortest text that reads back to the same double; "" for NaN.
std::string CsvNumber(double value);
// The same appended to `line` (no allocation once the line has room).
void AppendCsvNumber(std::string& line, double value);

}  // namespace bead
