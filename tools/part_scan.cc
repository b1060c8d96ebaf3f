#include "tools/part_scan.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "libbead/archive/open_run.h"
#include "libbead/core/worker_pool.h"
#include "libbead/io/part_scan_csv.h"
#include "libbead/io/run_archive.h"
#include "libbead/part/measure_part.h"
#include "libbead/core/error.h"
#include "libbead/part/part_csv.h"
#include "libbead/part/flow_hampel.h"
#include "libbead/part/part_flow.h"
#include "tools/rig_input.h"
#include "tools/tty_progress.h"

namespace bead::tools {
namespace {

// The rows whose bead's outline is not one the model knows, by why
// (part/hidden_groove.h: OutlineMisfit).
void SayMisfits(const part::LayerSummary& l) {
  using part::OutlineMisfit;
  // (Where the tops and walls did not pin their shape, the misfit is the
  // ellipse assumed for them: SayShape.)
  std::printf(
      "    %zu valid profiles without a corrected area: %s, so the hidden groove is not estimated and the area "
      "seen stands (",
      l.Misfits(),
      l.shape && l.shape->ShapeUnpinned()
          ? "the ellipse assumed for their beads (their own shape not solved: below) is not their outline"
          : "the bead's outline is none of the model's shapes");
  const char* sep = "";
  const auto say = [&](OutlineMisfit m, const std::string& why) {
    if (const std::size_t n = l.misfit[static_cast<std::size_t>(m)])
      std::printf("%s%zu: %s", sep, n, why.c_str()), sep = "; ";
  };
  char top[640];
  if (l.shape)
    std::snprintf(top, sizeof top,
                  "the layer's shape misses its beads' tops by %.1f times what a top may leave (the noise, %.1f "
                  "%% of the height and what the ends' cells, a point spacing wide, leave on it, in quadrature; "
                  "median; over %.0f, it is not their shape, or it cannot be placed on them: where a bead's end "
                  "stands over a steep flank of the layer below that the points sample a spacing apart, that "
                  "surface between two points is not known, nor the end's wall)",
                  l.shape->top_noise, 100.0 * part::kTopShapeHeights, part::kTopOffNoise);
  else
    std::snprintf(top, sizeof top,
                  "too few rows to pool the layer's shape, and each one's own misses its top by over %.0f times the "
                  "noise, %.1f %% of its height and what the ends' cells leave, in quadrature",
                  part::kTopOffNoise, 100.0 * part::kTopShapeHeights);
  say(OutlineMisfit::kFloats, "the shape fitting its top would float over the surface it was laid on");
  say(OutlineMisfit::kTopOff, top);
  say(OutlineMisfit::kFamilyEdge, "boxier or more pointed than any of the shapes");
  if (l.shape && l.shape->ends_off_layer >= 0)
    say(OutlineMisfit::kEndsOff,
        "as layer " + std::to_string(l.shape->ends_off_layer) +
            "'s walls showed (this layer shows too few walls to judge its own, and carries the shape of the layers "
            "below): in most of that layer's rows placed at their walls, the shape solved over the top put an end off "
            "the wall the profile showed, and no shape of the model's has both those tops and those walls");
  else
    say(OutlineMisfit::kEndsOff,
        "in most of the layer's rows placed at their walls, the shape solved over the top puts an end off the wall "
        "the profile shows: no shape of the model's has both those tops and those walls");
  std::printf(")\n");
}

// Layer 0's profiles whose reference areas hold no bare flat bed (a bead
// standing in them; no line to the noise).
void SayNoBareBed(std::size_t in_reference, std::size_t not_a_line, const char* indent) {
  if (in_reference)
    std::printf(
        "%s%zu profiles of layer 0 have a bead standing in the rig's reference areas (sensor.reference_areas_mm): "
        "they hold no bare bed to measure against, and those profiles are not measured (status "
        "bead_in_reference_area): set the areas where the bed is bare\n",
        indent, in_reference);
  if (not_a_line)
    std::printf(
        "%s%zu profiles of layer 0 have reference areas that are no line to the profile's noise (status "
        "reference_not_a_line; over %.0f times it, and over the least bead threshold): a bead fills them, or the bed "
        "is not flat there (a pipe: part: "
        "{bed: cylinder}); those profiles are not measured: set the areas where the bed is bare and flat, or the "
        "bed's shape\n",
        indent, not_a_line, part::kReferenceNoises);
}

// A layer's profiles whose new surface lies under the surface before it
// (status under_surface_below), in words: what is wrong and where to look.
void SayUnder(const part::LayerSummary& l, const char* indent) {
  if (l.under_mm.empty()) return;
  if (l.layer == 0)
    std::printf(
        "%s%zu profiles of layer 0 lie under the bed line the rig's reference areas give, over more of their points "
        "than any bead stands over it (status under_surface_below; %.3f mm under, median): its z is a distance from "
        "the sensor, not a height (the bead a trough: bead import --z-distance), or the areas do not lie on the bed "
        "the bead was laid on (a clamp, a raised plate: set them where the bed is bare); those profiles are not "
        "measured\n",
        indent, l.under_mm.size(), -l.MedianUnder());
  else
    std::printf(
        "%s%zu profiles' surface lies under the surface layer %lld left, over more of their points than any bead "
        "stands over it (status under_surface_below; %.3f mm under, median): a layer only adds material, so the "
        "two scans are not where their frames say. /profiles/frame_z_mm must be the head's height above the bed at "
        "each profile (bead import --frame-z-column; without it every profile's is 0, right only where the "
        "profiler does not rise with the part); those profiles are not measured\n",
        indent, l.under_mm.size(), static_cast<long long>(l.layer - 1), -l.MedianUnder());
}

// A layer's profiles whose bare bed in the reference areas lies off the
// layer below's scan of it (status bed_moved).
void SayBedMoved(const part::LayerSummary& l, const char* indent) {
  if (l.bed_off_mm.empty()) return;
  const double off = l.MedianBedOff();
  std::printf(
      "%s%zu profiles' bare bed in the rig's reference areas lies %.3f mm %s where layer %lld's scan has it (status "
      "bed_moved; median): the bed does not move between layers, so the two scans are not where their frames say. "
      "/profiles/frame_z_mm must be the head's height above the bed at each profile, in mm, and z a height, not a "
      "distance from the sensor (bead import --z-distance)%s; those profiles are not measured\n",
      indent, l.bed_off_mm.size(), std::abs(off), off < 0.0 ? "under" : "over", static_cast<long long>(l.layer - 1),
      off < 0.0 ? ""
                : ". Or this layer's material covers both areas at one height (a layer wider than the field of view), "
                  "which a profile cannot tell from a frame one layer off: sensor.reference_areas_mm must lie where "
                  "no layer reaches");
}

void SayLayers(const std::vector<part::LayerSummary>& layers) {
  for (const part::LayerSummary& l : layers) {
    std::printf("  layer %lld: %zu profiles over path %.1f to %.1f mm, %zu valid", static_cast<long long>(l.layer),
                l.profiles, l.first_path_mm, l.last_path_mm, l.valid);
    if (l.valid) std::printf(", mean area %.3f mm^2 seen", l.MeanArea());
    if (l.corrected) std::printf(", %.3f less the groove hidden under its overhangs", l.MeanCorrected());
    if (l.layer == 0) {
      std::printf(" (on the bed)\n");
      if (l.no_surface_below)
        std::printf(
            "    %zu profiles of layer 0 have no bed to measure against (status no_surface_below): the rig's reference "
            "areas (sensor.reference_areas_mm) hold too few of their points (at least 5 each, on the bare bed, within "
            "the profiles' x range), or no line (an arc, for bed: cylinder) fits them\n",
            l.no_surface_below);
    } else if (l.no_surface_below == l.profiles)
      std::printf("; layer %lld is not in the scan: nothing to measure it against\n",
                  static_cast<long long>(l.layer - 1));
    else if (!l.valid)
      std::printf("\n");  // (no shift to speak of: why none is valid follows)
    else if (l.shift_found)
      std::printf("; pass shift %+.3f mm (median; found in %zu profiles)\n", l.MedianShift(), l.shift_found);
    else
      std::printf("; pass shift not found (the layer below shows nowhere beside the new bead): no offset\n");
    if (l.layer > 0 && l.no_surface_below && l.no_surface_below < l.profiles)
      std::printf(
          "    %zu profiles lie where layer %lld's profiles around them are more than %.0f mm of path apart, or it "
          "ends more than that before them (status no_surface_below): its surface there is not known\n",
          l.no_surface_below, static_cast<long long>(l.layer - 1), part::SurfaceBelowOptions{}.max_path_gap_mm);
    SayNoBareBed(l.bead_in_reference, l.reference_not_a_line, "    ");
    SayUnder(l, "    ");
    SayBedMoved(l, "    ");
    if (l.Misfits()) SayMisfits(l);
    if (l.valid > l.corrected + l.Misfits())
      std::printf("    %zu valid profiles without a corrected area: the bead's outline could not be fitted\n",
                  l.valid - l.corrected - l.Misfits());
    if (l.loose)
      std::printf(
          "    %zu profiles' corrected areas are loose (sigma over a tenth of the area): the bead's sides are not "
          "seen steep enough to place its widest point\n",
          l.loose);
    if (l.below_steps)
      std::printf(
          "    %zu profiles stand where layer %lld steps between its two profiles around them (its bead's area "
          "changes there beyond its trend along the path, as where a corner's bulge begins or ends): where between "
          "them the step lies is not seen, and their sigmas hold it (up to %.3f mm^2)\n",
          l.below_steps, static_cast<long long>(l.layer - 1), l.below_step_sigma_mm2);
    if (l.inside_cliff)
      std::printf(
          "    %zu profiles' beads placed at the rise inside the largest, which steps over the cliff of the layers "
          "below (read at another pass's points, that cliff leaves gains past the bead's end): their tops fit "
          "there, and half the two placements' difference is in their sigmas\n",
          l.inside_cliff);
    if (l.shape && !l.shape->exponent_solved && l.corrected && l.hidden_sum_mm2 <= 1e-9 * l.area_sum_mm2)
      std::printf(
          "    bead shape: not seen (no bead of the layer overhangs what it was laid on, so nothing is hidden and the "
          "area seen is the material, whatever the outline under the surface)\n");
    else if (l.shape)
      SayShape(*l.shape);
  }
}

}  // namespace

// The part scan's rig file, its warnings said.
Rig PartRigSaying(const std::string& rig_path) {
  const RigFile rig = ReadPartRigFile(rig_path);
  SayRigWarnings(rig);
  return rig.rig;
}

// What was measured: a line for the scan, one per layer.
void SayMeasured(const std::string& run, const std::vector<part::LayerSummary>& layers, std::size_t total,
                 std::chrono::steady_clock::time_point start) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::size_t valid = 0;
  for (const auto& l : layers) valid += l.valid;
  std::printf("%s: part scan, %zu profiles in %zu layer%s, %zu valid, measured in %.3f s\n", run.c_str(), total,
              layers.size(), layers.size() == 1 ? "" : "s", valid, seconds);
  SayLayers(layers);
}

