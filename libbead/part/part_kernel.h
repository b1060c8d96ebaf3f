// A part profile's loops, built as the per-profile kernel is
// (profile/kernel.h): once for AVX2 with FMA in namespace bead::part::avx2,
// once for the x86-64 baseline in bead::part::baseline, the one this
// processor can run chosen once.
//  - The grid path's sums (part/grid_costs.h), over lattice indices
//    [begin, end) (inside every row): zn the new points (NaN where none)
//    over the surface below's rows (GridRows).
//  - The noise's second differences and the band its median is looked for
//    in (part/added_bead.cc).
//  - A profile's points moved into the bed frame (part/measure_part.cc).
//  - In doubles, four a register (part_kernel_doubles.cc): the hidden
//    groove's ellipse, its residuals' sums over the points under it
//    (part/hidden_groove.cc); the held top's sums over a bead's top
//    (part/silhouette_top.cc); the surface below at the points around a
//    bead (part/hidden_groove.cc).
#pragma once

#include <cstddef>

namespace bead::part {

// The surface below at the lattice's indices: one row, or two blended as
// SurfaceGrid blends them (the second weighed w; where one is not known,
// the other stands for both). Row r's value at index i lies a fraction
// t[r] of the way from z[r][i] to z[r][i + 1] (the pointers moved so),
// its variance (1 - t)^2 v[r][i] + t^2 v[r][i + 1].
struct GridRows {
  const float* z[2] = {};
  const float* v[2] = {};
  float t[2] = {};
  float w = 0.0f;
  int count = 1;
  // Every value's variance one point's (rows of measured points, none
  // resampled): truncated reads no v, each row's variance a constant of it.
  bool unit = false;
};

// What every point's term shares at one shift: one point's noise variance,
// the cap, and 1 / dx.
struct GridShared {
  float noise2, cap, inv_dx;
};

// The ellipse (centre x0, z0; semi-axes a across, b up) and the aspect b /
// a where it is held (NaN: b fitted).
struct EllipseAt {
  double x0, z0, a, b, aspect;
};

// Its residuals' sum of squares over the points, and the normal equations
// J^T J (upper triangle, row by row: 00 01 02 03 11 12 13 22 23 33) and
// J^T r of x0, z0, a, b (b's column 0 where the aspect is held).
struct EllipseSums {
  double rss = 0.0;
  double jtj[10] = {};
  double jtr[4] = {};
};

// The surface below as one or two rows on their own grids (SurfaceRow),
// moved by a shift: row r's value at x is linear between its values k and
// k + 1 around the index (x - shift - x0[r]) per_mm[r] (NaN off the row);
// two blended as SurfaceGrid blends them, the second weighed w (where one
// is not known, the other stands for both).
struct RowsAt {
  const float* z[2] = {};
  std::size_t size[2] = {};
  double x0[2] = {}, per_mm[2] = {};
  double shift = 0.0, w = 0.0;
  int count = 1;
};

// A superellipse's table as the held top reads it (part/superellipse.h
// SuperellipseTable): s at |u| = k reach / last_entry for k = 0 ..
// last_entry, linear between, |u| beyond reach read at it.
struct TopTable {
  const double* s;
  double reach;
  int last_entry;
};

// The held top's sums over its points (part/silhouette_top.cc): of z, z^2,
// s(u), s(u)^2 and z s(u), u = (x - x0) per_a.
struct TopSums5 {
  double z1 = 0.0, zz = 0.0, s1 = 0.0, s2 = 0.0, zs = 0.0;
};

// Three sums, named by the loop that fills them.
struct GridSums {
  double first = 0.0, second = 0.0, third = 0.0;
};

struct PartKernel {
  const char* name;
  // The truncated cost (first); over rows of unit variance (rows.unit)
  // without reading rows.v.
  GridSums (*truncated)(const float* zn, const GridRows& rows, std::ptrdiff_t begin, std::ptrdiff_t end,
                        const GridShared& c);
  // The truncated cost, its gradient and its Gauss-Newton curvature in s.
  GridSums (*local)(const float* zn, const GridRows& rows, std::ptrdiff_t begin, std::ptrdiff_t end,
                    const GridShared& c);
  // Where |gain| <= limit: the squared gains, the points, those where the
  // surface below rises more than `steep` over the grid step.
  GridSums (*agree)(const float* zn, const GridRows& rows, std::ptrdiff_t begin, std::ptrdiff_t end, float limit,
                    float steep);
  // The surface below at indices [begin, end) to out[begin, end).
  void (*below_at)(const GridRows& rows, std::ptrdiff_t begin, std::ptrdiff_t end, float* out);
  // out[i] = |z[i] - 2 z[i + 1] + z[i + 2]| for i < n - 2 (n >= 3), each
  // difference of neighbours taken first (exact in floats for heights
  // within a factor of two of each other).
  void (*second_differences)(const float* z, std::size_t n, float* out);
  // The values of v[0, n) in [lo, hi) to band (in v's order; band holds n
  // + 8), how many there are; `below`: how many are under lo.
  std::size_t (*band)(const float* v, std::size_t n, float lo, float hi, float* band, std::size_t& below);
  // The k-th smallest of v[0, n) (k < n; no NaN; v reordered): sorted in
  // registers up to 128 values, selected beyond.
  float (*kth)(float* v, std::size_t n, std::size_t k);
  // The ellipse's sums over points [lo, hi) of x, z (the new surface) and
  // old (the surface below there), as hidden_groove.cc defines them.
  EllipseSums (*ellipse)(const double* x, const double* z, const double* old, std::size_t lo, std::size_t hi,
                         const EllipseAt& e);
  // A profile's points moved into the bed frame: ox[i] = x[i] + frame_x,
  // oz[i] = z[i] + frame_z, each sum in doubles rounded once to a float
  // (the same in both builds); whether any moved value is NaN or infinite.
  bool (*to_bed)(const float* x, const float* z, std::size_t n, double frame_x, double frame_z, float* ox, float* oz);
  // The held top's sums over points [lo, hi) of x, z (every u within the
  // table's reach), four points a register.
  TopSums5 (*top)(const double* x, const double* z, std::size_t lo, std::size_t hi, double x0, double per_a,
                  const TopTable& table);
  // The surface below at x[0, n) to out (NaN where not known), four places
  // a register.
  void (*rows_at)(const double* x, std::size_t n, const RowsAt& rows, double* out);
  // Over points [0, n - 2) of x, z and the surface below there (under),
  // where |z - under| <= tau: those whose rise to the next point exceeds
  // steep times the step (first); of the rest, those whose rise exceeds run
  // times the step and again to the point after, the same way (second).
  GridSums (*flanks)(const float* x, const float* z, const float* under, std::size_t n, float tau, float steep,
                     float run);
  // local's sums over [begin, end) for rows whose values are measured
  // points (each one point's variance: rows.v not read), and there the
  // surface below to below[i] and the gain zn[i] - below[i], at least 0
  // (NaN where either is), to gain[i]: one pass.
  GridSums (*gains)(const float* zn, const GridRows& rows, std::ptrdiff_t begin, std::ptrdiff_t end,
                    const GridShared& c, float* below, float* gain);
  // The first k in [lo, hi) (lo >= 1, z holding hi + 1 values) where the
  // median of z[k - 1], z[k], z[k + 1] (core/median.h Median3, its order
  // for NaN) is greatest; lo where none is over -infinity.
  std::size_t (*crest)(const float* z, std::size_t lo, std::size_t hi);
};

// The build this processor runs.
const PartKernel& ActivePartKernel();
// The baseline build (always there), for tests to compare against.
const PartKernel& BaselinePartKernel();

#ifdef BEAD_KERNEL
namespace BEAD_KERNEL {
const PartKernel& PartKernelBuild();
}  // namespace BEAD_KERNEL
#endif

}  // namespace bead::part
