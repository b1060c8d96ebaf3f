// The stripe options of `bead frames` and `bead calibrate laser`
// (libbead/vision/stripe.h), one set of flags for both.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "libbead/vision/stripe.h"

namespace bead::tools {

struct StripeFlags {
  std::string axis = "auto", method = "gaussian", rule = "strongest";
  vision::StripeOptions options;
  // Which flags the user gave (a sensor file's stripe settings hold for
  // the rest).
  CLI::Option *axis_opt = nullptr, *method_opt = nullptr, *rule_opt = nullptr, *threshold_opt = nullptr,
              *min_peak_opt = nullptr, *min_width_opt = nullptr, *max_width_opt = nullptr, *min_relative_opt = nullptr;
};

void AddStripeFlags(CLI::App* cmd, StripeFlags& flags);

// The options the flags give, over `base` (the flags not given keep
// base's values). Throws bead::Error naming a bad flag.
vision::StripeOptions ApplyStripeFlags(const StripeFlags& flags, vision::StripeOptions base);

}  // namespace bead::tools
