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
  opened.archive = true;
  opened.profiles = std::make_unique<ProfileStream>(path, pool);
  return opened;
}

MotionGap MissingMotion(bool encoder_absent, std::optional<std::size_t> log_samples, const std::string& needs) {
  if (encoder_absent)
    return {"/profiles/encoder",
            "holds no readings (root attribute encoder=absent: imported without an encoder "
            "column); " +
                needs + " needs the wheel's motion"};
  if (!log_samples) return {"/log", "missing: " + needs + " needs the acquisition log"};
  if (*log_samples < 3)
    return {"/log/t_s", "holds " + std::to_string(*log_samples) +
                            " sample(s): the wheel's speed needs at least 3 (is the log cut short?)"};
  return {};
}

MotionGap MissingMotion(const RunArchive& run, const std::string& needs) {
  return MissingMotion(EncoderAbsent(run), run.log ? std::optional<std::size_t>(run.log->size()) : std::nullopt, needs);
}

void RequireMotion(const RunArchive& run, const std::string& path, const std::string& needs) {
  const MotionGap gap = MissingMotion(run, needs);
  if (!gap.none()) throw Error(Located(path, gap.dataset, gap.why));
}

}  // namespace bead
