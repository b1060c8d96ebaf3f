/* libbead's C interface: the per-profile bead geometry and the on-line
 * flow, for acquisition software in C, LabVIEW (Call Library Function
 * Node), Python (ctypes), C# (P/Invoke) and MATLAB (loadlibrary).
 *
 *   bead_processor* p = bead_processor_create(left_mm, right_mm);
 *   if (!p) { puts(bead_last_error()); ... }
 *   bead_geometry g;
 *   if (bead_processor_measure(p, x_mm, z_mm, n, &g) == 0 && g.valid) use(g.area_mm2);
 *   bead_processor_destroy(p);
 *
 * Conventions: functions returning int give 0 on success and -1 on an
 * error, whose message bead_last_error() then holds (per thread, until
 * that thread's next failing call); constructors give NULL on an error.
 * No C++ exception crosses this interface. Nothing is allocated per
 * profile or per flow sample once created (a profile longer than any
 * before it grows the processor's buffers once). Lengths are in mm, times
 * in s, areas in mm^2. A handle is used by one thread at a time; distinct
 * handles run on distinct threads freely.
 *
 * Structs that carry a `size` field are versioned: fill them with their
 * _init function (which sets size to sizeof the struct this header
 * declares), then change what you need; a later libbead reads only the
 * fields an older size covers.
 *
 * The definitions of area, width, height and the statuses are libbead's
 * (README.md, "Profile geometry, defined"). */
#ifndef BEAD_BEAD_H
#define BEAD_BEAD_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#define BEAD_API __declspec(dllexport)
#else
#define BEAD_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Why a profile has no geometry (status of bead_geometry). */
enum bead_status {
  BEAD_VALID = 0,
  BEAD_TOO_FEW_POINTS = 1,   /* fewer valid points than min_profile_points */
  BEAD_NO_REFERENCE = 2,     /* a reference area holds too few valid points */
  BEAD_NO_BEAD = 3,          /* nothing stands above the threshold */
  BEAD_EDGE_NOT_SEEN = 4,    /* the bead's foot runs into a long dropout or far into an area */
  BEAD_IN_REFERENCE_AREA = 5 /* the bead reaches into a reference area */
};

typedef struct bead_geometry {
  double area_mm2;       /* seen area between the reference line and the profile; NaN when not valid */
  double area_sigma_mm2; /* its standard uncertainty (edges, noise, the line's fit) */
  double width_mm;       /* between the two edges */
  double height_mm;      /* robust maximum height above the line */
  double center_x_mm;    /* x of the area centroid */
  double left_edge_x_mm, right_edge_x_mm;
  double threshold_mm;      /* detection threshold used */
  double reference_rms_mm;  /* residual RMS of the reference line */
  int32_t reference_points; /* points the reference line used */
  int32_t bead_points;      /* valid points above the threshold in the bead */
  int32_t dropped_points;   /* missing or spike points between the edges */
  int32_t valid;            /* 1 when status == BEAD_VALID */
  int32_t status;           /* enum bead_status */
} bead_geometry;

typedef struct bead_options {
  size_t size;                /* sizeof(bead_options): set by bead_options_init */
  double threshold_mm;        /* least height that counts as bead (0.05) ... */
  double threshold_sigmas;    /* ... or this many reference RMS when larger (6) */
  double spike_mm;            /* a point this far off its neighbours' median is a spike (0.5) */
  double max_gap_mm;          /* longest dropout bridged inside a bead (1) */
  double edge_floor_mm;       /* the feet end below the larger of this (0.001) ... */
  double edge_floor_sigmas;   /* ... and this many reference RMS (2) */
  int32_t min_bead_points;    /* fewest points above the threshold that make a bead (3) */
  int32_t min_profile_points; /* fewest valid points a profile needs (10) */
  double inlier_sigmas;       /* reference line: inlier band in robust sigmas (3.5) */
  size_t max_points;          /* buffers sized for profiles this long up front (2048) */
} bead_options;

BEAD_API void bead_options_init(bead_options* options);

typedef struct bead_processor bead_processor;

/* left_mm and right_mm: the reference areas [x_min, x_max] either side of
 * the bead (the rig file's sensor.reference_areas_mm). */
