// The C interface of include/bead/bead.h over ProfileProcessor and
// StreamingFlow. Every entry point catches what the C++ below may throw
// and turns it into -1 / NULL and a thread-local message.
#include "bead/bead.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <span>

#include "libbead/flow/streaming_flow.h"
#include "libbead/profile/profile_processor.h"

struct bead_processor {
  bead::ProfileProcessor processor;
};

struct bead_flow {
  bead::StreamingFlow flow;
};

namespace {

static_assert(BEAD_VALID == int(bead::ProfileStatus::kValid) &&
              BEAD_TOO_FEW_POINTS == int(bead::ProfileStatus::kTooFewPoints) &&
              BEAD_NO_REFERENCE == int(bead::ProfileStatus::kNoReference) &&
              BEAD_NO_BEAD == int(bead::ProfileStatus::kNoBead) &&
              BEAD_EDGE_NOT_SEEN == int(bead::ProfileStatus::kBeadEdgeNotSeen) &&
              BEAD_IN_REFERENCE_AREA == int(bead::ProfileStatus::kBeadInReferenceArea));

thread_local char g_error[512] = "";

void SetError(const char* where, const char* what) { std::snprintf(g_error, sizeof g_error, "%s: %s", where, what); }

// Runs `body`, turning exceptions into `fail` and a message.
template <class F, class R>
R Guard(const char* where, R fail, F body) noexcept {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    SetError(where, "out of memory");
  } catch (const std::exception& e) {
    SetError(where, e.what());
  } catch (...) {
    SetError(where, "unknown error");
  }
  return fail;
}

// Copies the fields of a versioned struct an older caller's size covers
// over the defaults (a newer caller's extra fields are not read).
template <class T>
bool ReadVersioned(const T* in, T& out, const char* where) {
  if (in == nullptr) return true;
  const std::size_t given = in->size;
  if (given < sizeof(std::size_t) || given > (std::size_t{1} << 20)) {
    SetError(where, "the struct's size field is not set: fill it with its _init function first");
    return false;
  }
  std::memcpy(static_cast<void*>(&out), in, std::min(given, sizeof(T)));
  out.size = sizeof(T);
  return true;
}

bool AreaOk(const double a[2], const char* name, const char* where) {
  if (a == nullptr || !std::isfinite(a[0]) || !std::isfinite(a[1]) || !(a[1] > a[0])) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s must be two finite x, the second larger ([x_min, x_max] mm)", name);
    SetError(where, buf);
    return false;
  }
  return true;
}

void ToC(const bead::BeadGeometry& g, bead_geometry* out) {
  out->area_mm2 = g.area_mm2;
  out->area_sigma_mm2 = g.area_sigma_mm2;
  out->width_mm = g.width_mm;
  out->height_mm = g.height_mm;
  out->center_x_mm = g.center_x_mm;
  out->left_edge_x_mm = g.left_edge_x_mm;
  out->right_edge_x_mm = g.right_edge_x_mm;
  out->threshold_mm = g.threshold_mm;
  out->reference_rms_mm = g.reference.residual_rms_mm;
  out->reference_points = g.reference.points_used;
  out->bead_points = g.bead_points;
  out->dropped_points = g.dropped_points;
  out->valid = g.valid() ? 1 : 0;
  out->status = static_cast<int32_t>(g.status);
}

}  // namespace

