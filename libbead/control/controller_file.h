// The controller file of `bead tune -o` (docs/data-formats.md,
// "Controller file"): YAML with the gains, the method, the model they came
// from and the figures of the closed loop on that model.
#pragma once

#include <string>

#include "libbead/control/closed_loop.h"
#include "libbead/control/pid_tuning.h"
#include "libbead/model/transfer_function.h"

namespace bead::control {

// A design with its figures on the model.
struct Evaluated {
  Design design;
  Margins margins;
  StepFigures setpoint, load;
  double duration_s = 0;  // simulated
};

// The figures of `d` on `plant` (setpoint and load steps over a horizon of
// 40 / J, at most 200 times the model's own time scale).
Evaluated Evaluate(const model::TransferFunction& plant, const Design& d);

// Writes the file atomically; `model_source` names the model file.
void WriteControllerFile(const std::string& path, const Evaluated& e, const model::TransferFunction& plant,
                         const std::string& model_source);

}  // namespace bead::control
