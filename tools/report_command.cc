// bead report: one self-contained HTML page about a run. This command
// measures (geometry, flow, pin scans) and writes the numbers as CSV into
// a scratch folder; tools/report/bead_report.py (matplotlib) draws them and
// writes the page, pictures embedded.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "calibration/pin_offset.h"
#include "tools/rig_input.h"
#include "libbead/archive/run_flow.h"
#include "libbead/core/error.h"
#include "libbead/core/worker_pool.h"
#include "libbead/flow/flow.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/model/model_file.h"
#include "libbead/io/run_archive.h"
#include "tools/commands.h"
#include "tools/own_folder.h"
#include "tools/report_part.h"
#include "tools/scratch_folder.h"
#include "libbead/archive/measure_run.h"
#include "libbead/occlusion/occlusion_fit.h"
#include "tools/occlusion_step.h"
#include "tools/tty_progress.h"

namespace bead::tools {
namespace {

namespace fs = std::filesystem;

// The report script: installed beside the tool (PREFIX/share/bead), else
// in the source tree this tool was built from.
std::string ReportScript() {
  return InstalledOr("bead_report.py", std::string(BEAD_SOURCE_DIR) + "/tools/report/bead_report.py");
}

// A few profiles across the run (valid ones first), their points and lines.
void WriteSampleProfiles(const std::string& run_path, const MeasuredRun& m, WorkerPool& pool, const fs::path& dir) {
  const std::size_t n = m.geometry.size();
  std::vector<std::size_t> picks;
  for (int k = 1; k <= 5 && n > 0; ++k) {
    std::size_t at = n * k / 6;
    for (std::size_t step = 0; step < n / 12 && at < n && !m.geometry[at].valid(); ++step) ++at;
    if (at < n) picks.push_back(at);
  }
  OpenedRun again = OpenRun(run_path, pool, /*with_log=*/false);
  ProfileBlock block;
  std::ofstream pts(dir / "profiles.csv"), lines(dir / "lines.csv");
  pts << "profile,x_mm,z_mm\n";
  lines << "profile,t_s,valid,status,intercept_mm,slope,threshold_mm,left_edge_x_mm,right_edge_x_mm,area_mm2,"
           "area_corrected_mm2\n";
  for (std::size_t i : picks) {
    again.profiles->Read(i, 1, block);
    const ProfileView v = block.view(0);
    for (std::size_t k = 0; k < v.x_mm.size(); ++k)
      if (std::isfinite(v.x_mm[k]) && std::isfinite(v.z_mm[k]))
        pts << i << ',' << v.x_mm[k] << ',' << v.z_mm[k] << '\n';
    const BeadGeometry& g = m.geometry[i];
    const double corrected = i < m.corrected.size() ? m.corrected[i] : NAN;
    lines << i << ',' << v.t_s << ',' << g.valid() << ',' << StatusName(g.status) << ',' << g.reference.intercept_mm
          << ',' << g.reference.slope << ',' << g.threshold_mm << ',' << g.left_edge_x_mm << ',' << g.right_edge_x_mm
          << ',' << g.area_mm2 << ',' << corrected << '\n';
  }
}

// Each pin scan's chord widths against counts, and its fit.
void WritePins(const Rig& rig, const std::string& path, const fs::path& dir) {
  const PinScanArchive pins = ReadPinScanArchive(path);
  const calibration::OffsetCalibration cal = calibration::CalibrateOffset(rig, pins);
  std::ofstream pts(dir / "pin_points.csv"), fits(dir / "pin_fits.csv"), off(dir / "pin_offset.csv");
  pts << "scan,counts,width_mm\n";
  fits << "scan,ok,outlier,center_counts,center_se_counts,radius_mm,rms_mm,argmax_counts\n";
  ProfileProcessor processor(rig.reference_left, rig.reference_right);
  for (std::size_t s = 0; s < pins.scans.size(); ++s) {
    const PinScan& scan = pins.scans[s];
    for (std::size_t k = 0; k < scan.profiles.size(); ++k) {
      const BeadGeometry& g = processor.Process(scan.profiles.view(k));
      if (g.valid())
        pts << s << ',' << double(scan.profiles.encoder[k] - scan.start_encoder) * rig.encoder.direction << ','
            << g.width_mm << '\n';
    }
    const auto& f = cal.scans[s];
    fits << s << ',' << f.ok << ',' << f.outlier << ',' << f.center_counts << ',' << f.center_se_counts << ','
         << f.radius_mm << ',' << f.rms_mm << ',' << f.argmax_counts << '\n';
  }
  off << "ok,offset_counts,ci95_counts,rig_offset_counts,mm_per_count,used,total,reason\n"
      << cal.ok << ',' << cal.offset_counts << ',' << cal.ci95_counts << ',' << rig.offset_counts << ','
      << rig.MmPerCount() << ',' << cal.used << ',' << cal.total << ",\"" << cal.reason << "\"\n";
}

// Draws the page from the numbers in `dir` (tools/report/bead_report.py).
void DrawPage(const fs::path& dir, const std::string& output, const std::string& explain) {
  const std::string script = ReportScript();
  // Debian's python3 (where python3-matplotlib installs), unless BEAD_PYTHON names another.
  const char* py = std::getenv("BEAD_PYTHON");
  const std::string python = py && *py ? py : fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string cmdline = "'" + python + "' '" + script + "' '" + dir.string() + "' '" + output + "'";
  if (!explain.empty()) cmdline += " --explain '" + explain + "'";
  const int status = std::system(cmdline.c_str());
  // The script's exit 3: matplotlib (or NumPy) missing; otherwise its
  // own one line is above.
  if (status != 0)
    throw Error(Located(output, "",
                        WIFEXITED(status) && WEXITSTATUS(status) == 3
                            ? "the report needs Debian's python3-matplotlib and python3-numpy (apt-get install "
                              "python3-matplotlib), or BEAD_PYTHON naming a python that has them"
                            : "the report script " + script + " failed (its message is above)"));
}

// The --explain file is an explain report, before any work.
void CheckExplainReport(const std::string& path) {
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) throw Error(Located(path, "", "not JSON: --explain takes an explain report (bead explain -o)"));
  if (model::JsonKind(j) != "explain")
    throw Error(Located(path, "",
                        "is " + model::DescribeJsonKind(j) + ": --explain takes an explain report (bead explain -o)"));
}

}  // namespace

