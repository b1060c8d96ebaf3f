#include "tools/csv_columns.h"

#include <cmath>
#include <cstdlib>

#include "libbead/core/error.h"
#include "libbead/io/csv_reader.h"

namespace bead::tools {

Series ReadColumns(const std::string& path, const std::string& time, const std::string& input, const std::string& output) {
  CsvReader csv(path);
  const auto header = csv.Header({}, "data CSV with a header row");
  auto find = [&](const std::string& name) -> long {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<long>(i);
    std::string all;
    for (const auto& h : header) all += (all.empty() ? "" : ", ") + h;
    throw Error(Located(path, "line 1", "no column '" + name + "' (columns: " + all + ")"));
  };
  const long ti = time.empty() ? -1 : find(time), ui = find(input), yi = find(output);
  Series s;
  long row = 0;
  while (csv.Next()) {
    ++row;
    double v[3];
    bool ok = true;
    const long cols[3] = {ti, ui, yi};
    for (int k = 0; k < 3; ++k) {
      if (cols[k] < 0) {
        v[k] = static_cast<double>(row - 1);
        continue;
      }
      if (static_cast<std::size_t>(cols[k]) >= csv.columns() || csv.Empty(static_cast<std::size_t>(cols[k]))) {
        ok = false;
        break;
      }
      char* end = nullptr;
      const std::string f(csv.Field(static_cast<std::size_t>(cols[k])));
      v[k] = std::strtod(f.c_str(), &end);
      ok = ok && end && *end == '\0' && std::isfinite(v[k]);
    }
    if (!ok) {
      ++s.skipped;
      continue;
    }
    if (!s.t.empty() && !(v[0] > s.t.back()))
      csv.Fail("time does not increase (" + std::to_string(s.t.back()) + " then " + std::to_string(v[0]) + ")");
    s.t.push_back(v[0]);
    s.u.push_back(v[1]);
    s.y.push_back(v[2]);
  }
  if (s.t.size() < 20) throw Error(Located(path, "", "fewer than 20 usable rows"));
  return s;
}

}  // namespace bead::tools
