#include "libbead/archive/streamed_flow.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <optional>

#include <unistd.h>

#include "libbead/core/error.h"
#include "libbead/core/median_by_walks.h"
#include "libbead/flow/streaming_flow.h"
#include "libbead/io/log_stream.h"
#include "libbead/series/encoder.h"

namespace bead {
namespace {

// What the flow needs of a profile, as spilled between the passes.
struct FlowRow {
  double t_s;
  int64_t encoder;
  ProfileStatus status;
  double area_mm2, area_sigma_mm2, corrected_mm2, corrected_sigma_mm2;
};

// A scratch file of FlowRows in $TMPDIR (else /tmp), unlinked as soon as
// it is made: gone however the process ends.
class Spill {
 public:
  explicit Spill(const std::string& path) : file_(nullptr, &std::fclose), path_(path) {
    const char* env = std::getenv("TMPDIR");
    std::string name = std::string(env && *env ? env : "/tmp") + "/bead-flow-rows-XXXXXX";
    const int fd = mkstemp(name.data());
    if (fd >= 0) {
      unlink(name.c_str());
      file_.reset(fdopen(fd, "w+b"));
      if (!file_) close(fd);
    }
    if (!file_)
      throw Error(Located(path, "",
                          "cannot make a scratch file for the flow's rows in " + name.substr(0, name.rfind('/')) +
                              " (set TMPDIR to a writable folder)"));
  }
  void Append(const FlowRow& r) {
    if (std::fwrite(&r, sizeof r, 1, file_.get()) != 1)
      throw Error(Located(path_, "", "cannot write the flow's scratch file (is the temporary folder full?)"));
    ++count_;
  }
  // visit(row) for every row, in order.
  template <class F>
  void Walk(F&& visit) {
    std::fflush(file_.get());
    std::rewind(file_.get());
    std::vector<FlowRow> block(4096);
    for (std::size_t done = 0; done < count_;) {
      const std::size_t want = std::min(block.size(), count_ - done);
      if (std::fread(block.data(), sizeof(FlowRow), want, file_.get()) != want)
        throw Error(Located(path_, "", "cannot read the flow's scratch file back"));
      for (std::size_t i = 0; i < want; ++i) visit(block[i]);
      done += want;
    }
  }

