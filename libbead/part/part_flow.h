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
#include <vector>

#include "libbead/core/run_data.h"
#include "libbead/part/measure_part.h"

namespace bead::part {

// When the nozzle was where: the log's samples of each layer while the
// head moved forward along the path (printing; a travel back is not).
class NozzleClock {
 public:
  // Throws (naming `file`) when the log is not a part scan's.
  NozzleClock(const AcquisitionLog& log, const std::string& file);

  struct Passing {
    double t_s = 0.0, head_speed_mm_s = 0.0, screw_rpm = 0.0;
  };
  // The first time the nozzle passed `path_mm` moving forward in `layer`,
  // linear between the log's samples; nullopt where it never did.
  std::optional<Passing> At(int64_t layer, double path_mm) const;

 private:
  const AcquisitionLog& log_;
  // Each layer's forward stretches: [first, last] sample indices.
  std::map<int64_t, std::vector<std::pair<std::size_t, std::size_t>>> forward_;
  double SpeedAt(std::size_t i, double t) const;
};

struct PartFlowRow {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double t_s = kNaN;  // when the nozzle laid this place
  int64_t layer = 0;
  double path_mm = 0.0;
  double head_speed_mm_s = kNaN;
  double area_mm2 = kNaN;
  double area_corrected_mm2 = kNaN;
  double flow_mm3_s = kNaN;  // v_head times the corrected area where there is one, else the area
  double screw_rpm = kNaN;
  int64_t profile = 0;
  bool valid = false;
  // The area the flow stands for: the corrected one where there is one.
  double Area() const { return std::isnan(area_corrected_mm2) ? area_mm2 : area_corrected_mm2; }
};

// A profile's flow row; invalid (NaN) where its geometry is, or where the
// log never had the nozzle at its place.
PartFlowRow FlowOf(const PartGeometryRow& geometry, const NozzleClock& clock);

// The volume each layer added, the trapezoid integral of the area along the
// path (mm^3), over the valid rows of each layer in path order.
class LayerVolumes {
 public:
  void Add(const PartFlowRow& row);
  const std::map<int64_t, double>& volumes_mm3() const { return volume_; }

 private:
  std::map<int64_t, double> volume_;
  std::map<int64_t, std::pair<double, double>> last_;  // path, area of the layer's last valid row
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
  double TotalVolume() const;
};
PartScanFlow MeasurePartScanFlow(const std::string& path, const PartPlaces& places, const AcquisitionLog* log,
                                 const Rig& rig, const MeasurePartOptions& options, unsigned threads,
                                 const std::function<void(const PartGeometryRow&)>& on_geometry,
                                 const std::function<void(const PartFlowRow&)>& on_flow,
                                 const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

}  // namespace bead::part
