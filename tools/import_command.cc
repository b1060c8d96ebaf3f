#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "libbead/core/error.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/mat_run.h"
#include "libbead/io/part_scan_csv.h"
#include "libbead/io/point_cloud.h"
#include "libbead/io/profiles_csv.h"
#include "libbead/io/run_archive.h"
#include "libbead/io/vendor_csv.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {
namespace {

// The reader for the input's extension: .csv, .mat, .ply or .pcd.
ImportedRun ReadForeignRun(const std::string& path, const ImportColumns& columns) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".csv" || ext == ".txt") return ReadVendorCsv(path, columns);
  if (columns.part())
    throw CLI::ValidationError("--layer-column", "a part scan's columns are read from a vendor CSV (.csv) only");
  if (ext == ".mat") return ReadMatRun(path, columns);
  if (IsPointCloudPath(path)) return ReadPointCloud(path, columns);
  throw Error(Located(path, "", "import reads .csv, .mat, .ply or .pcd files (by their extension)"));
}

// The run's log from its CSV (--log): a part scan's nozzle log, else the
// wheel's acquisition log; it must overlap the profiles in time.
AcquisitionLog ReadLogFor(const std::string& path, const ImportedRun& imported) {
  AcquisitionLog log = imported.run.part ? ReadPartLogCsv(path) : ReadLogCsv(path);
  const auto& t = imported.run.profiles.t_s;
  if (!t.empty() && (log.t_s.back() < t.front() || log.t_s.front() > t.back()))
    throw Error(Located(path, "",
                        "the log's times (" + CsvNumber(log.t_s.front()) + " .. " + CsvNumber(log.t_s.back()) +
                            " s) never meet the profiles' (" + CsvNumber(t.front()) + " .. " + CsvNumber(t.back()) +
                            " s): the log must be on the profiles' clock (--time-scale applies to the profiles only)"));
  return log;
}

// A part scan whose file counts its layers from `first` (its number for the
// layer on the bed): renumbered from 0, the log's layers too.
void RenumberLayers(const std::string& path, const std::string& log_path, int64_t first, ImportedRun& imported) {
  if (!imported.run.part || first == 0) return;
  const auto renumber = [&](std::vector<int64_t>& layers, const std::string& file, const std::string& row) {
    if (const auto low = std::min_element(layers.begin(), layers.end()); low != layers.end() && *low < first)
      throw Error(Located(file, row + " " + std::to_string(low - layers.begin()),
                          "layer " + std::to_string(*low) + " is below --first-layer " + std::to_string(first) +
                              ": the first layer, on the bed, is the file's lowest"));
    for (int64_t& l : layers) l -= first;
  };
  renumber(imported.run.part->layer, path, "profile");
  if (imported.run.log) renumber(imported.run.log->layer, log_path, "log sample");
}

