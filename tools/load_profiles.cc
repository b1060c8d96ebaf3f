#include "tools/load_profiles.h"

#include <filesystem>
#include <string>

#include "libbead/core/error.h"
#include "libbead/io/profiles_csv.h"

namespace bead::tools {

RunArchive LoadRun(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".csv" || ext == ".CSV") {
    RunArchive run;
    run.profiles = ReadProfilesCsv(path);
    return run;
  }
  return ReadRunArchive(path);
}

void RequireMotion(const RunArchive& run, const std::string& path, const std::string& needs) {
  if (EncoderAbsent(run))
    throw Error(Located(path, "/profiles/encoder",
                        "holds no readings (root attribute encoder=absent: imported without an encoder column); " +
                            needs + " needs the wheel's motion"));
  if (!run.log) throw Error(Located(path, "/log", "missing: " + needs + " needs the acquisition log"));
  if (run.log->size() < 3)
    throw Error(Located(path, "/log/t_s",
                        "holds " + std::to_string(run.log->size()) +
                            " sample(s): the wheel's speed needs at least 3 (is the log cut short?)"));
}

}  // namespace bead::tools
