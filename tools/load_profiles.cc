#include "tools/load_profiles.h"

#include <filesystem>

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

}  // namespace bead::tools
