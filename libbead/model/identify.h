// Identification of a continuous-time transfer function with n poles, m
// zeros, an input delay, an operating point and an initial state from
// sampled input/output data (even or uneven sampling, stretches where the
// process was off left out), by output error:
//
//   y(t) = offset + N(s) / A(s) u(t - delay) + (free response of the
//          initial state of each segment) + e(t)
//
// as MATLAB's tfest does with InitialCondition 'estimate' and procest with
// an offset: a record that starts mid-process is the normal case.
//  1. The delay profile: at every sample step of delay in [0, max_delay], a
//     linear fit by Young's state-variable filter (signals filtered by
//     lambda^(n+1) / (s + lambda)^(n+1), the equation
//     s^n y + a1 s^(n-1) y + ... = b0 s^m u + ... + c solved by least
//     squares), scored by its output error with the numerator, offset and
//     initial states re-solved (below). The loss against delay is kept.
//  2. The best few basins of that curve are refined by output error over
//     the denominator and the delay (Ceres), the numerator, offset and
//     initial states solved by linear least squares at every trial
//     (variable projection: Golub & Pereyra, SIAM J. Numer. Anal. 10, 1973).
//  3. Only stable models are accepted; the best refined basin wins, and
//     two basins whose losses the data cannot tell apart are reported.
// Structures: any transfer function (poles 1-7, zeros <= poles), or a
// process model with real poles (MATLAB procest P1D, P2D, P1DZ, P2DZ, ...):
// K (1 + Tz s) / ((1 + Tp1 s)(1 + Tp2 s)) e^(-Td s).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "libbead/model/fit_metrics.h"
#include "libbead/model/lti_response.h"
#include "libbead/model/predict.h"
#include "libbead/model/transfer_function.h"

namespace bead::model {

struct IdentifyOptions {
  // The default order of every identified model (bead identify's and
  // bead explain's): two poles and one zero, a proper model a controller
  // can be designed for without a derivative filter.
  int poles = 2;
  int zeros = 1;
  bool real_poles = false;        // a process model: poles real, reported as time constants
  std::optional<double> delay_s;  // fixed; none: estimated
  double max_delay_s = 1.0;
  bool estimate_offset = true;         // the operating point (a constant term)
  bool estimate_initial_state = true;  // else each segment starts from rest
  double filter_rad_s = 0.0;           // SVF lambda; 0: from the sampling (2 pi / (20 dt))
  int max_iterations = 50;
  int basins = 3;                // delay basins refined by output error
  int max_profile_points = 250;  // delay profile resolution: a sample step, or coarser above this
  // A warm start: the output-error search refines from this model's
  // denominator and delay alone (no delay profile, no basins), so that
  // data changed a little is fitted in the start's basin. Its orders must
  // be the options' (poles, zeros).
  std::optional<TransferFunction> start;
};

struct DelayBasin {
  double delay_s = 0.0;       // where the refinement ended
  double profile_loss = 0.0;  // the linear fit's loss at the basin's grid point
  double refined_loss = 0.0;  // output-error loss after refinement (inf: failed)
};

struct DelayProfile {
  std::vector<double> delay_s, loss;  // the linear fit's output-error loss (mean square) at each delay
  std::vector<DelayBasin> basins;     // refined, best first
  bool ambiguous = false;             // the second basin fits as well as the best, within the noise
  std::string note;                   // what to say about it, if anything
  // The chosen delay lies at the searched range's end (max_delay_s): the
  // best delay may lie beyond it, and the model's other terms bend to make
  // up for the cut. Said in `limit_note`.
  bool at_limit = false;
  std::string limit_note;
};

struct ProcessForm {  // K (1 + Tz s) / prod (1 + Tp_k s) e^(-Td s); NaN where not applicable
  double K = 0.0, Tz_s = 0.0, Td_s = 0.0;
  std::vector<double> Tp_s;
  bool valid = false;  // every pole real and negative, every zero real
};

struct IdentifiedModel {
  bool ok = false;
  std::string reason;
  TransferFunction tf;
  double offset = 0.0;                             // the constant term: y = offset + G(s) u
  double input_level = 0.0;                        // operating point: the mean input over the fitted samples ...
  double output_level = 0.0;                       // ... and the output the model holds there (offset + K input_level)
  std::vector<std::vector<double>> initial_state;  // per segment, canonical-form state at its first sample
  int parameters = 0;      // counted in the criteria: poles, zeros + 1, offset, delay, initial states
  double fit_percent = 0;  // on the fitted samples, as given (not deviations)
  std::size_t fitted_samples = 0;
  InformationCriteria criteria;
  std::vector<double> poles_real, poles_imag;
  ProcessForm process;
  DelayProfile delay_profile;
  std::vector<double> prediction;  // at every sample (NaN outside the segments)
};

// `segments` (default: the whole record) are the stretches fitted; the
// input record u is used whole as the input's history. With the initial
// state estimated, each stretch's first max_delay_s (or the fixed delay)
// is left out of the fit: the output there depends on input from before
// the stretch. Without it (from rest), the input before the record is 0.
IdentifiedModel IdentifyTransferFunction(const std::vector<double>& t, const std::vector<double>& u,
                                         const std::vector<double>& y, const IdentifyOptions& options,
                                         const std::vector<Segment>& segments = {});

// A structure by name: "tf" (any poles and zeros: left as they are) or a
// process model as MATLAB's procest names them, P1D, P1DZ, P2D, P2DZ, P3D,
// P3DZ (real poles). Throws bead::Error naming the choices.
void SetStructure(const std::string& name, IdentifyOptions& options);

// Thesis Table 3: poles 1-3, zeros 0-2 (zeros <= poles), estimated on one
// data set and validated on another; `progress` told before each order.
struct OrderRow {
  int poles, zeros;
  double fit_estimation, fit_validation, aicc, delay_s;
  bool ok;
};
std::vector<OrderRow> OrderTable(const std::vector<double>& t, const std::vector<double>& u,
                                 const std::vector<double>& y, const std::vector<double>& tv,
                                 const std::vector<double>& uv, const std::vector<double>& yv, IdentifyOptions options,
                                 const std::vector<Segment>& segments = {},
                                 const std::vector<Segment>& validation_segments = {},
                                 const std::function<void(int done, int total)>& progress = {});

}  // namespace bead::model
