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

void CheckInputClocks(const SeriesNames& n, const std::string& validate) {
  if (n.inputs.size() > 1 && (!n.input_file.empty() || !n.input_time.empty()))
    throw Error("several inputs are read from DATA on its own clock: --input-file and --input-time take one input");
  CheckValidationInput(n.input_file, validate, n.validate_input_file);
}

Series ReadOneInputSeries(const SeriesNames& n, const std::string& path, const std::string& shown) {
  const std::string in_file = path == n.data ? n.input_file : n.validate_input_file;
  const std::string in_time = !n.input_time.empty() ? n.input_time : in_file.empty() ? "" : n.time;
  Series s = ReadSeries({path, n.time, n.inputs.at(0), n.output, in_file, in_time});
  PrintFileNote(s.file_note);
  std::printf("%s: %zu rows (%d skipped as gaps%s%s)\n", (shown.empty() ? path : shown).c_str(), s.t.size(), s.skipped,
              s.skipped ? "; the first at " : "", s.first_skip.c_str());
  if (!s.note.empty()) std::printf("%s\n", s.note.c_str());
  return s;
}

}  // namespace bead::tools
