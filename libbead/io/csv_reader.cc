#include "libbead/io/csv_reader.h"

#include <charconv>
#include <cmath>
#include <limits>

#include "libbead/core/error.h"

namespace bead {

CsvReader::CsvReader(const std::string& path) : path_(path), in_(path) {
  if (!in_) throw Error(Located(path, "", "cannot open CSV file"));
}

void CsvReader::Fail(const std::string& what) const {
  throw Error(Located(path_, "line " + std::to_string(line_), what));
}

void CsvReader::Split() {
  if (!text_.empty() && text_.back() == '\r') text_.pop_back();
  fields_.clear();
  std::string_view rest(text_);
  while (true) {
    const std::size_t comma = rest.find(',');
    std::string_view f = rest.substr(0, comma);
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\t')) f.remove_suffix(1);
    fields_.push_back(f);
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
}

std::vector<std::string> CsvReader::Header(const std::vector<std::string>& required, const std::string& form) {
  if (!std::getline(in_, text_)) {
    line_ = 1;
    Fail("empty file: expected the " + form + " header");
  }
  ++line_;
  if (text_.size() >= 3 && text_.compare(0, 3, "\xEF\xBB\xBF") == 0) text_.erase(0, 3);  // UTF-8 BOM
  Split();
  std::string want;
  for (const auto& r : required) want += (want.empty() ? "" : ",") + r;
  if (fields_.size() < required.size()) Fail("header must start with " + want + " (" + form + ")");
  for (std::size_t i = 0; i < required.size(); ++i)
    if (fields_[i] != required[i])
      Fail("column " + std::to_string(i + 1) + " of the header is '" + std::string(fields_[i]) + "', expected '" +
           required[i] + "' (" + form + " header: " + want + ")");
  return {fields_.begin(), fields_.end()};
}

bool CsvReader::Next() {
  while (std::getline(in_, text_)) {
    ++line_;
    if (text_.find_first_not_of(" \t\r") == std::string::npos) continue;
    Split();
    return true;
  }
  return false;
}

std::string_view CsvReader::Field(std::size_t i) const {
  if (i >= fields_.size())
    Fail("has " + std::to_string(fields_.size()) + " fields, expected at least " + std::to_string(i + 1));
  return fields_[i];
}

double CsvReader::Double(std::size_t i, const char* name) const {
  const std::string_view f = Field(i);
  double v = 0;
  const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (f.empty() || ec != std::errc() || end != f.data() + f.size())
    Fail("column " + std::to_string(i + 1) + " (" + name + ") is '" + std::string(f) + "', not a number");
  return v;
}

float CsvReader::Coordinate(std::size_t i, const char* name) const {
  return Empty(i) ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(Double(i, name));
}

int64_t CsvReader::Int64(std::size_t i, const char* name) const {
  const std::string_view f = Field(i);
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (f.empty() || ec != std::errc() || end != f.data() + f.size())
    Fail("column " + std::to_string(i + 1) + " (" + name + ") is '" + std::string(f) + "', not a whole number");
  return v;
}

void AppendCsvNumber(std::string& line, double value) {
  if (std::isnan(value)) return;
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), value);
  if (ec == std::errc()) line.append(buf, end);
}

std::string CsvNumber(double value) {
  std::string text;
  AppendCsvNumber(text, value);
  return text;
}

}  // namespace bead
