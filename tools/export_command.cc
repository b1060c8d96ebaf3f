#include <algorithm>
#include <cstdio>

#include "tools/rig_input.h"
#include "libbead/archive/open_run.h"
#include "libbead/archive/wheel_cloud_builder.h"
#include "libbead/core/error.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/part_scan_csv.h"
#include "libbead/io/point_cloud.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/part_cloud.h"
#include "libbead/io/profiles_csv.h"
#include "libbead/io/rig_yaml.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {
namespace {

// Every n-th profile of a block (n = 1: the block).
ProfileBlock EveryNth(ProfileBlock all, std::size_t n) {
  if (n <= 1) return all;
  ProfileBlock kept;
  kept.points = all.points;
  kept.shared_x = all.shared_x;
  if (all.shared_x) kept.x_mm = all.x_mm;
  for (std::size_t i = 0; i < all.size(); i += n) {
    kept.t_s.push_back(all.t_s[i]);
    kept.encoder.push_back(all.encoder[i]);
    const auto row = [&](const std::vector<float>& v) { return v.begin() + static_cast<long>(i * all.points); };
    kept.z_mm.insert(kept.z_mm.end(), row(all.z_mm), row(all.z_mm) + static_cast<long>(all.points));
    if (!all.shared_x) kept.x_mm.insert(kept.x_mm.end(), row(all.x_mm), row(all.x_mm) + static_cast<long>(all.points));
  }
  return kept;
}

// A part scan's cloud in the bed frame (part/part_cloud.h).
int ExportPartCloud(const std::string& run, const std::string& output, std::size_t every) {
  const RunArchive scan = ReadPartScan(run, true, false);
  const WheelCloud cloud = part::BuildPartCloud(scan.profiles, *scan.part, every);
  WritePointCloud(output, cloud);
  const auto [z_lo, z_hi] = std::minmax_element(cloud.z_mm.begin(), cloud.z_mm.end());
  std::printf("%s: part scan, %zu points of %zu layers in the bed frame; z %.3f .. %.3f mm; wrote %s\n", run.c_str(),
              cloud.size(), scan.part->layer.empty() ? 0 : static_cast<std::size_t>(scan.part->layer.back() + 1), *z_lo,
              *z_hi, output.c_str());
  return 0;
}

// A part scan's CSV forms (io/part_scan_csv.h): its profiles with their
// places, or (`log`) the nozzle's log.
int ExportPartCsv(const std::string& run, const std::string& output, std::size_t every, bool log) {
  const RunArchive scan = ReadPartScan(run, !log, log);
  if (log) {
    if (!scan.log || scan.log->size() == 0) throw Error(Located(run, "/log", "holds no nozzle log to export"));
    WritePartLogCsv(output, *scan.log);
    std::printf("%s: part scan, %zu log samples (t_s,layer,path_mm,screw_rpm%s); wrote %s\n", run.c_str(),
                scan.log->size(), scan.log->head_speed_mm_s.empty() ? "" : ",head_speed_mm_s", output.c_str());
    return 0;
  }
  WritePartProfilesCsv(output, scan.profiles, *scan.part, every);
  std::printf("%s: part scan, %zu profiles of %zu points each with their layer and place; wrote %s\n", run.c_str(),
              (scan.profiles.size() + every - 1) / every, scan.profiles.points, output.c_str());
  return 0;
}

// The profiles CSV long form of docs/data-formats.md: the sensor's own
// points, what the C and Python examples read.
void ExportProfilesCsv(const std::string& run, const std::string& output, std::size_t every) {
  WorkerPool pool;
  OpenedRun opened = OpenRun(run, pool, /*with_log=*/false);
  ProfileBlock profiles;
  opened.profiles->Read(0, opened.profiles->size(), profiles);
  const ProfileBlock kept = EveryNth(std::move(profiles), every);
  WriteProfilesCsv(output, kept);
  std::printf("%s: %zu profiles of %zu points each; wrote %s\n", run.c_str(), kept.size(), kept.points, output.c_str());
}

// The acquisition log CSV of docs/data-formats.md (t_s,encoder,screw_rpm
// and the two commands when recorded): for bead identify's voltage -> RPM.
void ExportLogCsv(const std::string& run, const std::string& output) {
  WorkerPool pool;
  const OpenedRun opened = OpenRun(run, pool, /*with_log=*/true);
  if (!opened.archive || !opened.run.log || opened.run.log->size() == 0)
    throw Error(Located(run, "/log", "holds no acquisition log to export"));
  WriteLogCsv(output, *opened.run.log);
  std::printf("%s: %zu log samples%s; wrote %s\n", run.c_str(), opened.run.log->size(),
              opened.run.log->extruder_cmd_v.empty() ? "" : " with the extruder and wheel commands", output.c_str());
}

}  // namespace

