// Flow along the toolpath of a part scan (format 1.1): each profile's
// extrusion time is when the nozzle stood at the profile's place (its
// layer and path_mm, from /log/layer and /log/path_mm), and the flow there
// is Q = v_head A: the head's speed along the path times the area the
// layer added (the thesis' Q = v A with the head's speed in place of the
// wheel's surface speed).
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "libbead/core/run_data.h"
#include "libbead/part/measure_part.h"

namespace bead::part {

// When the nozzle was where: the log's samples of each layer while the
// head moved along the path in the layer's printing direction. A layer is
// printed one way: forward (path_mm growing), or backward (a wall laid
// back and forth, every other layer from the far end); the other way is a
// travel. The printing direction is the one the extruder turned over
// longer (the screw's revolutions, /log/screw_rpm over time, summed over
// the layer's stretches each way; where the screw never turned, the time
// spent each way); forward on a tie.
class NozzleClock {
 public:
  // Throws (naming `file`) when the log is not a part scan's, or where it
  // logs the head's speed, when that speed is not the path's: its median
  // over the printing intervals' path speeds outside [kLoggedSpeedLow,
  // 1 / kLoggedSpeedLow] (a speed in mm/min, a commanded feed rate the
  // head did not reach: every flow off by that factor, unsaid). Braking
  // at corners moves a few intervals, not the median.
  static constexpr double kLoggedSpeedLow = 0.8;
  NozzleClock(const AcquisitionLog& log, const std::string& file);

  struct Passing {
    double t_s = 0.0, head_speed_mm_s = 0.0, screw_rpm = 0.0;
  };
  // The first time the nozzle passed `path_mm` in `layer` in its printing
  // direction; its speed along the path (a magnitude, whichever way), and
  // the screw's speed then; nullopt where it never did. Between two of the
  // log's samples, where it logs the head's speed: the speed quadratic in
  // time through the two logged speeds, its integral the path between them
  // (exact where the head accelerates evenly; where it brakes into a corner
  // within the interval, the path says by how much the speed dipped: at a
  // 10 Hz log of a generator's contour, the speed's RMS error 0.24 mm/s
  // linear, 0.08 this way; at 100 Hz, 0.007 and 0.002), the time where its
  // integral reaches the place. Where the log holds no speed, the path's
  // mean speed over the interval, the time linear; where that quadratic
  // would stop the head, linear between the logged speeds. (Speeds
  // at the samples from the path's differences, quadratic between, were
  // closer on average, 0.20 mm/s against the means' 0.31 at 10 Hz, but
  // spread a corner's braking over two intervals, which the flow's filter
  // along the path, part/flow_hampel.h, cannot take out, as it takes out
  // the means' few rows off: the flow fit 78.0 %, against 85.5 %.)
  std::optional<Passing> At(int64_t layer, double path_mm) const;
  // +1 where `layer` was printed forward, -1 backward, 0 not in the log.
  int Direction(int64_t layer) const;

 private:
  const AcquisitionLog& log_;
  // A monotone stretch of one layer's samples: [first, last] indices, the
  // path growing (forward) or falling along it.
  struct Stretch {
    std::size_t first, last;
    bool forward;
  };
  // Each layer's printing stretches.
  std::map<int64_t, std::vector<Stretch>> printing_;
  // Within samples i and i + 1, the place a fraction w of the path
  // between them: when (the fraction of the time between them) and at what
  // speed the head passed it.
  std::pair<double, double> Within(std::size_t i, double w) const;
  // Throws where the logged head speed is not the path's (the constructor's
  // check).
  void CheckLoggedSpeed(const std::string& file) const;
};

struct PartFlowRow {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double t_s = kNaN;  // when the nozzle laid this place
  int64_t layer = 0;
  double path_mm = 0.0;
  double head_speed_mm_s = kNaN;
  double area_mm2 = kNaN;
  double area_corrected_mm2 = kNaN;
  // v_head times the corrected area; the area seen where the groove is not
  // estimated (MeasurePartOptions::correct_hidden false)
  double flow_mm3_s = kNaN;
  // Its sigma, v_head times the corrected area's (NaN without one), and
  // whether a filter along the path replaced it (part/flow_hampel.h).
  double flow_sigma_mm3_s = kNaN;
  bool flow_replaced = false;
  double screw_rpm = kNaN;
  int64_t profile = 0;
  bool valid = false;
  // The area the flow stands for: the corrected one where there is one.
  double Area() const { return std::isnan(area_corrected_mm2) ? area_mm2 : area_corrected_mm2; }
};

// A profile's flow row; invalid (NaN) where its geometry is, or where the
// log never had the nozzle at its place, or, where the hidden groove is
// estimated (`corrected`), where the profile's corrected area was refused
// (its outline none of the model's shapes, or not fitted; the area seen
// then stands in the row, and counts what an overhanging bead hides as
// material: a flow from it is not checked, and not given).
PartFlowRow FlowOf(const PartGeometryRow& geometry, const NozzleClock& clock, bool corrected);

// The volume each layer added, the trapezoid integral of the area along the
// path (mm^3), over the valid rows of each layer in the scan's order: the
// steps the way the layer went along its path (forward, or backward on a
// layer laid from the far end: the way its steps cover more path); a step
// the other way (a place scanned again) is not new material.
class LayerVolumes {
 public:
  void Add(const PartFlowRow& row);
  std::map<int64_t, double> volumes_mm3() const;