void PrintSummary(const std::string& input, const std::string& output, const ImportedRun& imported) {
  const ProfileBlock& b = imported.run.profiles;
  std::size_t fewest = b.points, most = 0;
  float x_lo = INFINITY, x_hi = -INFINITY, z_lo = INFINITY, z_hi = -INFINITY;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const ProfileView v = b.view(i);
    std::size_t points = 0;
    for (std::size_t k = 0; k < v.z_mm.size(); ++k)
      if (std::isfinite(v.x_mm[k]) && std::isfinite(v.z_mm[k])) {
        ++points;
        x_lo = std::min(x_lo, v.x_mm[k]), x_hi = std::max(x_hi, v.x_mm[k]);
        z_lo = std::min(z_lo, v.z_mm[k]), z_hi = std::max(z_hi, v.z_mm[k]);
      }
    fewest = std::min(fewest, points), most = std::max(most, points);
  }
  std::printf("%s: %zu points in %zu profiles (%zu to %zu points each) over %.3f s; wrote %s\n", input.c_str(),
              imported.rows, b.size(), fewest, most, b.t_s.back() - b.t_s.front(), output.c_str());
  std::printf(
      "  x %.4g .. %.4g mm, z (height) %.4g .. %.4g mm: the rig's reference_areas_mm must lie in this x range\n", x_lo,
      x_hi, z_lo, z_hi);
  if (const auto& part = imported.run.part) {
    const auto [lo, hi] = std::minmax_element(part->path_mm.begin(), part->path_mm.end());
    std::printf("  a part scan: layers %lld to %lld, path %.1f .. %.1f mm (bead measure measures it layer on layer)\n",
                static_cast<long long>(part->layer.front()), static_cast<long long>(part->layer.back()), *lo, *hi);
    const auto [z_lo, z_hi] = std::minmax_element(part->frame_z_mm.begin(), part->frame_z_mm.end());
    if (part->layer.front() != part->layer.back() && *z_lo == *z_hi)
      std::printf(
          "  frame_z_mm is %.4g mm in every layer%s: right only where the profiler does not rise with the part; where "
          "it rides on the head, name the head's height with --frame-z-column (bead measure refuses a layer whose "
          "surface then lies under the one before it)\n",
          *z_lo, *z_lo == 0.0 ? " (no --frame-z-column)" : "");
    if (const int64_t low = *std::min_element(part->layer.begin(), part->layer.end()); low == 1)
      std::printf(
          "  no layer 0 (the first layer, on the bed): layer 1 will be measured against a layer 0 the scan does not "
          "hold; a file that counts its layers from 1 is read with --first-layer 1\n");
    else if (low > 1)
      std::printf(
          "  the scan starts at layer %lld: its profiles stand on layer %lld, which it does not hold, and have "
          "nothing to be measured against (the layers after it are measured on it); --first-layer %lld measures "
          "them as on a bed, against the rig's reference line over bare surface beside them\n",
          static_cast<long long>(low), static_cast<long long>(low - 1), static_cast<long long>(low));
  } else if (EncoderAbsent(imported.run)) {
    std::printf(
        "  no encoder column: /profiles/encoder holds 0, marked encoder=absent (flow needs the wheel's motion)\n");
  }
}

}  // namespace

