// A run's plain data as every stage sees it, whatever file it came from:
// the profiles (time, encoder, points) and the acquisition log. io/ reads
// and writes them; profile/, flow/ and explain/ work on them and read no
// file format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "libbead/core/profile_view.h"

namespace bead {

// N profiles of P points each (profiles with fewer points pad with NaN).
// A block may also hold only t_s and encoder (points = 0): the per-profile
// clock of a run whose points were streamed and let go.
struct ProfileBlock {
  std::vector<double> t_s;       // [N]
  std::vector<int64_t> encoder;  // [N]
  std::vector<float> x_mm;       // [P] when shared_x, else [N * P]
  std::vector<float> z_mm;       // [N * P]
  std::size_t points = 0;        // P
  bool shared_x = true;

  std::size_t size() const { return t_s.size(); }
  ProfileView view(std::size_t i) const {
    ProfileView v;
    v.x_mm = shared_x ? std::span<const float>(x_mm.data(), points)
                      : std::span<const float>(x_mm.data() + i * points, points);
    v.z_mm = std::span<const float>(z_mm.data() + i * points, points);
    v.t_s = t_s[i];
    v.encoder = encoder[i];
    return v;
  }
};

// Any other quantity the acquisition recorded on the log's clock (a barrel
// temperature, heater power, melt pressure, motor current): /log/<name>.
struct LogChannel {
  std::string name;
  std::string unit;            // "" when the file does not say
  std::vector<double> values;  // [M]
};

// Where each profile of a part scan stood (format 1.1: beads on a part, the
// profiler on the print head): motion, not recorded channels. A place on
// the part is its layer and its position along the layer's toolpath, the
// same curve in every layer.
struct PartPlaces {
  std::vector<int64_t> layer;      // [N] 0 = the first layer, on the bed
  std::vector<double> path_mm;     // [N] along the toolpath from its start
  std::vector<double> frame_z_mm;  // [N] height above the bed of the profile frame's z = 0
  std::vector<double> frame_x_mm;  // [N] the frame's x = 0 left of the path's centre line; 0 when not recorded
  std::size_t size() const { return layer.size(); }
};

// The acquisition log (thesis 3.1: the wheel's encoder and the screw's RPM,
// sampled on their own clock). A part scan's log has no encoder and holds
// where the nozzle was instead (layer, path_mm; the head's speed when
// recorded).
struct AcquisitionLog {
  std::vector<double> t_s;
  std::vector<int64_t> encoder;  // empty in a part scan's log
  std::vector<double> screw_rpm;
  std::vector<double> extruder_cmd_v;   // empty when absent
  std::vector<double> wheel_cmd_v;      // empty when absent
  std::vector<LogChannel> channels;     // the other recorded channels, by name
  std::vector<int64_t> layer;           // part scans: the layer being printed
  std::vector<double> path_mm;          // part scans: the nozzle's place along the toolpath
  std::vector<double> head_speed_mm_s;  // part scans, optional: the head's speed along the path
  bool part() const { return !layer.empty() || !path_mm.empty(); }
  std::size_t size() const { return t_s.size(); }
};

}  // namespace bead
