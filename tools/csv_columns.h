// Three named columns of any CSV with a header row (time, input, output),
// for the commands that take measured data from anywhere (identify,
// explain). Rows with an empty or non-numeric field in them are skipped as
// gaps, and counted; time must increase.
#pragma once

#include <string>
#include <vector>

namespace bead::tools {

struct Series {
  std::vector<double> t, u, y;
  int skipped = 0;
};

// Without a time column, rows are unit-spaced. Throws bead::Error naming
// the file and line.
Series ReadColumns(const std::string& path, const std::string& time, const std::string& input, const std::string& output);

}  // namespace bead::tools