int MeasurePartScan(const std::string& rig_path, const std::string& run, const std::string& output,
                    const ProfileOptions& bed, unsigned threads) {
  const RunArchive scan = ReadPartScan(run, false, false);
  const Rig rig = PartRigSaying(rig_path);
  part::PartGeometryCsvWriter out(output);
  const part::MeasurePartOptions options = part::PartOptionsFor(bed);
  const auto start = std::chrono::steady_clock::now();
  const auto layers = part::MeasurePartFile(
      run, *scan.part, rig, options, threads, [&](const part::PartGeometryRow& r) { out.Append(r); },
      TtyProgress("measured"));
  out.Commit();
  SayMeasured(run, layers, scan.part->size(), start);
  std::printf("wrote %s (area_corrected_mm2: less the groove a bead hides under its overhangs, with its sigma)\n",
              output.c_str());
  return 0;
}

namespace {

// A run's profiles as a part's first layer: each on the bed.
PartPlaces OnTheBed(std::size_t n) {
  PartPlaces p;
  p.layer.assign(n, 0);
  p.path_mm.assign(n, std::nan(""));
  p.frame_z_mm.assign(n, 0.0);
  p.frame_x_mm.assign(n, 0.0);
  return p;
}

void SayRoads(const part::RoadsSummary& s, bool laid_left_first, const std::vector<part::LayerSummary>& layers) {
  // Profiles with no surface below, or none to trust (said below, with
  // why) hold no beads: the count of none is of those measured that showed
  // none.
  std::size_t no_surface = 0, in_reference = 0, not_a_line = 0, under = 0;
  for (const part::LayerSummary& l : layers)
    no_surface += l.no_surface_below, in_reference += l.bead_in_reference, not_a_line += l.reference_not_a_line,
        under += l.FramesDisagree();
  const bool above_bed =
      std::any_of(layers.begin(), layers.end(), [](const part::LayerSummary& l) { return l.layer > 0; });
  const std::size_t unmeasured = no_surface + in_reference + not_a_line + under;
  for (const auto& [count, profiles] : s.profiles_by_count) {
    if (count > 0)
      std::printf("  %zu profiles with %zu bead%s\n", profiles, count, count == 1 ? "" : "s");
    else if (profiles > unmeasured)
      std::printf("  %zu profiles measured with no bead over the surface below\n", profiles - unmeasured);
  }
  if (s.cut_by_edge)
    std::printf("  %zu beads cut by the field of view's end: flagged invalid, their size not given\n", s.cut_by_edge);
  if (s.no_fit) std::printf("  %zu stretches the overlap model could not explain: flagged no_fit\n", s.no_fit);
  if (const std::string words = s.SpacingInWords(); !words.empty()) std::printf("  %s\n", words.c_str());
  if (const std::string words = s.OrderInWords(laid_left_first); !words.empty()) std::printf("  %s\n", words.c_str());
  SayNoBareBed(in_reference, not_a_line, "  ");
  for (const part::LayerSummary& l : layers) SayUnder(l, "  "), SayBedMoved(l, "  ");
  if (no_surface)
    std::printf(
        "  %zu profiles have no surface below to measure against (layer 0: no bare bed in the reference areas; "
        "above: the layer below not scanned within 5 mm along the path): no beads there\n",
        no_surface);
  if (above_bed)
    std::printf(
        "  layers above the first: their beads over the layer below, moved by the shift its registration found\n");
  std::printf(
      "  area_corrected_mm2 is left empty: the overlap model's road tops are surfaces over x, which hide nothing "
      "from a sensor above, and what an outer road may hide under an overhanging flank the profile cannot show "
      "(no occlusion model for several beads yet): area_mm2 is the material seen\n");
}

}  // namespace

