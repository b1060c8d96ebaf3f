// Whether the wheel's speed changes apart from the flow. The run tells a
// position error (the encoder offset) from a time error and from the
// base model's own dynamics only through the wheel's speed changes: a
// position error dx moves each sample's extrusion time by dx / v(t). When
// v itself is a linear filter of the model's input (a wheel fed forward
// from the extruder's command), that time error is a function of the
// input's history, which a misfit of the base model's poles and zeros
// mimics: the least of the offset profile then sits where the model's
// misfit puts it (the twin's fed-forward wheel: 118 counts from the truth
// at +-80), and no interval from the run bounds it.
#pragma once

#include "libbead/explain/series_data.h"

namespace bead::explain {

// The share of the wheel speed's variance over the samples that a linear
// filter of the model's input explains: R^2 of the speed at the nozzle
// (the wheel part's angle differenced over about 50 ms) regressed on the
// input's filter basis (SeriesData::dynamics; the input itself without
// one) and a constant. NaN without a wheel, or when the speed does not
// vary.
double SpeedShareFromInput(const SeriesData& d);

}  // namespace bead::explain
