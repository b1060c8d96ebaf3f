#include "tools/series_stretches.h"

#include <cstdio>
#include <set>

#include "libbead/core/error.h"

namespace bead::tools {

ProcessOn SeriesStretches(const Series& s, const std::string& path, bool keep_off, const std::string& purpose) {
  ProcessOn on;
  if (keep_off) {
    on.segments = WholeRecord(s.t.size());
  } else {
    on = FindProcessOn(s.t, s.u, s.y);
    if (!on.excluded.empty())
      std::printf("%s: left out of the fit: %s\n", path.c_str(), DescribeExclusions(on.excluded).c_str());
  }
  if (on.segments.empty()) throw Error(Located(path, "", "no stretch where the process ran: nothing to " + purpose));
  return on;
}

void CheckValidationInput(const std::string& input_file, const std::string& validate,
                          const std::string& validate_input_file) {
  if (!validate_input_file.empty() && validate.empty())
    throw Error("--validate-input-file is the input of the --validate run: give --validate too");
  if (!validate_input_file.empty() && input_file.empty())
    throw Error("--validate-input-file needs --input-file (the estimation run's input in its own file)");
  if (!validate.empty() && !input_file.empty() && validate_input_file.empty())
    throw Error("--validate " + validate + " with --input-file needs --validate-input-file (that run's own input CSV)");
}

void PrintFileNote(const std::string& note) {
  static std::set<std::string> told;
  if (!note.empty() && told.insert(note).second) std::printf("%s\n", note.c_str());
}

}  // namespace bead::tools
