#include <algorithm>
#include <cmath>
#include <cstdio>

#include "libbead/io/run_archive.h"
#include "libbead/io/vendor_csv.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {

Run AddImport(CLI::App& app) {
  struct Args {
    std::string input, output;
    VendorCsvColumns columns;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("import", Summary("import"));
  cmd->footer(
      "In:  a vendor CSV export, one row per point, with a header; name the columns that hold\n"
      "     the profile id (rows of one profile together), its time, x and z. Other columns\n"
      "     are ignored. A profile takes the time of its first row.\n"
      "Out: RUN.h5, the run archive of docs/data-formats.md (profiles only, no /log),\n"
      "     z as height (up): --z-distance turns a distance from the sensor into one.\n"
      "     Without --encoder-column, /profiles/encoder holds 0 and the root attribute\n"
      "     encoder=absent says so: `bead measure` works, `bead flow` refuses the archive.\n"
      "Example (testdata/realdata/bead-observer, a real export):\n"
      "  bead import Representative_Layer_raw_points.csv -o layer.h5 --profile-column ScanID \\\n"
      "       --time-column Timestamp --x-column X --z-column Z --z-distance");
  auto& c = args->columns;
  cmd->add_option("csv", args->input, "Vendor CSV export")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Run archive to write (.h5, written atomically)")->required();
  cmd->add_option("--profile-column", c.profile, "Column of the profile id (whole numbers)")->required();
  cmd->add_option("--time-column", c.time, "Column of the time")->required();
  cmd->add_option("--x-column", c.x, "Column of x, mm")->required();
  cmd->add_option("--z-column", c.z, "Column of z, mm")->required();
  cmd->add_option("--encoder-column", c.encoder, "Column of the raw wheel encoder counter (if the export has one)");
  cmd->add_option("--time-scale", c.time_scale, "The time column times this is seconds (0.001 for ms)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_flag("--z-distance", c.z_is_distance, "z is the distance from the sensor (grows away from it)");

  return [args]() {
    const VendorImport imported = ReadVendorCsv(args->input, args->columns);
    const ProfileBlock& b = imported.run.profiles;
    WriteRunArchive(args->output, imported.run);
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
    std::printf("%s: %zu points in %zu profiles (%zu to %zu points each) over %.3f s; wrote %s\n",
                args->input.c_str(), imported.rows, b.size(), fewest, most, b.t_s.back() - b.t_s.front(),
                args->output.c_str());
    std::printf("  x %.4g .. %.4g mm, z (height) %.4g .. %.4g mm: the rig's reference_areas_mm must lie in this x range\n",
                x_lo, x_hi, z_lo, z_hi);
    if (EncoderAbsent(imported.run))
      std::printf("  no encoder column: /profiles/encoder holds 0, marked encoder=absent (flow needs the wheel's motion)\n");
    return 0;
  };
}

}  // namespace bead::tools
