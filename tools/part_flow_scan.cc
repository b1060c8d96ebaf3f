// bead flow on a part scan: the flow along the toolpath, each layer's
// volume, and in words what the log and the scan say of each other (how
// long after laying each place was seen; places or layers the log never
// passed).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "libbead/io/run_archive.h"
#include "libbead/part/flow_hampel.h"
#include "libbead/part/part_csv.h"
#include "libbead/part/part_flow.h"
#include "tools/part_scan.h"
#include "tools/tty_progress.h"

namespace bead::tools {
namespace {

// The profiles measured whose corrected areas were refused: no flow.
void SayUncorrectedFlow(const std::vector<part::LayerSummary>& layers) {
  std::size_t refused = 0;
  for (const part::LayerSummary& l : layers) refused += l.valid - l.corrected;
  if (refused)
    std::printf(
        "  %zu measured profiles have no flow (valid 0): their corrected areas were refused (the lines above say "
        "why), and the area seen, in their rows, counts the groove an overhanging bead hides as material\n",
        refused);
}

// Where most profiles' places were never passed in the log: the path each
// spans, and the layers, side by side (a path in metres, layers counted
// from 1, another toolpath's start).
void SayPathRanges(const PartPlaces& scan, const AcquisitionLog& log) {
  const auto [scan_lo, scan_hi] = std::minmax_element(scan.path_mm.begin(), scan.path_mm.end());
  const auto [log_lo, log_hi] = std::minmax_element(log.path_mm.begin(), log.path_mm.end());
  const auto [scan_first, scan_last] = std::minmax_element(scan.layer.begin(), scan.layer.end());
  const auto [log_first, log_last] = std::minmax_element(log.layer.begin(), log.layer.end());
  std::printf(
      "  most profiles were never placed: the scan's path spans %.4g .. %.4g mm over layers %lld to %lld, the log's "
      "%.4g .. %.4g mm over layers %lld to %lld; /log/path_mm and /log/layer must name places as the profiles' do "
      "(the same units, the same toolpath's start, the same first layer)\n",
      *scan_lo, *scan_hi, static_cast<long long>(*scan_first), static_cast<long long>(*scan_last), *log_lo, *log_hi,
      static_cast<long long>(*log_first), static_cast<long long>(*log_last));
}

// The scan's layers the log never printed (a log counting its layers from
// 1, or from the part's start where the scan does not).
void SayLayersNotLogged(const PartPlaces& scan, const AcquisitionLog& log) {
  const std::set<int64_t> logged(log.layer.begin(), log.layer.end());
  std::set<int64_t> missing;
  for (const int64_t l : scan.layer)
    if (!logged.count(l)) missing.insert(l);
  if (missing.empty() || logged.empty()) return;
  std::string names;
  for (const int64_t l : missing) names += (names.empty() ? "" : ", ") + std::to_string(l);
  std::printf(
      "  the scan's layer%s %s %s not in the log (its layers %lld to %lld): /log/layer must count the layers as the "
      "profiles do; if it counts from another first layer, every layer's flow is timed at another layer's pass\n",
      missing.size() == 1 ? "" : "s", names.c_str(), missing.size() == 1 ? "is" : "are",
      static_cast<long long>(*logged.begin()), static_cast<long long>(*logged.rbegin()));
}

// How long after the nozzle laid each place the profiler saw it, or that
// it saw places before they were laid (the log on another clock).
void SayScanDelay(const part::PartScanFlow::ScanDelay& d) {
  if (!d.rows) return;
  if (2 * d.early > d.rows)
    std::printf(
        "the profiler saw %zu of %zu places before the nozzle laid them (by %.3f s, mean): the log is not on the "
        "profiles' clock, or its layers or places are not the scan's; the flow stands on the log's own times and "
        "speeds, but when each place was measured after it was laid cannot be read\n",
        d.early, d.rows, -d.Mean());
  else
    std::printf(
        "the profiler saw each place %.3f s after the nozzle laid it (mean; %.3f to %.3f s): the bead's time to cool "
        "before it was measured%s\n",
        d.Mean(), d.min_s, d.max_s,
        d.early ? "; some places were seen before they were laid: the log's clock and the profiles' disagree there"
                : "");
}

}  // namespace

Error NoNozzleLog(const std::string& run) {
  if (run.ends_with(".csv"))
    return Error(Located(run, "",
                         "a part profiles CSV carries no log, and the flow along the path needs the nozzle's: bead "
                         "import it with --log LOG.csv (docs/data-formats.md, part scan CSV forms)"));
  return Error(Located(run, "/log", "missing group: the flow along the path needs the nozzle's log"));
}

int FlowPartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                 const ProfileOptions& bed) {
  const RunArchive scan = ReadPartScan(run, false, true);
  if (!scan.log) throw NoNozzleLog(run);
  const Rig rig = PartRigSaying(rig_path);
  part::PartFlowCsvWriter out(output);
  const part::MeasurePartOptions options = part::PartOptionsFor(bed);
  const auto start = std::chrono::steady_clock::now();
  const part::PartScanFlow f = part::MeasurePartScanFlow(
      run, *scan.part, &*scan.log, rig, options, 0, nullptr, [&](const part::PartFlowRow& row) { out.Append(row); },
      TtyProgress("measured"));
  out.Commit();
  SayMeasured(run, f.layers, scan.part->size(), start);
  std::printf("wrote %s (t_s: when the nozzle laid each place; flow = head speed x area)\n", output.c_str());
  for (const part::LayerSummary& l : f.layers)
    if (const auto v = f.volumes_mm3.find(l.layer); v != f.volumes_mm3.end())
      std::printf("  layer %lld: %.1f mm^3 along the path\n", static_cast<long long>(l.layer), v->second);
    else
      std::printf("  layer %lld: no volume (none of its profiles has a flow: below)\n",
                  static_cast<long long>(l.layer));
  if (f.volumes_mm3.size() < f.layers.size())
    std::printf("total volume %.1f mm^3 over %zu of the %zu layers, those with a flow: not the part's\n",
                f.TotalVolume(), f.volumes_mm3.size(), f.layers.size());
  else
    std::printf("total volume %.1f mm^3 (the area integrated along the path, valid profiles)\n", f.TotalVolume());
  SayScanDelay(f.delay);
  SayUncorrectedFlow(f.layers);
  if (const part::CornerBulge& b = f.bulge; b.slow)
    std::printf(
        "where the head slowed below 90 %% of its median speed (%zu profiles, %.1f against %.1f mm/s: corners), the "
        "area is %+.1f %% over the rest and the flow %+.1f %%: %s\n",
        b.slow, b.slow_speed_mm_s, b.rest_speed_mm_s, 100 * b.area_excess, 100 * b.flow_excess,
        std::abs(b.flow_excess) < 0.5 * std::abs(b.area_excess)
            ? "the extruder did not follow the head (the corner bulge, thesis 1.3.2)"
            : "the extruder's flow followed the head's speed");
  if (f.replaced)
    std::printf(
        "  %zu profiles' flows stood apart from their neighbours' along the layer's path (over %.0f sigmas; a Hampel "
        "filter of +-%d profiles, as the wheel's area): each took its window's median\n",
        f.replaced, part::FlowHampel::kSigmas, part::FlowHampel::kHalfWindow);
  if (f.unplaced)
    std::printf("  %zu %s where the log never had the nozzle pass in the layer's printing direction: no time\n",
                f.unplaced, f.unplaced == 1 ? "profile stands" : "profiles stand");
  if (2 * f.unplaced > scan.part->size())
    SayPathRanges(*scan.part, *scan.log);
  else if (f.unplaced)
    SayLayersNotLogged(*scan.part, *scan.log);
  return 0;
}

}  // namespace bead::tools