int MeasureRoads(const std::string& rig_path, const std::string& run, const std::string& output,
                 const ProfileOptions& bed, bool laid_left_first, unsigned threads) {
  const Rig rig = PartRigSaying(rig_path);
  part::MeasurePartOptions options = part::PartOptionsFor(bed);
  options.several_beads = true;
  options.correct_hidden = false;  // the roads' rows carry no corrected area: its fit would be thrown away
  options.roads.laid_left_first = laid_left_first;
  WorkerPool pool(threads);
  std::unique_ptr<ProfileStream> stream;
  PartPlaces places;
  if (IsPartScanFile(run)) {
    places = *ReadPartScan(run, false, false).part;
    stream = OpenPartProfiles(run, pool);
  } else {
    stream = std::move(OpenRun(run, pool, /*with_log=*/false).profiles);
    places = OnTheBed(stream->size());
  }
  part::RoadsCsvWriter out(output);
  part::RoadsSummary summary;
  const auto tty = TtyProgress("measured");
  const std::size_t total = stream->size();
  const std::vector<part::LayerSummary> layers = part::MeasurePart(
      *stream, places, rig, options,
      [&](const part::PartGeometryRow& r) {
        out.Append(r);
        summary.Add(r.roads, laid_left_first);
      },
      [&](std::size_t done) {
        if (tty) tty(done, total);
      });
  out.Commit();
  std::printf("%s: %zu profiles, %zu beads found (laid %s); wrote %s\n", run.c_str(), total, summary.roads,
              laid_left_first ? "left to right" : "right to left", output.c_str());
  SayRoads(summary, laid_left_first, layers);
  return 0;
}

}  // namespace bead::tools
