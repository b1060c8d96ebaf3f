#include "libbead/archive/batch.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libbead/archive/batch_part.h"
#include "libbead/archive/run_flow.h"
#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"

namespace bead {
namespace fs = std::filesystem;
namespace {

constexpr const char* kResultHeader =
    "name,run,rig,status,profiles,valid,flow_samples,total_volume_mm3,offset_counts,occlusion_fraction,warnings";

// Text for a CSV field of ours: no commas, no line breaks.
std::string Plain(std::string text) {
  for (char& c : text)
    if (c == ',')
      c = ';';
    else if (c == '\n' || c == '\r')
      c = ' ';
  return text;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

uint64_t Fnv1a(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
  return h;
}

// What a run's results are made from; a change redoes the run.
std::string Fingerprint(const BatchRun& run, const BatchOptions& o) {
  std::ostringstream s;
  std::error_code ec;
  const auto size = fs::file_size(run.run, ec);
  const auto time = fs::last_write_time(run.run, ec).time_since_epoch().count();
  s << "run " << run.run << " bytes " << size << " modified " << time << "\n";
  s << "rig " << run.rig << " text " << std::hex << Fnv1a(ReadText(run.rig)) << std::dec << "\n";
  const BeadOptions& b = o.profile.bead;
  s << "options occlusion " << static_cast<int>(o.occlusion) << " threshold_mm " << CsvNumber(b.min_threshold_mm)
    << " threshold_sigmas " << CsvNumber(b.threshold_sigmas) << " spike_mm " << CsvNumber(b.spike_mm) << " max_gap_mm "
    << CsvNumber(b.max_gap_mm) << " speed_window_s " << CsvNumber(o.flow.speed_window_s) << " area_smooth "
    << o.flow.area_smooth_window << "\n";
  return s.str();
}

std::string ResultLine(const RunResult& r) {
  std::string warnings;
  for (const std::string& w : r.warnings) warnings += (warnings.empty() ? "" : " | ") + w;
  std::ostringstream s;
  s << Plain(r.name) << ',' << Plain(r.run) << ',' << Plain(r.rig) << ',' << Plain(r.status) << ',' << r.profiles << ','
    << r.valid << ',' << r.flow_samples << ',' << CsvNumber(r.total_volume_mm3) << ',' << CsvNumber(r.offset_counts)
    << ',' << CsvNumber(r.occlusion_fraction) << ',' << Plain(warnings);
  return s.str();
}

// The data line of a run's result.csv ("" when there is none).
std::string ReadResultLine(const std::string& path) {
  std::ifstream in(path);
  std::string header, line;
  if (!in || !std::getline(in, header) || header != kResultHeader || !std::getline(in, line)) return "";
  return line;
}

std::string StatusOf(const std::string& line) {
  std::size_t pos = 0;
  for (int k = 0; k < 3 && pos != std::string::npos; ++k) pos = line.find(',', pos) + 1;
  if (pos == 0 || pos > line.size()) return "";
  return line.substr(pos, line.find(',', pos) - pos);
}

void WriteText(const std::string& path, const std::string& text) {
  AtomicFile out(path);
  out.stream() << text;
  out.Commit();
}

}  // namespace

std::string RunFolder(const BatchOptions& options, const BatchRun& run) {
  return (fs::path(options.out) / run.name).string();
}

bool RunComplete(const BatchRun& run, const BatchOptions& options) {
  const fs::path dir = RunFolder(options, run);
  return StatusOf(ReadResultLine((dir / "result.csv").string())) == "ok" &&
         ReadText((dir / "inputs.txt").string()) == Fingerprint(run, options);
}

namespace {

// A wheel run: measured and its flow computed as it streams.
void ProcessWheelRun(const BatchRun& job, const std::string& dir_name, const BatchOptions& options, WorkerPool& pool,
                     const std::function<void(std::size_t, std::size_t)>& progress, RunResult& r) {
  const fs::path dir = dir_name;
  std::error_code ec;
  const Rig rig = ReadRig(job.rig, &r.warnings);
  r.offset_counts = rig.offset_counts;
  MeasureRunOptions measure;
  measure.profile = options.profile;
  measure.occlusion = options.occlusion;
  measure.estimate = options.estimate;
  measure.progress = progress;
  auto measured = [&](const MeasureRunSummary& summary) {
    r.profiles = summary.profiles;
    r.valid = summary.valid;
    if (options.occlusion == OcclusionMode::kPooled) {
      if (summary.pooled.ok)
        r.occlusion_fraction = summary.pooled.bias_fraction;
      else
        r.warnings.push_back("occlusion: " + summary.pooled.note);
    }
    if (r.valid == 0 && r.profiles > 0) {
      // Why, in the words of the geometry CSV's status column: the most common reason.
      const auto& by = summary.by_status;
      const std::size_t most = static_cast<std::size_t>(std::max_element(by.begin() + 1, by.end()) - by.begin());
      r.warnings.push_back("no profile could be measured (" + std::to_string(by[most]) + " of " +
                           std::to_string(r.profiles) + ": " + StatusName(static_cast<ProfileStatus>(most)) + ")");
    }
  };
  RunFlowRequest request;
  request.measure = measure;
  request.flow = options.flow;
  request.geometry_csv = (dir / "geometry.csv").string();
  request.flow_csv = (dir / "flow.csv").string();
  request.require_motion = false;
  const RunFlow f = MeasureRunFlow(job.run, rig, pool, request);
  measured(f.measure);
  if (!f.whole_run_why.empty())
    r.warnings.push_back("the flow was computed on the whole run in memory: " + f.whole_run_why);
  if (f.gap.none()) {
    r.flow_samples = f.valid;
    r.total_volume_mm3 = f.total_volume_mm3;
    r.warnings.insert(r.warnings.end(), f.warnings.begin(), f.warnings.end());
  } else {
    fs::remove(dir / "flow.csv", ec);
    r.warnings.push_back("no flow: " + f.gap.dataset + " " + f.gap.why);
  }
}

}  // namespace

RunResult ProcessRun(const BatchRun& job, const BatchOptions& options, WorkerPool& pool,
                     const std::function<void(std::size_t, std::size_t)>& progress) {
  RunResult r;
  r.name = job.name;
  r.run = job.run;
  r.rig = job.rig;
  const fs::path dir = RunFolder(options, job);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(Located(dir.string(), "", "cannot create the run's output folder: " + ec.message()));
  const std::string inputs = Fingerprint(job, options);
  try {
    // A part scan (kind = "part") is measured layer on layer.
    if (IsPartScanFile(job.run))
      ProcessPartScan(job, dir.string(), options, r);
    else
      ProcessWheelRun(job, dir.string(), options, pool, progress, r);
  } catch (const std::exception& e) {
    r.status = std::string("failed: ") + e.what();
  }
  WriteText((dir / "inputs.txt").string(), inputs);
  WriteText((dir / "result.csv").string(), std::string(kResultHeader) + "\n" + ResultLine(r) + "\n");
  return r;
}

SummaryState WriteSummary(const std::vector<BatchRun>& runs, const BatchOptions& options) {
  const std::string lock_path = (fs::path(options.out) / ".summary.lock").string();
  const int lock = ::open(lock_path.c_str(), O_RDWR | O_CREAT, 0644);
  if (lock < 0) throw Error(Located(lock_path, "", "cannot create the summary's lock file"));
  ::flock(lock, LOCK_EX);
  SummaryState state;
  std::string text = std::string(kResultHeader) + "\n";
  try {
    for (const BatchRun& run : runs) {
      const std::string line = ReadResultLine((fs::path(RunFolder(options, run)) / "result.csv").string());
      if (line.empty()) {
        state.missing.push_back(run.name);
        continue;
      }
      ++state.complete;
      state.failed += StatusOf(line) != "ok";
      text += line + "\n";
    }
    WriteText((fs::path(options.out) / "summary.csv").string(), text);
  } catch (...) {
    ::flock(lock, LOCK_UN);
    ::close(lock);
    throw;
  }
  ::flock(lock, LOCK_UN);
  ::close(lock);
  return state;
}

}  // namespace bead
