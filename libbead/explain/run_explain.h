// explain's run mode as one call: a run's measured flow (and another run
// as held-out data) against a model of flow from screw speed, the loop
// run on it, the offset the run implies set beside the rig file's and the
// pin scans', and the flow with what acts on the measurement undone. The
// caller measures the runs (archive/measured_run.h) and reads the model and
// the pins; `bead explain --rig` is this call and its printing.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "libbead/core/rig.h"
#include "libbead/core/run_data.h"
#include "libbead/explain/corrected_flow.h"
#include "libbead/explain/explain_loop.h"
#include "libbead/explain/run_series.h"
#include "libbead/flow/flow.h"
#include "libbead/model/transfer_function.h"
#include "libbead/profile/bead_geometry.h"

namespace bead::explain {

// A measured run, as views (the caller keeps them alive).
struct MeasuredFlow {
  std::string path;  // for messages
  const ProfileBlock* profiles = nullptr;
  const std::vector<BeadGeometry>* geometry = nullptr;
  const AcquisitionLog* log = nullptr;
  const FlowResult* flow = nullptr;
  const std::vector<double>* corrected_area = nullptr;  // the occlusion stage's (may be empty)
  const std::vector<double>* corrected_sigma = nullptr;

  // The occlusion stage's columns, empty where it gave none.
  const std::vector<double>& CorrectedArea() const { return OrNone(corrected_area); }
  const std::vector<double>& CorrectedSigma() const { return OrNone(corrected_sigma); }

 private:
  static const std::vector<double>& OrNone(const std::vector<double>* v) {
    static const std::vector<double> none;
    return v ? *v : none;
  }
};

struct RunExplainOptions {
  ExplainOptions explain;               // its `validation` is set by the call
  std::vector<std::string> channels;    // the recorded channels to try (empty: every one)
  bool no_channels = false;             // try none
  bool correct_flow = false;            // compute the corrected flow
  std::size_t profiles_per_sample = 0;  // profiles averaged per sample of the series (0: ExplainBinOf)
};

// The encoder offset the run implies, in counts of the rig file's scale.
struct OffsetFromRun {
  bool estimated = false;
  double counts = NAN, lo_counts = NAN, hi_counts = NAN;  // best and 95 % interval
  double ci95_counts = NAN;                               // half-width (larger side); infinite: not pinned
  bool pinned = false;                                    // the interval does not reach the searched range
  bool excludes_rig = false;                              // the rig file's offset lies outside it
  double delay_correlation = NAN;
  // Not pinned because the profile with the model identified again at each
  // trial offset was scattered by identify's delay basins
  // (reidentified_profile.h).
  bool scattered = false;
};

// The run's offset beside the pin scans'.
struct OffsetComparison {
  double pins_counts = NAN, pins_ci95_counts = NAN;
  double difference = NAN;  // run - pins
  bool run_pinned = false, agree = false;
  double combined_counts = NAN, combined_ci95_counts = NAN;  // inverse-variance, where they agree
};

struct RunExplanation {
  double aligned_at_counts = NAN;  // the offset the series is aligned at (the rig's given to the call)
  RunSeries series;
  ExplainReport report;
  OffsetFromRun offset;
  std::optional<CorrectedFlow> corrected;
};

// Throws bead::Error naming the file when a channel named is not recorded,
// or the held-out run does not record the same channels.
RunExplanation ExplainMeasuredRun(const Rig& rig, const MeasuredFlow& run, const MeasuredFlow* held_out,
                                  const model::TransferFunction& model, double model_offset,
                                  const RunExplainOptions& options);

// The profiles per sample explain's run mode uses for this run's flow
// (run_series.h, ExplainBin over its valid samples); the caller that
// identifies a base model on the run's flow bins it alike (AverageInBins).
std::size_t ExplainBinOf(const FlowResult& flow);

// Two independent estimates of one offset: combined by inverse variance
// where they agree within their intervals (|difference| <= 1.96 times the
// combined standard deviation), never where the run does not pin it.
OffsetComparison CompareOffsets(const OffsetFromRun& run, double pins_counts, double pins_ci95_counts);

// Keeps the channels named (all with an empty list, none with `none`).
void SelectChannels(std::vector<Channel>& channels, const std::vector<std::string>& names, bool none,
                    const std::string& path);

}  // namespace bead::explain