Run AddImport(CLI::App& app) {
  struct Args {
    std::string input, output, log;
    ImportColumns columns;
    int64_t first_layer = 0;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("import", Summary("import"));
  cmd->footer(
      "In (by the extension; the --*-column options name what holds what):\n"
      "  .csv  a vendor CSV export, one row per point, with a header: columns of the profile id\n"
      "        (rows of one profile together), its time, x and z; other columns are ignored.\n"
      "  .mat  a MATLAB file with the profiles as matrices: z N x P (or P x N), x a vector of P\n"
      "        or a matrix as z, the time a vector of N, the encoder (optional) a vector of N.\n"
      "  .ply, .pcd  a line scanner's point cloud: --profile-column names the field that numbers\n"
      "        the scan lines (the lines are ordered by it; an organized cloud may leave it out:\n"
      "        a profile per row); also the fields of time, x and z. `bead export` writes such a\n"
      "        cloud (fields profile, t_s, encoder, x, z_sensor) which comes back in this way.\n"
      "  A profile takes the time of its first point; non-finite x or z are dropouts.\n"
      "  A part scan (format 1.1; .csv): --layer-column names each profile's layer, and\n"
      "        --path-column its place along the toolpath (mm), or --head-speed-mm-s places it at\n"
      "        that speed times its time since its layer's first profile; --frame-z-column and\n"
      "        --frame-x-column the profile frame's height above the bed and lateral offset (0 when\n"
      "        not named). It writes a part scan (kind = \"part\", no encoder) that bead measure\n"
      "        measures layer on layer; with --log LOG.csv (t_s,layer,path_mm,screw_rpm\n"
      "        [,head_speed_mm_s]: where the nozzle was, as `bead export PART.h5 --log` writes it)\n"
      "        bead flow gives its flow along the path.\n"
      "  --log LOG.csv  the run's log on the profiles' clock: a part scan's as above, a wheel\n"
      "        run's t_s,encoder,screw_rpm (docs/data-formats.md).\n"
      "Out: RUN.h5, the run archive of docs/data-formats.md (profiles, and /log from --log),\n"
      "     z as height (up): --z-distance turns a distance from the sensor into one.\n"
      "     Without --encoder-column, /profiles/encoder holds 0 and the root attribute\n"
      "     encoder=absent says so: `bead measure` works, `bead flow` refuses the archive.\n"
      "Examples:\n"
      "  bead import Representative_Layer_raw_points.csv -o layer.h5 --profile-column ScanID \\\n"
      "       --time-column Timestamp --x-column X --z-column Z --z-distance\n"
      "  bead import Representative_Layer_raw_points.csv -o layer25.h5 --profile-column ScanID \\\n"
      "       --time-column Timestamp --x-column X --z-column Z --z-distance --layer-column Layer \\\n"
      "       --head-speed-mm-s 10\n"
      "  bead import scans.mat -o run.h5 --time-column t --x-column X --z-column Z --encoder-column enc\n"
      "  bead import run.ply -o back.h5 --profile-column profile --time-column t_s --x-column x \\\n"
      "       --z-column z_sensor --encoder-column encoder");
  auto& c = args->columns;
  cmd->add_option("file", args->input, "The file to import: .csv, .mat, .ply or .pcd")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Run archive to write (.h5, written atomically)")->required();
  cmd->add_option("--profile-column", c.profile,
                  "Column of the profile id (CSV: whole numbers; PLY/PCD: the field ordering the scan lines)");
  cmd->add_option("--time-column", c.time, "Column (variable, field) of the time")->required();
  cmd->add_option("--x-column", c.x, "Column (variable, field) of x, mm")->required();
  cmd->add_option("--z-column", c.z, "Column (variable, field) of z, mm")->required();
  cmd->add_option("--encoder-column", c.encoder, "Column of the raw wheel encoder counter (if the file has one)");
  cmd->add_option("--time-scale", c.time_scale, "The time column times this is seconds (0.001 for ms)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--z-distance", c.z_is_distance, "z is the distance from the sensor (grows away from it)");
  cmd->add_option("--layer-column", c.layer, "Column of each profile's layer: the file is a part scan (CSV)");
  cmd->add_option("--path-column", c.path, "Column of each profile's place along the toolpath, mm (part scan)");
  cmd->add_option("--head-speed-mm-s", c.head_speed_mm_s,
                  "Place each profile at this head speed times its time in its layer, mm/s (part scan)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--first-layer", args->first_layer,
                  "The file's number for the first layer, the one on the bed (1 where it counts from 1): the "
                  "archive numbers it 0 (part scan; the log's layers too)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--frame-z-column", c.frame_z, "Column of the profile frame's height above the bed, mm (part)");
  cmd->add_option("--frame-x-column", c.frame_x, "Column of the profile frame's lateral offset, mm (part)");
  cmd->add_option("--log", args->log,
                  "The run's log (CSV on the profiles' clock): a part scan's t_s,layer,path_mm,screw_rpm"
                  "[,head_speed_mm_s], a wheel run's t_s,encoder,screw_rpm")
      ->check(CLI::ExistingFile);

  return [args]() {
    ImportedRun imported = ReadForeignRun(args->input, args->columns);
    if (!args->log.empty()) imported.run.log = ReadLogFor(args->log, imported);
    RenumberLayers(args->input, args->log, args->first_layer, imported);
    WriteRunArchive(args->output, imported.run);
    PrintSummary(args->input, args->output, imported);
    if (imported.run.log) std::printf("  /log: %zu samples from %s\n", imported.run.log->size(), args->log.c_str());
    return 0;
  };
}

}  // namespace bead::tools
