#include "libbead/archive/open_run.h"

#include <filesystem>

#include "libbead/core/error.h"
#include "libbead/io/profiles_csv.h"

namespace bead {

OpenedRun OpenRun(const std::string& path, WorkerPool& pool, bool with_log) {
  OpenedRun opened;
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".csv" || ext == ".CSV") {
    opened.profiles = std::make_unique<ProfileStream>(path, ReadProfilesCsv(path));
    return opened;
  }
  opened.run = ReadRunArchive(path, false, with_log);
  opened.profiles = std::make_unique<ProfileStream>(path, pool);
  return opened;
}

MotionGap MissingMotion(const RunArchive& run, const std::string& needs) {
  if (EncoderAbsent(run))
    return {"/profiles/encoder", "holds no readings (root attribute encoder=absent: imported without an encoder "
                                 "column); " + needs + " needs the wheel's motion"};
  if (!run.log) return {"/log", "missing: " + needs + " needs the acquisition log"};
  if (run.log->size() < 3)
    return {"/log/t_s", "holds " + std::to_string(run.log->size()) +
                            " sample(s): the wheel's speed needs at least 3 (is the log cut short?)"};
  return {};
}

void RequireMotion(const RunArchive& run, const std::string& path, const std::string& needs) {
  const MotionGap gap = MissingMotion(run, needs);
  if (!gap.none()) throw Error(Located(path, gap.dataset, gap.why));
}

}  // namespace bead
