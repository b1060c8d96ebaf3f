// MeasureProfiles: the geometry of many profiles, split over threads, each
// thread with its own ProfileProcessor (the same code the streaming path
// runs, so batch and on-line results are identical).
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "libbead/profile/profile_processor.h"

namespace bead {

// (Named BatchOptions until archive/batch.h's BatchOptions came: two
// classes of one name in one namespace, their inline members free to be
// taken one for the other in a program linking both.)
struct BlockOptions {
  unsigned threads = 0;  // 0: all hardware threads
  // Called now and then with (profiles done, total), from one thread.
  std::function<void(std::size_t, std::size_t)> progress;
};

// `view(i)` returns profile i of `count`.
std::vector<BeadGeometry> MeasureProfiles(std::size_t count, const std::function<ProfileView(std::size_t)>& view,
                                          const ReferenceArea& left, const ReferenceArea& right,
                                          const ProfileOptions& options, const BlockOptions& batch = {});

}  // namespace bead