Run AddReport(CLI::App& app) {
  struct Args {
    std::string rig, run, pins, explain, output, occlusion = "pooled";
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "report", "One self-contained HTML page about a run or a part scan: profiles, geometry, flow, pins");
  cmd->footer(
      "In:  RIG.yaml and RUN.h5; --pins PINS.h5 (pin scans of the rig), --explain explain.json (bead explain -o).\n"
      "Out: REPORT.html, one page that opens offline (pictures embedded, drawn by matplotlib through the\n"
      "     script tools/report/bead_report.py, installed as share/bead/bead_report.py): a summary; five\n"
      "     profiles across the run with their reference line, threshold, edges and the measured area\n"
      "     shaded (the occlusion correction's share said); area, width and height against time with the\n"
      "     invalid profiles marked by status; the flow in extrusion time with its uncertainty band; with\n"
      "     --explain the model before and after, the effects added and the residual's spectrum with its\n"
      "     peaks and what they track (the rotating parts' rates); with --pins each scan's chord widths and\n"
      "     fitted centre, and the offset with its interval against the rig file's. Written atomically.\n"
      "     A part scan (format 1.1): each layer in brief, the cross-sections of every layer stacked at three\n"
      "     places along the path (bed frame), the area seen and corrected, the layer height and the wall's\n"
      "     wander along the path, and the flow and area against the head's speed (the corner bulge).\n"
      "     Needs Debian's python3 with matplotlib (python3-matplotlib); BEAD_PYTHON names another python.\n"
      "Example:\n"
      "  bead report --rig testdata/sample/rig.yaml testdata/sample/run.h5 --pins testdata/sample/pins.h5 -o "
      "report.html");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive or part scan (.h5)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--pins", args->pins, "Pin-scan archive (.h5) of this rig")->check(CLI::ExistingFile);
  cmd->add_option("--explain", args->explain, "Explain report (JSON, bead explain -o)")->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "HTML page to write")->required();
  AddOcclusionOption(cmd, args->occlusion);
  return [args]() {
    CheckWritable(args->output);
    if (!args->explain.empty()) CheckExplainReport(args->explain);
    const bool part = IsPartScanFile(args->run);
    if (part && !args->pins.empty())
      throw Error(Located(args->run, "", "is a part scan, which has no encoder: --pins takes a wheel run's pin scans"));
    const ScratchFolder scratch("the report");
    const fs::path& dir = scratch.dir;
    if (part) {
      WritePartReportData(args->rig, args->run, ProfileOptions{}, dir);
      DrawPage(dir, args->output, args->explain);
      std::printf("wrote %s\n", args->output.c_str());
      return 0;
    }
    const Rig rig = ReadRigSaying(args->rig);
    WorkerPool pool;
    RunFlowRequest request;
    request.measure.occlusion = ParseOcclusionMode(args->occlusion);
    request.measure.estimate = occlusion::EstimateOcclusion;
    request.measure.progress = TtyProgress("measured");
    request.geometry_csv = (dir / "geometry.csv").string();
    request.flow_csv = (dir / "flow.csv").string();
    request.keep = true;  // the sample profiles are drawn from the measured run
    request.require_motion = false;
    const RunFlow f = MeasureRunFlow(args->run, rig, pool, request);
    const MeasuredRun& m = f.whole;
    const bool motion = f.gap.none();
    WriteSampleProfiles(args->run, m, pool, dir);
    if (!args->pins.empty()) WritePins(rig, args->pins, dir);
    {
      std::ofstream about(dir / "about.csv");
      about << "run,rig,pins,explain,occlusion,occlusion_line,motion\n\"" << args->run << "\",\"" << args->rig
            << "\",\"" << args->pins << "\",\"" << args->explain << "\"," << args->occlusion << ",\""
            << OcclusionLine(m.summary) << "\"," << motion << '\n';
    }
    DrawPage(dir, args->output, args->explain);
    std::printf("wrote %s\n", args->output.c_str());
    return 0;
  };
}

}  // namespace bead::tools
