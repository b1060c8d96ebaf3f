#include "libbead/profile/measure_block.h"

#include <algorithm>
#include <atomic>
#include <thread>

namespace bead {

std::vector<BeadGeometry> MeasureProfiles(std::size_t count, const std::function<ProfileView(std::size_t)>& view,
                                          const ReferenceArea& left, const ReferenceArea& right,
                                          const ProfileOptions& options, const BlockOptions& batch) {
  std::vector<BeadGeometry> out(count);
  unsigned threads = batch.threads ? batch.threads : std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(count / 256, 1)));
  std::atomic<std::size_t> done{0};
  auto work = [&](std::size_t begin, std::size_t end, bool reports) {
    ProfileProcessor processor(left, right, options, 0);
    for (std::size_t i = begin; i < end; ++i) {
      out[i] = processor.Process(view(i));
      if ((i - begin) % 4096 == 4095) {
        const std::size_t now = done.fetch_add(4096) + 4096;
        if (reports && batch.progress) batch.progress(now, count);
      }
    }
  };
  std::vector<std::thread> pool;
  const std::size_t chunk = (count + threads - 1) / std::max(threads, 1u);
  for (unsigned t = 1; t < threads; ++t) {
    const std::size_t begin = std::min(count, t * chunk), end = std::min(count, (t + 1) * chunk);
    pool.emplace_back(work, begin, end, false);
  }
  work(0, std::min(count, chunk), true);
  for (auto& th : pool) th.join();
  if (batch.progress) batch.progress(count, count);
  return out;
}

}  // namespace bead
