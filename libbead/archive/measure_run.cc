#include "libbead/archive/measure_run.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "libbead/core/error.h"

namespace bead {
namespace {

// Rows waiting for the run's pooled occlusion: an unnamed temporary file.
class RowSpill {
 public:
  explicit RowSpill(const std::string& run) : run_(run), file_(std::tmpfile(), &std::fclose) {
    if (!file_) throw Error(Located(run, "", "cannot create a scratch file (is the temporary folder full?)"));
  }
  void Write(const std::vector<GeometryRow>& rows) {
    if (std::fwrite(rows.data(), sizeof(GeometryRow), rows.size(), file_.get()) != rows.size())
      throw Error(Located(run_, "", "cannot write the scratch file (is the temporary folder full?)"));
  }
  // Rows [begin, begin + count) into `rows`.
  void Read(std::size_t begin, std::size_t count, std::vector<GeometryRow>& rows) {
    rows.resize(count);
    if (std::fseek(file_.get(), static_cast<long>(begin * sizeof(GeometryRow)), SEEK_SET) != 0 ||
        std::fread(rows.data(), sizeof(GeometryRow), count, file_.get()) != count)
      throw Error(Located(run_, "", "cannot read back the scratch file"));
  }

 private:
  std::string run_;
  std::unique_ptr<FILE, int (*)(FILE*)> file_;
};

}  // namespace

OcclusionMode ParseOcclusionMode(const std::string& text) {
  if (text == "none") return OcclusionMode::kNone;
  if (text == "pooled") return OcclusionMode::kPooled;
  if (text == "each") return OcclusionMode::kEach;
  throw Error("occlusion mode '" + text + "' is none of none, pooled, each");
}

namespace {

// One pass over the run window by window, every profile measured on every
// core (and, in mode each, its occlusion fitted); the rows to `spill`, the
// counts to `summary`, each profile's validity to `valid`.
void MeasurePass(ProfileStream& stream, const Rig& rig, WorkerPool& pool, const MeasureRunOptions& options,
                 const occlusion::OcclusionOptions& occ, RowSpill& spill, std::vector<bool>& valid,
                 MeasureRunSummary& summary) {
  const std::size_t n = stream.size();
  std::vector<ProfileProcessor> processors;
  for (unsigned w = 0; w < pool.size(); ++w)
    processors.emplace_back(rig.reference_left, rig.reference_right, options.profile, stream.points());
  std::vector<int> fitted(pool.size(), 0), constrained(pool.size(), 0);
  ProfileBlock block;
  std::vector<GeometryRow> rows;
  const std::size_t window = stream.WindowRows(options.window_rows);
  constexpr std::size_t kTask = 256;  // profiles per work item
  for (std::size_t begin = 0; begin < n; begin += window) {
    const std::size_t count = std::min(window, n - begin);
    stream.Read(begin, count, block);
    rows.resize(count);
    pool.Run((count + kTask - 1) / kTask, [&](std::size_t task, unsigned worker) {
      const std::size_t end = std::min(count, (task + 1) * kTask);
      for (std::size_t i = task * kTask; i < end; ++i) {
        GeometryRow& r = rows[i];
        const ProfileView v = block.view(i);
        r = GeometryRow{};
        r.profile = static_cast<int64_t>(begin + i);
        r.t_s = v.t_s;
        r.encoder = v.encoder;
        r.geometry = processors[worker].Process(v);
        if (options.occlusion != OcclusionMode::kEach || !r.geometry.valid()) continue;
        const occlusion::OcclusionEstimate e = options.estimate(v, r.geometry, occ);
        if (!e.ok) continue;
        r.area_corrected_mm2 = e.corrected_area_mm2;
        r.occlusion_bias_mm2 = e.bias_mm2;
        r.area_corrected_sigma_mm2 = e.sigma_mm2;
        ++fitted[worker];
        constrained[worker] += e.constrained;
      }
    });
    for (std::size_t i = 0; i < count; ++i) {
      const BeadGeometry& g = rows[i].geometry;
      valid[begin + i] = g.valid();
      summary.valid += g.valid();
      ++summary.by_status[static_cast<std::size_t>(g.status)];
    }
    spill.Write(rows);
    if (options.progress) options.progress(begin + count, n);
  }
  for (unsigned w = 0; w < pool.size(); ++w) {
    summary.each_fitted += fitted[w];
    summary.each_constrained += constrained[w];
  }
}

// The pooled occlusion shape: the chosen valid profiles read again by index
// (together: each chunk decompressed once) and fitted on every core.
occlusion::PooledOcclusion PooledShape(ProfileStream& stream, WorkerPool& pool, const MeasureRunOptions& options,
                                       const occlusion::OcclusionOptions& occ, RowSpill& spill,
                                       const std::vector<bool>& valid, std::size_t valid_count) {
  std::vector<std::size_t> chosen = occlusion::PoolRanks(valid_count);
  std::size_t rank = 0, next = 0;
  for (std::size_t i = 0; i < valid.size() && next < chosen.size(); ++i)
    if (valid[i]) {
      while (next < chosen.size() && chosen[next] == rank) chosen[next++] = i;
      ++rank;
    }
  ProfileBlock profiles;
  stream.ReadRows(chosen, profiles);
  std::vector<BeadGeometry> geometry(chosen.size());
  std::vector<GeometryRow> one;
  for (std::size_t j = 0; j < chosen.size(); ++j) {
    spill.Read(chosen[j], 1, one);
    geometry[j] = one[0].geometry;
  }
  std::vector<occlusion::OcclusionEstimate> fits(chosen.size());
  pool.Run(chosen.size(),
           [&](std::size_t j, unsigned) { fits[j] = options.estimate(profiles.view(j), geometry[j], occ); });
  return occlusion::PoolFromFits(fits, geometry);
}

}  // namespace

MeasureRunSummary MeasureRun(ProfileStream& stream, const Rig& rig, WorkerPool& pool, const MeasureRunOptions& options,
                             const std::function<void(const GeometryRow&)>& sink) {
  if (options.occlusion != OcclusionMode::kNone && options.estimate == nullptr)
    throw Error(
        "MeasureRun: an occlusion mode other than none needs MeasureRunOptions::estimate "
        "(occlusion::EstimateOcclusion from bead::occlusion)");
  const auto start = std::chrono::steady_clock::now();
  MeasureRunSummary summary;
  summary.occlusion = options.occlusion;
  const std::size_t n = stream.size();
  summary.profiles = n;
  occlusion::OcclusionOptions occ;
  occ.laser_origin = rig.laser_origin;
  RowSpill spill(stream.name());
  std::vector<bool> valid(n);
  MeasurePass(stream, rig, pool, options, occ, spill, valid, summary);
  if (options.occlusion == OcclusionMode::kPooled)
    summary.pooled = PooledShape(stream, pool, options, occ, spill, valid, summary.valid);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The rows handed on in order, the pooled correction applied.
  const std::size_t window = stream.WindowRows(options.window_rows);
  std::vector<GeometryRow> rows;
  for (std::size_t begin = 0; begin < n; begin += window) {
    spill.Read(begin, std::min(window, n - begin), rows);
    for (GeometryRow& r : rows) {
      if (options.occlusion == OcclusionMode::kPooled) {
        const occlusion::CorrectedArea c = occlusion::ApplyPooled(summary.pooled, r.geometry);
        r.area_corrected_mm2 = c.area_mm2;
        r.occlusion_bias_mm2 = c.bias_mm2;
        r.area_corrected_sigma_mm2 = c.sigma_mm2;
      }
      sink(r);
    }
  }
  return summary;
}

std::string OcclusionLine(const MeasureRunSummary& s) {
  char line[512];
  switch (s.occlusion) {
    case OcclusionMode::kNone:
      return "";
    case OcclusionMode::kEach:
      std::snprintf(line, sizeof line,
                    "occlusion (a fit per profile): %d profiles corrected, %d with a hidden part the data constrains",
                    s.each_fitted, s.each_constrained);
      return line;
    case OcclusionMode::kPooled:
      if (!s.pooled.ok) return "occlusion: " + s.pooled.note + "; no correction";
      std::snprintf(line, sizeof line,
                    "occlusion (pooled over %d profiles, mostly %s): hidden area %.2f %% +- %.2f %% of the measured "
                    "area%s",
                    s.pooled.fitted, s.pooled.family.c_str(), 100 * s.pooled.bias_fraction,
                    100 * s.pooled.fraction_sigma,
                    s.pooled.constrained ? "" : " -- NOT constrained by the data: read it as a range, not a value");
      return line;
  }
  return "";
}

}  // namespace bead
