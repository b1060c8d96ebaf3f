#include <algorithm>
#include <cstdio>

#include "libbead/archive/open_run.h"
#include "libbead/archive/wheel_cloud_builder.h"
#include "libbead/core/error.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/point_cloud.h"
#include "libbead/io/rig_yaml.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {

Run AddExport(CLI::App& app) {
  struct Args {
    std::string rig, run, output;
    WheelCloudOptions options;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("export", Summary("export"));
  cmd->footer(
      "In:  RIG.yaml and RUN.h5 (or a profiles CSV).\n"
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
      "Example:\n"
      "  bead export --rig rig.yaml run.h5 -o run.ply && pcl_viewer run.ply");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("run", args->run, "Run archive (.h5) or profiles CSV (.csv)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Point cloud to write (.ply or .pcd)")->required();
  cmd->add_option("--every", args->options.every, "Keep every N-th profile")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--surface-speed-mm-s", args->options.surface_speed_mm_s,
                  "Place s = v t at this surface speed, mm/s (for runs without encoder readings)")
      ->check(CLI::PositiveNumber);

  return [args]() {
    if (!IsPointCloudPath(args->output))
      throw Error(Located(args->output, "", "a point cloud is written as .ply or .pcd"));
    const Rig rig = ReadRig(args->rig);
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