Run AddExport(CLI::App& app) {
  struct Args {
    std::string rig, run, output;
    WheelCloudOptions options;
    bool log = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("export", Summary("export"));
  cmd->footer(
      "In:  RIG.yaml and RUN.h5 (or a profiles CSV); a profiles CSV out needs RUN.h5 alone.\n"
      "Out: the run as one point cloud in wheel coordinates, for CloudCompare, pcl_viewer, MeshLab:\n"
      "       x  across the bead, mm (the sensor's x, so the rig's reference areas still hold)\n"
      "       y  s along the wheel's surface from the first profile, mm (the unwrapped encoder,\n"
      "          pi D / counts per revolution per count; or --surface-speed-mm-s times time)\n"
      "       z  height above the profile's reference line, mm (perpendicular to it)\n"
      "     and per point the fields z_sensor (the sensor's own z), profile (its index in the\n"
      "     run), t_s and encoder, so that `bead import CLOUD --profile-column profile\n"
      "     --time-column t_s --x-column x --z-column z_sensor --encoder-column encoder` brings\n"
      "     the run's measured points back exactly (dropouts stay out). .ply: binary PLY;\n"
      "     .pcd: binary compressed PCD. Written atomically. Profiles without a reference line\n"
      "     (too few points in an area) are left out and counted. The cloud is built in memory\n"
      "     (about 70 bytes a point): --every thins a long run.\n"
      "     .csv: the profiles CSV (profile,t_s,encoder,x_mm,z_mm, one row per point, the sensor's\n"
      "     own coordinates; no rig needed), what examples/c and examples/python read.\n"
      "     --log with .csv: the acquisition log CSV (t_s,encoder,screw_rpm[,extruder_cmd_v,wheel_cmd_v]).\n"
      "     A part scan (format 1.1, kind = \"part\"; no rig needed) as a cloud is in the bed frame:\n"
      "     x + frame_x_mm across the path, y = path_mm along it, z + frame_z_mm above the bed,\n"
      "     each point with its layer (field layer; encoder 0): the part as printed. As .csv\n"
      "     (profile,t_s,layer,path_mm,frame_z_mm,frame_x_mm,x_mm,z_mm, one row per point) its profiles\n"
      "     with their places; with --log the nozzle's log (t_s,layer,path_mm,screw_rpm[,head_speed_mm_s]).\n"
      "     `bead import P.csv --profile-column profile --time-column t_s --x-column x_mm --z-column z_mm\n"
      "     --layer-column layer --path-column path_mm --frame-z-column frame_z_mm --frame-x-column\n"
      "     frame_x_mm --log LOG.csv` makes the part scan again.\n"
      "Example:\n"
      "  bead export --rig rig.yaml run.h5 -o run.ply && pcl_viewer run.ply\n"
      "  bead export run.h5 --every 10 -o profiles.csv\n"
      "  bead export run.h5 --log -o log.csv");
  cmd->add_option("--rig", args->rig, "Rig file (YAML; for a point cloud)")->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive (.h5) or profiles CSV (.csv)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Point cloud to write (.ply or .pcd), or profiles CSV (.csv)")
      ->required();
  cmd->add_option("--every", args->options.every, "Keep every N-th profile")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--log", args->log, "Write the run's acquisition log (CSV), not its profiles");
  cmd->add_option("--surface-speed-mm-s", args->options.surface_speed_mm_s,
                  "Place s = v t at this surface speed, mm/s (for runs without encoder readings)")
      ->check(CLI::PositiveNumber);

  return [args]() {
    CheckWritable(args->output);  // before the run is read
    const bool part = IsPartScanFile(args->run);
    if (part && args->output.ends_with(".csv"))
      return ExportPartCsv(args->run, args->output, args->options.every, args->log);
    if (args->log) {
      if (!args->output.ends_with(".csv"))
        throw CLI::ValidationError("--log", "the log is written as a CSV (-o LOG.csv)");
      ExportLogCsv(args->run, args->output);
      return 0;
    }
    if (args->output.ends_with(".csv")) {
      ExportProfilesCsv(args->run, args->output, args->options.every);
      return 0;
    }
    if (!IsPointCloudPath(args->output))
      throw Error(Located(args->output, "", "is written as a point cloud (.ply or .pcd) or a profiles CSV (.csv)"));
    if (part) return ExportPartCloud(args->run, args->output, args->options.every);
    if (args->rig.empty()) throw CLI::RequiredError("--rig (a point cloud is placed in wheel coordinates)");
    const Rig rig = ReadRigSaying(args->rig);
    WorkerPool pool;
    OpenedRun opened = OpenRun(args->run, pool, /*with_log=*/false);
    ProfileBlock profiles;
    opened.profiles->Read(0, opened.profiles->size(), profiles);
    WheelCloudCount count;
    const WheelCloud cloud =
        BuildWheelCloud(profiles, EncoderAbsent(opened.run), rig, args->options, args->run, &count);
    WritePointCloud(args->output, cloud);
    const auto [s_lo, s_hi] = std::minmax_element(cloud.s_mm.begin(), cloud.s_mm.end());
    const auto [z_lo, z_hi] = std::minmax_element(cloud.z_mm.begin(), cloud.z_mm.end());
    std::printf(
        "%s: %zu points of %zu profiles (%zu left out: no reference line); s %.2f .. %.2f mm, "
        "z %.3f .. %.3f mm; wrote %s\n",
        args->run.c_str(), count.points, count.profiles - count.no_reference, count.no_reference, *s_lo, *s_hi, *z_lo,
        *z_hi, args->output.c_str());
    return 0;
  };
}

}  // namespace bead::tools
