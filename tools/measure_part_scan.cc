#include "tools/measure_part_scan.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "libbead/io/profile_stream.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/measure_part.h"
#include "libbead/part/part_geometry_csv.h"
#include "tools/rig_input.h"
#include "tools/tty_progress.h"

namespace bead::tools {
namespace {

void SayLayers(const std::vector<part::LayerSummary>& layers) {
  for (const part::LayerSummary& l : layers) {
    std::printf("  layer %lld: %zu profiles over path %.1f to %.1f mm, %zu valid, mean area %.3f mm^2",
                static_cast<long long>(l.layer), l.profiles, l.first_path_mm, l.last_path_mm, l.valid, l.MeanArea());
    if (l.layer == 0)
      std::printf(" (on the bed)\n");
    else if (l.no_surface_below == l.profiles)
      std::printf("; layer %lld is not in the scan: nothing to measure it against\n",
                  static_cast<long long>(l.layer - 1));
    else if (l.shift_found)
      std::printf("; pass shift %+.3f mm (median; found in %zu profiles)\n", l.MedianShift(), l.shift_found);
    else
      std::printf("; pass shift not found (the layer below shows nowhere beside the new bead): no offset\n");
  }
}

}  // namespace

int MeasurePartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                    const ProfileOptions& bed, unsigned threads) {
  const RigFile rig = ReadPartRigFile(rig_path);
  SayRigWarnings(rig);
  const RunArchive places = ReadPartScan(run, false, false);
  WorkerPool pool(threads);
  ProfileStream stream(run, pool);
  part::MeasurePartOptions options;
  options.bed = bed;
  part::PartGeometryCsvWriter out(output);
  const auto start = std::chrono::steady_clock::now();
  const auto tty = TtyProgress("measured");
  const std::size_t total = stream.size();
  const std::vector<part::LayerSummary> layers = part::MeasurePart(
      stream, *places.part, rig.rig, options, [&](const part::PartGeometryRow& r) { out.Append(r); },
      [&](std::size_t done) {
        if (tty) tty(done, total);
      });
  out.Commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::size_t valid = 0;
  for (const auto& l : layers) valid += l.valid;
  std::printf("%s: part scan, %zu profiles in %zu layers, %zu valid, measured in %.3f s; wrote %s\n", run.c_str(),
              total, layers.size(), valid, seconds, output.c_str());
  SayLayers(layers);
  std::printf(
      "  area_corrected_mm2 is empty: what a bead hides under its overhang on the layer below is not yet\n"
      "  modelled on parts (the area is what the sensor sees the layer add)\n");
  return 0;
}

}  // namespace bead::tools
