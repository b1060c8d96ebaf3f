// bead explain, part mode: a part scan (format 1.1) and its rig. The flow
// along the toolpath (what bead flow writes: Q = v_head A at each place, in
// the time the nozzle laid it) is the series, the screw's RPM its input;
// the loop runs on it as series mode runs on any series, with the head's
// speed tried as a recorded cause.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/part_csv.h"
#include "libbead/part/part_flow.h"
#include "tools/explain_modes.h"
#include "tools/part_scan.h"
#include "tools/rig_input.h"
#include "tools/scratch_folder.h"

namespace bead::tools {
namespace {

namespace fs = std::filesystem;

// The scan's flow along the path into `csv`; its counts said.
void PartFlowCsv(const Rig& rig, const std::string& run, const fs::path& csv) {
  const RunArchive scan = ReadPartScan(run, /*with_profiles=*/false, /*with_log=*/true);
  if (!scan.log) throw NoNozzleLog(run);
  part::PartFlowCsvWriter out(csv.string());
  const part::PartScanFlow f = part::MeasurePartScanFlow(run, *scan.part, &*scan.log, rig, {}, 0, nullptr,
                                                         [&](const part::PartFlowRow& row) { out.Append(row); });
  out.Commit();
  std::printf(
      "%s: part scan, %zu profiles in %zu layer%s, %zu placed and valid: the flow along the path (bead flow's) "
      "is the series, input screw_rpm, output flow_mm3_s, in the time the nozzle laid each place\n",
      run.c_str(), scan.part->size(), f.layers.size(), f.layers.size() == 1 ? "" : "s", f.flow_samples);
}

}  // namespace

int ExplainPartMode(const ExplainArgs& a) {
  if (!a.pins.empty() || !a.flow_out.empty())
    throw CLI::ValidationError("--pins and --flow-out",
                               "are for a run on the wheel: a part scan has no encoder, and its flow is bead flow's");
  if (!a.inputs.empty() || !a.output.empty() || !a.time.empty())
    throw CLI::ValidationError("--input, --output and --time",
                               "are for CSV mode: a part scan's series is its flow along the path (input screw_rpm, "
                               "output flow_mm3_s, time t_s)");
  const RigFile rig = ReadPartRigFile(a.rig);
  SayRigWarnings(rig);
  const ScratchFolder scratch("the part's flow");
  ExplainArgs s = a;
  s.rig.clear();
  s.data = (scratch.dir / (fs::path(a.data).stem().string() + "_flow.csv")).string();
  PartFlowCsv(rig.rig, a.data, s.data);
  if (!a.validate.empty()) {
    if (!(IsPartScanFile(a.validate)))
      throw Error(Located(a.validate, "", "is not a part scan: --validate takes another part scan of the same rig"));
    s.validate = (scratch.dir / (fs::path(a.validate).stem().string() + "_validate_flow.csv")).string();
    PartFlowCsv(rig.rig, a.validate, s.validate);
  }
  s.time = "t_s", s.inputs = {"screw_rpm"}, s.output = "flow_mm3_s";
  if (a.channels.empty() && !a.no_channels) s.channels = {"head_speed_mm_s"};
  s.series_mode = "part";
  // The series are scratch files: what is said about them is said of the
  // scans' flows (an error from a reader below, naming the scratch path,
  // too; its line numbers are those of `bead flow` on the scan).
  s.data_name = a.data + "'s flow along the path";
  if (!a.validate.empty()) s.validate_name = a.validate + "'s flow along the path";
  try {
    return ExplainSeriesMode(s);
  } catch (const Error& e) {
    std::string what = e.what();
    for (const auto& [path, name] : {std::pair{s.data, s.data_name}, std::pair{s.validate, s.validate_name}})
      for (std::size_t at = what.find(path); !path.empty() && at != std::string::npos;
           at = what.find(path, at + name.size()))
        what.replace(at, path.size(), name);
    throw Error(what);
  }
}

}  // namespace bead::tools
