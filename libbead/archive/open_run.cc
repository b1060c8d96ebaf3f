#include "libbead/archive/open_run.h"

#include <filesystem>

#include "libbead/io/profiles_csv.h"

namespace bead {

OpenedRun OpenRun(const std::string& path, WorkerPool& pool) {
  OpenedRun opened;
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".csv" || ext == ".CSV") {
    opened.profiles = std::make_unique<ProfileStream>(path, ReadProfilesCsv(path));
    return opened;
  }
  opened.run = ReadRunArchive(path, false);
  opened.profiles = std::make_unique<ProfileStream>(path, pool);
  return opened;
}

}  // namespace bead
