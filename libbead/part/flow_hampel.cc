#include "libbead/part/flow_hampel.h"

#include <algorithm>
#include <cmath>

#include "libbead/core/median.h"
#include "libbead/series/hampel.h"

namespace bead::part {

void FlowHampel::EmitNext(const Emit& emit) {
  PartFlowRow row = rows_[next_];
  if (row.valid) {
    flows_.clear(), sigmas_.clear();
    for (const PartFlowRow& r : rows_) {
      flows_.push_back(r.valid ? r.flow_mm3_s : NAN);
      if (r.valid && std::isfinite(r.flow_sigma_mm3_s)) sigmas_.push_back(r.flow_sigma_mm3_s);
    }
    double floor = 0.0;
    if (!sigmas_.empty()) floor = MiddleInPlace(sigmas_);
    bool outlier = false;
    const double flow = HampelAt(flows_.data(), flows_.size(), next_, kHalfWindow, kSigmas, &outlier, scratch_, floor);
    if (outlier) row.flow_mm3_s = flow, row.flow_replaced = true, ++replaced_;
  }
  emit(row);
  ++next_;
  // Only kHalfWindow rows before the next one are in its window.
  if (next_ > static_cast<std::size_t>(kHalfWindow)) {
    const std::size_t drop = next_ - kHalfWindow;
    rows_.erase(rows_.begin(), rows_.begin() + static_cast<std::ptrdiff_t>(drop));
    next_ -= drop;
  }
}

void FlowHampel::Add(const PartFlowRow& row, const Emit& emit) {
  if (!rows_.empty() && rows_.back().layer != row.layer) Flush(emit);
  rows_.push_back(row);
  while (next_ + kHalfWindow < rows_.size()) EmitNext(emit);
}

void FlowHampel::Flush(const Emit& emit) {
  while (next_ < rows_.size()) EmitNext(emit);
  rows_.clear(), next_ = 0;
}

}  // namespace bead::part
