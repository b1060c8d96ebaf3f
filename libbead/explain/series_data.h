// SeriesData: what the explain loop works on - a measured output y against
// a base model's prediction at the same times, with whatever the data lets
// us reconstruct beside it (the phase of each rotating part, the time
// between laying and measuring, the bead's height, time since the process
// started), and how to re-evaluate y and the prediction when the data is
// shifted in wheel position or the model's input in time.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace bead::explain {

// A rotating part whose phase the data gives: its angle at each sample.
struct RotatingPart {
  std::string name;               // e.g. "wheel at the nozzle"
  std::vector<double> angle_rad;  // unwrapped
};

// Another recorded quantity (a barrel temperature, a pressure) on its own
// clock: a candidate cause acting on the output through a lag and delay.
struct Channel {
  std::string name, unit;
  std::vector<double> t, values;  // same length, t increasing
};

// The last shifted evaluation (effect_fit.cc), so that a fit whose
// parameters do not move the data (a channel's lag, a periodic term) does
// not re-find every extrusion time at each trial. A copy of the data starts
// with an empty memo: a copy may be given other hooks.
struct ShiftMemo {
  bool valid = false;
  double shift = 0.0;
  std::vector<double> delay, y, base;
  std::vector<std::vector<double>> initial;
};
class ShiftMemoSlot {
 public:
  ShiftMemoSlot() = default;
  ShiftMemoSlot(const ShiftMemoSlot&) {}
  ShiftMemoSlot& operator=(const ShiftMemoSlot&) {
    memo.valid = false;
    return *this;
  }
  ShiftMemo memo;
};

// Another input of a base model with several (model/identify_multi.h): its
// part of `base` at each sample, its gain refitted with the base's.
struct InputPart {
  std::string name;
  std::vector<double> values;
};

struct SeriesData {
  std::vector<double> t, u, y, base;  // same length, finite
  std::string y_unit = "";            // for the report
  std::vector<RotatingPart> parts;
  std::vector<double> time_to_laser_s;  // empty when not known
  std::vector<double> height_mm;        // the bead height the model implies (never the measured one); empty: not known
  std::vector<double> segment_time_s;   // time since the process (re)started
  std::vector<Channel> channels;        // the other recorded channels
  std::vector<InputPart> input_parts;   // a base model's inputs after the first (their parts are in base)
  // The model's input through a basis of linear filters (the states of
  // 1 / (s + p)^K and the input itself, p from the model's own poles): any
  // linear correction of the model's dynamics is a combination of these.
  // The explain loop holds every candidate against it, so an effect that
  // only buys a wrong base model's misfit is not added.
  std::vector<std::vector<double>> dynamics;
  // The model's free responses from each stretch's start (n per stretch,
  // zero outside it): the base model's initial state, refitted with every
  // candidate like its gain and operating point.
  std::vector<std::vector<double>> initial;
  // y and base with the extrusion times moved by `counts` of wheel position
  // and the model input delayed by extra_delay_s[i] more; empty function
  // when the data has no wheel (then only the delay applies, through
  // base_delayed).
  std::function<void(double counts, const std::vector<double>& extra_delay_s, std::vector<double>& y,
                     std::vector<double>& base)>
      shifted;
  std::function<std::vector<double>(const std::vector<double>& extra_delay_s)> base_delayed;
  // Set the hooks before the first evaluation: the memo is keyed on the
  // shift and the delays only.
  mutable ShiftMemoSlot shift_memo;

  std::size_t size() const { return t.size(); }
};

}  // namespace bead::explain