BEAD_API bead_processor* bead_processor_create(const double left_mm[2], const double right_mm[2]);
BEAD_API bead_processor* bead_processor_create_with(const double left_mm[2], const double right_mm[2],
                                                    const bead_options* options);
/* One profile: n points (x_mm[i], z_mm[i]), z up, NaN z a dropout; x in
 * any order. 0 when measured (a profile without a bead is measured too:
 * out->valid = 0 and out->status say why), -1 on bad arguments. */
BEAD_API int bead_processor_measure(bead_processor* processor, const float* x_mm, const float* z_mm, size_t n,
                                    bead_geometry* out);
BEAD_API void bead_processor_destroy(bead_processor* processor);

/* The wheel and its encoder (the rig file's keys). */
typedef struct bead_rig {
  size_t size;               /* sizeof(bead_rig): set by bead_rig_init */
  double counts_per_rev;     /* encoder counts per wheel revolution */
  int32_t encoder_bits;      /* counter width (wraps modulo 2^bits); 0: never wraps (32) */
  int32_t encoder_direction; /* +1: counts grow as the surface moves from nozzle to laser (1) */
  double wheel_diameter_mm;
  double offset_counts;         /* nozzle to laser, encoder counts */
  double wheel_eccentricity_mm; /* 0: a centred wheel */
  double wheel_eccentricity_phase_deg;
} bead_rig;

typedef struct bead_flow_options {
  size_t size;                 /* sizeof(bead_flow_options): set by bead_flow_options_init */
  double speed_window_s;       /* Savitzky-Golay window on the wheel speed (0.04) */
  double speed_hampel_s;       /* Hampel half window on the speed (0.05) */
  int32_t area_hampel_half;    /* Hampel half window on the area, profiles (5) */
  double hampel_nsigma;        /* (3) */
  double area_sigma_floor_mm2; /* floor on the area Hampel's sigma; < 0: the running median (-1) */
  double history_s;            /* log history kept: longer than the nozzle-to-laser travel (600) */
} bead_flow_options;

typedef struct bead_flow_sample {
  int64_t profile; /* index of the profile, in the order pushed */
  double t_s;      /* extrusion time; NaN: laid before the log began */
  int64_t encoder; /* raw counter at extrusion time */
  double surface_speed_mm_s;
  double area_mm2;   /* after the Hampel filter */
  double flow_mm3_s; /* surface speed x area */
  double screw_rpm;  /* at extrusion time */
  int32_t valid;
} bead_flow_sample;

BEAD_API void bead_rig_init(bead_rig* rig);
BEAD_API void bead_flow_options_init(bead_flow_options* options);

typedef struct bead_flow bead_flow;

/* log_rate_hz: the acquisition log's sampling rate (fixes the filters'
 * windows in samples). options may be NULL (defaults). */
BEAD_API bead_flow* bead_flow_create(const bead_rig* rig, const bead_flow_options* options, double log_rate_hz);
/* A log sample: time, raw encoder counter, screw RPM; in time order. */
BEAD_API int bead_flow_push_log(bead_flow* flow, double t_s, int64_t raw_encoder, double screw_rpm);
/* A profile's time, its raw encoder counter and its geometry. */
BEAD_API int bead_flow_push_profile(bead_flow* flow, double t_s, int64_t raw_encoder, const bead_geometry* geometry);
/* 1 and *out filled when a finished sample is ready (in profile order),
 * 0 when none is yet, -1 on bad arguments. */
BEAD_API int bead_flow_pop(bead_flow* flow, bead_flow_sample* out);
/* No more input: finish the last samples (windows truncated at the end,
 * the speed fitted to the log's last window, as `bead flow` does). */
BEAD_API int bead_flow_finish(bead_flow* flow);
BEAD_API void bead_flow_destroy(bead_flow* flow);

/* The message of this thread's last failed call ("" when none). */
BEAD_API const char* bead_last_error(void);
/* "valid", "too_few_points", ... (the geometry CSV's status column). */
BEAD_API const char* bead_status_name(int32_t status);
/* libbead's version, "MAJOR.MINOR.PATCH". */
BEAD_API const char* bead_version(void);

#ifdef __cplusplus
}
#endif

#endif /* BEAD_BEAD_H */
