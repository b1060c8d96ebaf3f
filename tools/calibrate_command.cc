#include <cstdio>
#include <filesystem>

#include "calibration/pin_offset.h"
#include "tools/rig_input.h"
#include "libbead/core/error.h"
#include "libbead/io/profiles_csv.h"
#include "libbead/io/rig_yaml.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {

Run AddCalibrateLaser(CLI::App* cal);      // calibrate_laser_command.cc
Run AddCalibrateWheel(CLI::App* cal);      // calibrate_wheel_command.cc
Run AddCalibrateReference(CLI::App* cal);  // calibrate_reference_command.cc

namespace {

Run AddCalibrateOffset(CLI::App* cal) {
  struct Args {
    std::string rig, pins, output;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = cal->add_subcommand("offset", "Nozzle-to-laser encoder offset from pin scans");
  cmd->footer(
      "In:  RIG.yaml and PINS.h5 (pin-scan archive) or PINS.csv (pin-scan CSV).\n"
      "Out: a table of the scans (each pin centre fitted to sub-count precision), then the line\n"
      "       offset_counts=<value> ci95_counts=<half width> scans_used=<n>/<total>\n"
      "     With -o, a copy of the rig file with the new offset (other keys kept), written atomically.\n"
      "Outlier rule: a scan more than 3.5 robust sigmas (1.4826 MAD) from the median is not used.\n"
      "Example:\n"
      "  bead calibrate offset --rig testdata/sample/rig.yaml testdata/sample/pins.h5 -o rig-new.yaml");
  cmd->add_option("--rig", args->rig, "Rig file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("pins", args->pins, "Pin-scan archive (.h5) or CSV (.csv)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Rig file to write with the calibrated offset");
  return [args]() {
    RigFile rig = ReadRigFileSaying(args->rig);
    const std::string ext = std::filesystem::path(args->pins).extension().string();
    const PinScanArchive pins = ext == ".csv" ? ReadPinScansCsv(args->pins) : ReadPinScanArchive(args->pins);
    const calibration::OffsetCalibration cal = calibration::CalibrateOffset(rig.rig, pins);
    const double mpc = rig.rig.MmPerCount();
    std::printf("%4s %12s %8s %12s %8s %9s %8s %12s  %s\n", "scan", "start", "on_pin", "centre", "se", "radius", "rms",
                "argmax", "used");
    std::printf("%4s %12s %8s %12s %8s %9s %8s %12s\n", "", "counts", "profiles", "counts", "counts", "mm", "mm",
                "counts");
    for (std::size_t k = 0; k < cal.scans.size(); ++k) {
      const auto& s = cal.scans[k];
      if (!s.ok) {
        std::printf("%4zu %12lld %8d %s\n", k, static_cast<long long>(s.start_encoder), s.profiles_on_pin,
                    s.reason.c_str());
        continue;
      }
      std::printf("%4zu %12lld %8d %12.2f %8.2f %9.3f %8.4f %12.1f  %s\n", k, static_cast<long long>(s.start_encoder),
                  s.profiles_on_pin, s.center_counts, s.center_se_counts, s.radius_mm, s.rms_mm, s.argmax_counts,
                  s.outlier ? "no (outlier)" : "yes");
    }
    if (!cal.ok) throw Error(Located(args->pins, "", "cannot calibrate: " + cal.reason));
    std::printf("offset: %.2f counts = %.3f mm +- %.2f counts (%.3f mm, 95 %%); scan spread %.2f counts (%.3f mm)\n",
                cal.offset_counts, cal.offset_mm, cal.ci95_counts, cal.ci95_mm, cal.sd_counts, cal.sd_counts * mpc);
    if (!cal.note.empty()) std::printf("warning: %s: %s\n", args->pins.c_str(), cal.note.c_str());
    const double rig_offset = rig.rig.offset_counts;
    if (std::abs(rig_offset - cal.offset_counts) > cal.ci95_counts)
      std::printf(
          "warning: the rig file's offset, %.2f counts, lies outside this interval (%.2f counts away): "
          "the rig has moved or the file is stale; consider -o to write the new offset\n",
          rig_offset, rig_offset - cal.offset_counts);
    if (!args->output.empty()) {
      rig.rig.offset_counts = cal.offset_counts;
      WriteRigFile(args->output, rig);
      std::printf("wrote %s with offset.counts = %.2f\n", args->output.c_str(), cal.offset_counts);
    }
    std::printf("offset_counts=%.2f ci95_counts=%.2f scans_used=%d/%d\n", cal.offset_counts, cal.ci95_counts, cal.used,
                cal.total);
    return 0;
  };
}

}  // namespace

Run AddCalibrate(CLI::App& app) {
  CLI::App* cal = app.add_subcommand("calibrate", Summary("calibrate"));
  cal->require_subcommand(1);
  cal->footer(
      "Subcommands: offset (nozzle-to-laser encoder offset from pin scans), laser (camera, lens and\n"
      "laser plane from chessboard images), wheel (runout and eccentricity from a run), reference\n"
      "(reference areas from a run).\n"
      "`bead calibrate SUB --help` for each.");
  Run offset = AddCalibrateOffset(cal);
  Run laser = AddCalibrateLaser(cal);
  Run wheel = AddCalibrateWheel(cal);
  Run reference = AddCalibrateReference(cal);
  CLI::App* offset_app = cal->get_subcommand("offset");
  CLI::App* laser_app = cal->get_subcommand("laser");
  CLI::App* wheel_app = cal->get_subcommand("wheel");
  return [=]() {
    return offset_app->parsed()  ? offset()
           : laser_app->parsed() ? laser()
           : wheel_app->parsed() ? wheel()
                                 : reference();
  };
}

}  // namespace bead::tools
