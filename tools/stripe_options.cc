#include "tools/stripe_options.h"

#include "libbead/core/error.h"

namespace bead::tools {

void AddStripeFlags(CLI::App* cmd, StripeFlags& f) {
  const vision::StripeOptions d;
  f.axis_opt = cmd->add_option("--stripe-axis", f.axis,
                               "Direction the stripe runs in the image: rows (across: one point per column), "
                               "columns (down: one per row), auto (the one found on more lines)")
                   ->capture_default_str()
                   ->group("Stripe");
  f.method_opt =
      cmd->add_option("--stripe-method", f.method,
                      "Sub-pixel centre: cog (centre of gravity above the threshold), gaussian, "
                      "parabolic, steger (the smoothed profile's peak, a bright line by the Hessian; wide or "
                      "saturated stripes)")
          ->capture_default_str()
          ->group("Stripe");
  f.rule_opt = cmd->add_option("--peak-rule", f.rule,
                               "Several stripe-shaped peaks on a line (reflections): strongest, widest, first, "
                               "last, nearest (to the previous line's)")
                   ->capture_default_str()
                   ->group("Stripe");
  f.options = d;
  f.threshold_opt = cmd->add_option("--threshold", f.options.threshold,
                                    "Least peak value, grey levels (0: none); the cog method's cut when set")
                        ->capture_default_str()
                        ->check(CLI::NonNegativeNumber)
                        ->group("Stripe");
  f.min_peak_opt = cmd->add_option("--min-peak", f.options.min_peak,
                                   "Least height of the stripe above the darkest value on each side, grey levels")
                       ->capture_default_str()
                       ->check(CLI::PositiveNumber)
                       ->group("Stripe");
  f.min_width_opt =
      cmd->add_option("--min-width-px", f.options.min_width_px, "Narrowest stripe (full width at half height), px")
          ->capture_default_str()
          ->check(CLI::NonNegativeNumber)
          ->group("Stripe");
  f.max_width_opt = cmd->add_option("--max-width-px", f.options.max_width_px,
                                    "Widest stripe, px; also how far each side the background is looked for")
                        ->capture_default_str()
                        ->check(CLI::PositiveNumber)
                        ->group("Stripe");
  f.min_relative_opt = cmd->add_option("--min-relative", f.options.min_relative,
                                       "Least stripe height as a share of the frame's stripe (its 95th-percentile "
                                       "height over the lines; 0: no test)")
                           ->capture_default_str()
                           ->check(CLI::Range(0.0, 0.99))
                           ->group("Stripe");
}

vision::StripeOptions ApplyStripeFlags(const StripeFlags& f, vision::StripeOptions o) {
  auto given = [](const CLI::Option* opt) { return opt != nullptr && opt->count() > 0; };
  try {
    if (given(f.axis_opt)) o.axis = vision::ParseStripeAxis(f.axis);
    if (given(f.method_opt)) o.method = vision::ParseStripeMethod(f.method);
    if (given(f.rule_opt)) o.rule = vision::ParsePeakRule(f.rule);
  } catch (const Error& e) {
    throw Error(std::string("--stripe-axis/--stripe-method/--peak-rule: ") + e.what());
  }
  if (given(f.threshold_opt)) o.threshold = f.options.threshold;
  if (given(f.min_peak_opt)) o.min_peak = f.options.min_peak;
  if (given(f.min_width_opt)) o.min_width_px = f.options.min_width_px;
  if (given(f.max_width_opt)) o.max_width_px = f.options.max_width_px;
  if (given(f.min_relative_opt)) o.min_relative = f.options.min_relative;
  return o;
}

}  // namespace bead::tools