 private:
  struct Layer {
    double path_mm = 0.0, area_mm2 = 0.0;  // its last valid row's
    double way[2] = {0.0, 0.0};            // the integral over its steps back [0] and forward [1]
    double covered[2] = {0.0, 0.0};        // the path those steps cover
  };
  std::map<int64_t, Layer> layers_;
};

// Where the head slowed (a corner) against where it did not: the thesis'
// corner bulge (1.3.2: the gantry slows into a corner with the extruder's
// command unchanged, so the bead grows there). Rows slower than `fraction`
// of the median head speed are the slow ones.
struct CornerBulge {
  std::size_t slow = 0, rest = 0;
  double slow_speed_mm_s = 0.0, rest_speed_mm_s = 0.0;  // mean
  double area_excess = 0.0;                             // mean area slow / rest - 1
  double flow_excess = 0.0;                             // mean flow slow / rest - 1
};

class SpeedAndArea {
 public:
  void Add(const PartFlowRow& row);
  // Nothing slow (a straight wall at one speed): slow = 0.
  CornerBulge Bulge(double fraction = 0.9) const;

 private:
  std::vector<double> speed_, area_, flow_;  // the valid rows'
};

// A part scan's geometry and its flow along the path in one streamed pass
// (bead flow, bead batch and bead report): each geometry row to
// `on_geometry`; with a log, each flow row to `on_flow`; `progress` with
// the profiles done and their total.
struct PartScanFlow {
  std::vector<LayerSummary> layers;
  bool has_flow = false;  // the scan has a log
  std::map<int64_t, double> volumes_mm3;
  CornerBulge bulge;
  std::size_t flow_samples = 0;  // valid flow rows
  std::size_t unplaced = 0;      // rows whose place the log never had the nozzle pass
  std::size_t replaced = 0;      // rows whose flow the filter along the path replaced (part/flow_hampel.h)
  // How long after the nozzle laid each place the profiler saw it (the
  // profile's time less its row's t_s), over the rows the log placed: the
  // bead's time to cool before it was measured. Rows seen before they were
  // laid (`early`, over kEarlyS) say the log is not on the profiles' clock,
  // or its layers or places are not the scan's.
  struct ScanDelay {
    static constexpr double kEarlyS = 1e-3;
    std::size_t rows = 0, early = 0;
    double sum_s = 0.0, min_s = INFINITY, max_s = -INFINITY;
    void Add(double delay_s);
    double Mean() const { return rows ? sum_s / static_cast<double>(rows) : std::nan(""); }
  } delay;
  double TotalVolume() const;
};
PartScanFlow MeasurePartScanFlow(const std::string& path, const PartPlaces& places, const AcquisitionLog* log,
                                 const Rig& rig, const MeasurePartOptions& options, unsigned threads,
                                 const std::function<void(const PartGeometryRow&)>& on_geometry,
                                 const std::function<void(const PartFlowRow&)>& on_flow,
                                 const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

}  // namespace bead::part
