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

// How far the wheel's speed changes let the run tell a position error from
// a time error, whatever delay the base model took. A position error dx
// moves the flow the run computes (Q = v A, A from the profile measured dx
// later) by dx (Q' - Q v'/v) / v at each sample, and a delay error dt
// moves the model's output by -Q' dt: the two differ only through the
// speed's own changes (v'/v, and 1/v's variation). Their correlation,
// with the model's output standing for Q and the gain and operating point
// projected out, is the offset-delay correlation a steady wheel allows
// (1 at a constant speed); it reads the wheel and the model's output only,
// so it does not depend on which of two delays that fit alike identify
// took (the joint fit's correlation does). NaN without a wheel.
double OffsetDelayCorrelationFromSpeed(const SeriesData& d);

}  // namespace bead::explain
