// An input held in steps, as identification tests drive a process: every
// `hold` samples (sampled every dt_s from 0) a new level drawn uniformly
// from [lo, hi) with `rng`.
#pragma once

#include <random>
#include <vector>

namespace bead::test {

struct Steps {
  std::vector<double> t, u;
};

inline Steps RandomSteps(std::mt19937_64& rng, double lo, double hi, int samples, int hold, double dt_s) {
  std::uniform_real_distribution<double> level(lo, hi);
  Steps s;
  double v = 0.0;
  for (int i = 0; i < samples; ++i) {
    if (i % hold == 0) v = level(rng);
    s.t.push_back(dt_s * i);
    s.u.push_back(v);
  }
  return s;
}

}  // namespace bead::test