 private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  std::string path_;
  std::size_t count_ = 0;
};

// The whole log's facts the batch uses (flow.cc, encoder.cc): the median
// step, and the glitch threshold from the median distance of each
// unwrapped position from the line through its neighbours.
struct LogPass {
  WholeLogFacts facts{};
  double first_s = 0.0, last_s = 0.0;
};

LogPass WalkLog(LogStream& log, const Rig& rig) {
  LogPass pass;
  LogWindow w;
  // Sequence 0: the steps; 1: the encoder's distances from its neighbours' line.
  const std::vector<double> medians = MediansByWalks(2, [&](const std::function<void(int, double)>& visit) {
    log.Rewind();
    EncoderUnwrapper unwrap(rig.encoder);
    double t0 = 0, t1 = 0, c0 = 0, c1 = 0;  // the two samples before this one
    std::size_t k = 0;
    while (log.Next(w, /*with_rpm=*/false))
      for (std::size_t i = 0; i < w.size(); ++i, ++k) {
        const double t2 = w.t_s[i], c2 = unwrap.Push(w.encoder[i]);
        if (k == 0) pass.first_s = t2;
        if (k >= 1) visit(0, t2 - t1);
        if (k >= 2) {
          const double f = (t1 - t0) / (t2 - t0);
          visit(1, std::abs(c1 - (c0 + f * (c2 - c0))));
        }
        pass.last_s = t2;
        t0 = t1, c0 = c1, t1 = t2, c1 = c2;
      }
  });
  pass.facts.step_s = medians[0];
  const double sigma = 1.4826 * medians[1];  // as encoder.cc, to the rounding
  pass.facts.glitch_counts = std::max(EncoderOptions{}.min_glitch_counts, 8.0 * sigma);
  return pass;
}

// AreaSigmaFloor's: the median of the valid profiles' sigmas, 0 without any.
double AreaSigmaFloorOf(Spill& spill) {
  const double floor = MedianByWalks([&](const std::function<void(double)>& visit) {
    spill.Walk([&](const FlowRow& r) {
      if (r.status == ProfileStatus::kValid && std::isfinite(r.area_sigma_mm2)) visit(r.area_sigma_mm2);
    });
  });
  return std::isnan(floor) ? 0.0 : floor;
}

// The spilled rows and the log, interleaved in time, through the flow;
// each sample handed on as it is done, counted and integrated into `out`.
// What the flow's warnings need of the run comes back.
FlowRunFacts Interleave(LogStream& log, Spill& spill, const LogPass& lp, StreamingFlow& flow,
                        const std::function<void(const FlowSample&)>& sample, StreamedFlow& out) {
  FlowRunFacts facts;
  facts.log_first_s = lp.first_s, facts.log_last_s = lp.last_s;
  bool have_last = false;
  FlowSample last;
  auto drain = [&]() {
    for (FlowSample s; flow.Pop(s);) {
      ++out.samples;
      if (s.valid) {
        ++out.valid;
        if (have_last && s.t_s > last.t_s)
          out.total_volume_mm3 += 0.5 * (s.flow_mm3_s + last.flow_mm3_s) * (s.t_s - last.t_s);
        last = s, have_last = true;
      }
      sample(s);
    }
  };
  log.Rewind();
  LogWindow w;
  std::size_t li = 0;
  bool more = log.Next(w);
  auto push_log_until = [&](double t) {
    while (more && w.t_s[li] <= t) {
      flow.PushLog(w.t_s[li], w.encoder[li], w.screw_rpm[li]);
      if (++li == w.size()) li = 0, more = log.Next(w);
    }
  };
  spill.Walk([&](const FlowRow& r) {
    push_log_until(r.t_s);
    BeadGeometry g;
    g.status = r.status, g.area_mm2 = r.area_mm2, g.area_sigma_mm2 = r.area_sigma_mm2;
    flow.PushProfile(r.t_s, r.encoder, g, r.corrected_mm2, r.corrected_sigma_mm2);
    if (facts.profiles == 0) facts.profile_first_s = r.t_s;
    facts.profile_last_s = r.t_s;
    ++facts.profiles;
    facts.outside += !(r.t_s >= lp.first_s && r.t_s <= lp.last_s);
    facts.beads += r.status == ProfileStatus::kValid;
    drain();
  });
  push_log_until(std::numeric_limits<double>::infinity());
  flow.Finish();
  drain();
  return facts;
}

}  // namespace

MotionGap MissingMotionUnread(const OpenedRun& opened, const std::string& path, const std::string& needs) {
  const std::unique_ptr<LogStream> log = opened.archive ? LogStream::OpenIfPresent(path) : nullptr;
  return MissingMotion(EncoderAbsent(opened.run), log ? std::optional<std::size_t>(log->size()) : std::nullopt, needs);
}

StreamedFlow StreamRunFlow(OpenedRun opened, const std::string& path, const Rig& rig, WorkerPool& pool,
                           const MeasureRunOptions& measure, const FlowOptions& options,
                           const std::function<void(const FlowSample&)>& sample,
                           const std::function<void(const GeometryRow&)>& row, double history_s) {
  if (!StreamableFlow(options))
    throw Error("the flow's area smoothing needs the whole run: it is not streamed (area_smooth_window " +
                std::to_string(options.area_smooth_window) + ")");
  const MotionGap gap = MissingMotionUnread(opened, path, "the flow");
  if (!gap.none()) throw Error(Located(path, gap.dataset, gap.why));
  const auto log = std::make_unique<LogStream>(path);

  StreamedFlow out;
  const LogPass lp = WalkLog(*log, rig);
  // A log shorter than the speed's window: the batch narrows the window to it.
  const int window = SpeedWindowSamples(options, lp.facts.step_s);
  if (log->size() < static_cast<std::size_t>(window)) {
    out.complete = false;
    out.why = "the log's " + std::to_string(log->size()) + " samples are fewer than the speed window's " +
              std::to_string(window) + ": the window is narrowed to the whole log";
    return out;
  }

  Spill spill(path);
  out.measure = MeasureRun(*opened.profiles, rig, pool, measure, [&](const GeometryRow& r) {
    spill.Append({r.t_s, r.encoder, r.geometry.status, r.geometry.area_mm2, r.geometry.area_sigma_mm2,
                  r.area_corrected_mm2, r.area_corrected_sigma_mm2});
    if (row) row(r);
  });

  FlowOptions o = options;
  if (o.area_sigma_floor_mm2 < 0) o.area_sigma_floor_mm2 = AreaSigmaFloorOf(spill);
  StreamingFlow flow(rig, o, lp.facts, history_s);
  FlowRunFacts facts = Interleave(*log, spill, lp, flow, sample, out);
  out.complete = flow.history_misses() == 0;
  if (!out.complete) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "%zu profile(s) were extruded more than %.0f s before they were measured (the wheel stood "
                  "still?): older than the log the stream keeps",
                  flow.history_misses(), history_s);
    out.why = line;
  }
  out.area_outliers = flow.area_outliers();
  out.speed_outliers = flow.speed_outliers();
  out.encoder_repairs = flow.encoder_repairs();
  facts.valid = out.valid;
  facts.counts_min = flow.counts_min(), facts.counts_max = flow.counts_max();
  out.warnings = FlowWarnings(facts);
  return out;
}

}  // namespace bead