extern "C" {

void bead_options_init(bead_options* o) {
  if (o == nullptr) return;
  const bead::ProfileOptions d;
  *o = bead_options{};
  o->size = sizeof(bead_options);
  o->threshold_mm = d.bead.min_threshold_mm;
  o->threshold_sigmas = d.bead.threshold_sigmas;
  o->spike_mm = d.bead.spike_mm;
  o->max_gap_mm = d.bead.max_gap_mm;
  o->edge_floor_mm = d.bead.min_edge_floor_mm;
  o->edge_floor_sigmas = d.bead.edge_floor_sigmas;
  o->min_bead_points = d.bead.min_bead_points;
  o->min_profile_points = d.bead.min_profile_points;
  o->inlier_sigmas = d.reference.inlier_sigmas;
  o->max_points = 2048;
}

bead_processor* bead_processor_create(const double left_mm[2], const double right_mm[2]) {
  return bead_processor_create_with(left_mm, right_mm, nullptr);
}

bead_processor* bead_processor_create_with(const double left_mm[2], const double right_mm[2],
                                           const bead_options* options) {
  const char* where = "bead_processor_create";
  return Guard(where, static_cast<bead_processor*>(nullptr), [&]() -> bead_processor* {
    bead_options o;
    bead_options_init(&o);
    if (!ReadVersioned(options, o, where) || !AreaOk(left_mm, "left_mm", where) || !AreaOk(right_mm, "right_mm", where))
      return nullptr;
    if (!(left_mm[1] < right_mm[0])) {
      SetError(where, "the left area must end before the right one begins: the bead lies between them");
      return nullptr;
    }
    if (!(o.threshold_mm > 0) || !(o.threshold_sigmas >= 0) || !(o.spike_mm > 0) || !(o.max_gap_mm >= 0) ||
        !(o.inlier_sigmas > 0) || o.max_points > (std::size_t{1} << 24)) {
      SetError(where, "an option is out of range (thresholds and spike size > 0, gap >= 0, max_points <= 2^24)");
      return nullptr;
    }
    bead::ProfileOptions po;
    po.bead.min_threshold_mm = o.threshold_mm;
    po.bead.threshold_sigmas = o.threshold_sigmas;
    po.bead.spike_mm = o.spike_mm;
    po.bead.max_gap_mm = o.max_gap_mm;
    po.bead.min_edge_floor_mm = o.edge_floor_mm;
    po.bead.edge_floor_sigmas = o.edge_floor_sigmas;
    po.bead.min_bead_points = o.min_bead_points;
    po.bead.min_profile_points = o.min_profile_points;
    po.reference.inlier_sigmas = o.inlier_sigmas;
    return new bead_processor{
        bead::ProfileProcessor({left_mm[0], left_mm[1]}, {right_mm[0], right_mm[1]}, po, o.max_points)};
  });
}

int bead_processor_measure(bead_processor* p, const float* x_mm, const float* z_mm, size_t n, bead_geometry* out) {
  const char* where = "bead_processor_measure";
  return Guard(where, -1, [&]() {
    if (p == nullptr || out == nullptr || (n > 0 && (x_mm == nullptr || z_mm == nullptr))) {
      SetError(where, "a NULL processor, output or point array");
      return -1;
    }
    bead::ProfileView view;
    view.x_mm = std::span<const float>(x_mm, n);
    view.z_mm = std::span<const float>(z_mm, n);
    ToC(p->processor.Process(view), out);
    return 0;
  });
}

void bead_processor_destroy(bead_processor* p) { delete p; }

void bead_rig_init(bead_rig* r) {
  if (r == nullptr) return;
  *r = bead_rig{};
  r->size = sizeof(bead_rig);
  r->encoder_bits = 32;
  r->encoder_direction = 1;
}

void bead_flow_options_init(bead_flow_options* o) {
  if (o == nullptr) return;
  const bead::FlowOptions d;
  *o = bead_flow_options{};
  o->size = sizeof(bead_flow_options);
  o->speed_window_s = d.speed_window_s;
  o->speed_hampel_s = d.speed_hampel_s;
  o->area_hampel_half = d.area_hampel_half;
  o->hampel_nsigma = d.hampel_nsigma;
  o->area_sigma_floor_mm2 = d.area_sigma_floor_mm2;
  o->history_s = 600.0;
}

bead_flow* bead_flow_create(const bead_rig* rig, const bead_flow_options* options, double log_rate_hz) {
  const char* where = "bead_flow_create";
  return Guard(where, static_cast<bead_flow*>(nullptr), [&]() -> bead_flow* {
    bead_rig r;
    bead_rig_init(&r);
    bead_flow_options o;
    bead_flow_options_init(&o);
    if (rig == nullptr) {
      SetError(where, "a NULL rig: fill a bead_rig with bead_rig_init, then its counts and diameter");
      return nullptr;
    }
    if (!ReadVersioned(rig, r, where) || !ReadVersioned(options, o, where)) return nullptr;
    if (!(log_rate_hz > 0) || !std::isfinite(log_rate_hz) || !(o.speed_window_s > 0) || !(o.speed_hampel_s > 0) ||
        o.area_hampel_half < 1 || !(o.hampel_nsigma > 0) || !(o.history_s > 0)) {
      SetError(where, "log_rate_hz, the windows, hampel_nsigma and history_s must be > 0, area_hampel_half >= 1");
      return nullptr;
    }
    bead::Rig cr;
    cr.encoder.counts_per_rev = r.counts_per_rev;
    cr.encoder.bits = r.encoder_bits;
    cr.encoder.direction = r.encoder_direction;
    cr.wheel_diameter_mm = r.wheel_diameter_mm;
    cr.offset_counts = r.offset_counts;
    cr.wheel_eccentricity_mm = r.wheel_eccentricity_mm;
    cr.wheel_eccentricity_phase_deg = r.wheel_eccentricity_phase_deg;
    if (std::string key, error; !bead::IsValid(cr, false, &key, &error)) {  // the rig file's rules (core/rig.h)
      SetError(where, ("rig: " + key + " " + error).c_str());
      return nullptr;
    }
    bead::FlowOptions fo;
    fo.speed_window_s = o.speed_window_s;
    fo.speed_hampel_s = o.speed_hampel_s;
    fo.area_hampel_half = o.area_hampel_half;
    fo.hampel_nsigma = o.hampel_nsigma;
    fo.area_sigma_floor_mm2 = o.area_sigma_floor_mm2;
    return new bead_flow{bead::StreamingFlow(cr, fo, log_rate_hz, o.history_s)};
  });
}

int bead_flow_push_log(bead_flow* f, double t_s, int64_t raw_encoder, double screw_rpm) {
  const char* where = "bead_flow_push_log";
  return Guard(where, -1, [&]() {
    if (f == nullptr || !std::isfinite(t_s)) {
      SetError(where, f == nullptr ? "a NULL flow" : "the time must be finite");
      return -1;
    }
    f->flow.PushLog(t_s, raw_encoder, screw_rpm);
    return 0;
  });
}

int bead_flow_push_profile(bead_flow* f, double t_s, int64_t raw_encoder, const bead_geometry* g) {
  const char* where = "bead_flow_push_profile";
  return Guard(where, -1, [&]() {
    if (f == nullptr || g == nullptr || !std::isfinite(t_s)) {
      SetError(where, f == nullptr || g == nullptr ? "a NULL flow or geometry" : "the time must be finite");
      return -1;
    }
    if (g->status < 0 || g->status > static_cast<int32_t>(bead::ProfileStatus::kBeadInReferenceArea)) {
      SetError(where, "the geometry's status is not one of enum bead_status");
      return -1;
    }
    bead::BeadGeometry bg;
    bg.status = static_cast<bead::ProfileStatus>(g->status);
    bg.area_mm2 = g->area_mm2;
    bg.area_sigma_mm2 = g->area_sigma_mm2;
    f->flow.PushProfile(t_s, raw_encoder, bg);
    return 0;
  });
}

int bead_flow_pop(bead_flow* f, bead_flow_sample* out) {
  const char* where = "bead_flow_pop";
  return Guard(where, -1, [&]() {
    if (f == nullptr || out == nullptr) {
      SetError(where, "a NULL flow or output");
      return -1;
    }
    bead::FlowSample s;
    if (!f->flow.Pop(s)) return 0;
    out->profile = s.profile;
    out->t_s = s.t_s;
    out->encoder = s.encoder;
    out->surface_speed_mm_s = s.surface_speed_mm_s;
    out->area_mm2 = s.area_mm2;
    out->flow_mm3_s = s.flow_mm3_s;
    out->screw_rpm = s.screw_rpm;
    out->valid = s.valid ? 1 : 0;
    return 1;
  });
}

int bead_flow_finish(bead_flow* f) {
  const char* where = "bead_flow_finish";
  return Guard(where, -1, [&]() {
    if (f == nullptr) {
      SetError(where, "a NULL flow");
      return -1;
    }
    f->flow.Finish();
    return 0;
  });
}

void bead_flow_destroy(bead_flow* f) { delete f; }

const char* bead_last_error(void) { return g_error; }

const char* bead_status_name(int32_t status) {
  if (status < 0 || status > static_cast<int32_t>(bead::ProfileStatus::kBeadInReferenceArea)) return "unknown";
  return bead::StatusName(static_cast<bead::ProfileStatus>(status));
}

const char* bead_version(void) { return BEAD_VERSION; }

}  // extern "C"
