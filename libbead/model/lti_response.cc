#include "libbead/model/lti_response.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "libbead/core/error.h"

namespace bead::model {
namespace {

constexpr int kMax = 8;  // states + 1

// exp(A h) = E and integral_0^h exp(A s) ds B = G for the companion A and
// B = e_(N-1): the Taylor series of the scaled step (|A h| / 2^s <= 1/2,
// terms until they fall below 1e-17 of the sum), squared back s times
// (E(2h) = E E, G(2h) = E G + G). With B = e_(N-1), the term of G is the
// last column of the previous term of E, times h / k.
template <int N>
struct StepMatrices {
  std::array<double, N * N> E;  // row-major
  std::array<double, N> G;
};

template <int N>
StepMatrices<N> TaylorStep(const std::array<double, N * N>& A, double h) {
  double norm = 0;
  for (int c = 0; c < N; ++c) {
    double col = 0;
    for (int r = 0; r < N; ++r) col += std::abs(A[static_cast<std::size_t>(r * N + c)]);
    norm = std::max(norm, col);
  }
  norm = std::max(norm * h, h);  // the input column's own length
  int squarings = norm > 0.5 ? static_cast<int>(std::ceil(std::log2(norm / 0.5))) : 0;
  const double hs = std::ldexp(h, -squarings);
  std::array<double, N * N> Ah;
  for (std::size_t k = 0; k < Ah.size(); ++k) Ah[k] = A[k] * hs;
  StepMatrices<N> out;
  std::array<double, N * N> term{};
  for (int k = 0; k < N; ++k) term[static_cast<std::size_t>(k * N + k)] = 1.0;
  out.E = term;
  out.G.fill(0.0);
  for (int k = 1; k <= 20; ++k) {
    // G += (previous term) B h / k; term <- term A h / k.
    double largest = 0;
    for (int r = 0; r < N; ++r) {
      const double g = term[static_cast<std::size_t>(r * N + N - 1)] * hs / k;
      out.G[static_cast<std::size_t>(r)] += g;
      largest = std::max(largest, std::abs(g));
    }
    std::array<double, N * N> next{};
    for (int r = 0; r < N; ++r)
      for (int c = 0; c < N; ++c) {
        double acc = 0;
        for (int m = 0; m < N; ++m)
          acc += term[static_cast<std::size_t>(r * N + m)] * Ah[static_cast<std::size_t>(m * N + c)];
        next[static_cast<std::size_t>(r * N + c)] = acc / k;
      }
    term = next;
    for (std::size_t q = 0; q < term.size(); ++q) {
      out.E[q] += term[q];
      largest = std::max(largest, std::abs(term[q]));
    }
    if (largest < 1e-17) break;
  }
  for (int s = 0; s < squarings; ++s) {
    std::array<double, N * N> E2{};
    std::array<double, N> G2{};
    for (int r = 0; r < N; ++r) {
      double g = out.G[static_cast<std::size_t>(r)];
      for (int m = 0; m < N; ++m) g += out.E[static_cast<std::size_t>(r * N + m)] * out.G[static_cast<std::size_t>(m)];
      G2[static_cast<std::size_t>(r)] = g;
      for (int c = 0; c < N; ++c) {
        double acc = 0;
        for (int m = 0; m < N; ++m)
          acc += out.E[static_cast<std::size_t>(r * N + m)] * out.E[static_cast<std::size_t>(m * N + c)];
        E2[static_cast<std::size_t>(r * N + c)] = acc;
      }
    }
    out.E = E2;
    out.G = G2;
  }
  return out;
}

// A short step r (|A r| small): E = I + Ar (I + Ar/2 (I + Ar/3 (I + Ar/4))),
// G = r (I + Ar/2 (I + Ar/3 (I + Ar/4 (I + Ar/5)))) e_(N-1), by Horner;
// the first term left out is (A r)^5 / 120.
template <int N>
StepMatrices<N> ShortStep(const std::array<double, N * N>& A, double r) {
  std::array<double, N * N> Ar;
  for (std::size_t k = 0; k < Ar.size(); ++k) Ar[k] = A[k] * r;
  std::array<double, N * N> M{};  // Horner accumulator for E
  for (int i = 0; i < N; ++i) M[static_cast<std::size_t>(i * N + i)] = 1.0;
  for (int d = 4; d >= 1; --d) {
    std::array<double, N * N> next{};
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        double acc = 0;
        for (int m = 0; m < N; ++m)
          acc += Ar[static_cast<std::size_t>(i * N + m)] * M[static_cast<std::size_t>(m * N + j)];
        next[static_cast<std::size_t>(i * N + j)] = (i == j ? 1.0 : 0.0) + acc / d;
      }
    M = next;
  }
  std::array<double, N> w{};
  w[N - 1] = 1.0;
  for (int d = 5; d >= 2; --d) {
    std::array<double, N> next{};
    for (int i = 0; i < N; ++i) {
      double acc = 0;
      for (int m = 0; m < N; ++m) acc += Ar[static_cast<std::size_t>(i * N + m)] * w[static_cast<std::size_t>(m)];
      next[static_cast<std::size_t>(i)] = (i == N - 1 ? 1.0 : 0.0) + acc / d;
    }
    w = next;
  }
  StepMatrices<N> out;
  out.E = M;
  for (int i = 0; i < N; ++i) out.G[static_cast<std::size_t>(i)] = r * w[static_cast<std::size_t>(i)];
  return out;
}

// The two step lengths an evenly sampled record alternates between (a
// fractional delay splits each step in two), remembered to the picosecond.
// Any other step h is composed from a grid of q = mean step / 64 (computed
// when first used): h = k q + r with |r| <= q / 2, E(h) = E(k q) E(r),
// G(h) = G(k q) + E(k q) G(r), the short step by ShortStep where |A r| is
// below 1e-2 (its error then below 1e-12). Other steps are computed whole.
template <int N>
class StepCache {
 public:
  StepCache(const std::array<double, N * N>& A, double mean_step) : A_(A), q_(mean_step / 64) {
    double norm = 0;  // the largest column sum of |A|
    for (int c = 0; c < N; ++c) {
      double col = 0;
      for (int r = 0; r < N; ++r) col += std::abs(A[static_cast<std::size_t>(r * N + c)]);
      norm = std::max(norm, col);
    }
    short_ok_ = norm * q_ / 2 < 1e-2;
  }
  const StepMatrices<N>& Get(double h) {
    const auto key = static_cast<int64_t>(std::llround(h * 1e12));
    for (int k = 0; k < 2; ++k)
      if (used_[k] && keys_[k] == key) return steps_[k];
    const int slot = next_++ & 1;
    keys_[slot] = key;
    used_[slot] = true;
    steps_[slot] = Compose(h);
    return steps_[slot];
  }

 private:
  StepMatrices<N> Compose(double h) {
    const double k_real = q_ > 0 ? std::round(h / q_) : 0.0;
    if (!(q_ > 0) || !short_ok_ || k_real > 64 * 6 || k_real < 1) return TaylorStep<N>(A_, h);
    const auto k = static_cast<std::size_t>(k_real);
    if (grid_.size() <= k) grid_.resize(k + 1), done_.resize(k + 1, false);
    if (!done_[k]) grid_[k] = TaylorStep<N>(A_, static_cast<double>(k) * q_), done_[k] = true;
    const StepMatrices<N>& g = grid_[k];
    const StepMatrices<N> r = ShortStep<N>(A_, h - static_cast<double>(k) * q_);
    StepMatrices<N> out;
    for (int a = 0; a < N; ++a) {
      double gsum = g.G[static_cast<std::size_t>(a)];
      for (int m = 0; m < N; ++m) gsum += g.E[static_cast<std::size_t>(a * N + m)] * r.G[static_cast<std::size_t>(m)];
      out.G[static_cast<std::size_t>(a)] = gsum;
      for (int c = 0; c < N; ++c) {
        double acc = 0;
        for (int m = 0; m < N; ++m)
          acc += g.E[static_cast<std::size_t>(a * N + m)] * r.E[static_cast<std::size_t>(m * N + c)];
        out.E[static_cast<std::size_t>(a * N + c)] = acc;
      }
    }
    return out;
  }

  std::array<double, N * N> A_;
  double q_;
  bool short_ok_ = false;
  std::vector<StepMatrices<N>> grid_;
  std::vector<bool> done_;
  std::array<int64_t, 2> keys_{};
  std::array<bool, 2> used_{};
  std::array<StepMatrices<N>, 2> steps_;
  int next_ = 0;
};

}  // namespace

bool HurwitzStable(const std::vector<double>& den) {
  const int n = static_cast<int>(den.size()) - 1;
  for (double c : den)
    if (!std::isfinite(c)) return false;
  if (n <= 0) return true;
  if (n == 1) return den[1] > 0;
  if (n == 2) return den[1] > 0 && den[2] > 0;
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) companion(0, k) = -den[static_cast<std::size_t>(k + 1)] / den[0];
  for (int k = 1; k < n; ++k) companion(k, k - 1) = 1.0;
  const Eigen::VectorXcd roots = companion.eigenvalues();
  for (int k = 0; k < n; ++k)
    if (!(roots(k).real() < 0)) return false;
  return true;
}

namespace {

// The walk over one segment for n = N states, in fixed-size arithmetic.
template <int N>
void WalkSegment(StepCache<N>& cache, double d, const std::vector<double>& t, const std::vector<double>& u,
                 const Segment& seg, double before, StateResponses& r) {
  const std::size_t size = t.size();
  auto switch_at = [&](long j) { return t[static_cast<std::size_t>(j)] + d; };
  double tau = t[seg.begin];
  long j = static_cast<long>(std::upper_bound(t.begin(), t.end(), tau - d) - t.begin()) - 1;
  while (j + 1 < static_cast<long>(size) && switch_at(j + 1) <= tau) ++j;
  while (j >= 0 && switch_at(j) > tau) --j;
  std::array<double, N> x{};
  std::array<double, N * N> F{};  // row-major
  for (int k = 0; k < N; ++k) F[static_cast<std::size_t>(k * N + k)] = 1.0;
  std::array<double*, N> state, free;
  for (int k = 0; k < N; ++k)
    state[static_cast<std::size_t>(k)] = r.state[static_cast<std::size_t>(k)].data(),
    free[static_cast<std::size_t>(k)] = r.free[static_cast<std::size_t>(k)].data();
  for (std::size_t i = seg.begin; i < seg.end; ++i) {
    for (int k = 0; k < N; ++k) {
      state[static_cast<std::size_t>(k)][i] = x[static_cast<std::size_t>(k)];
      free[static_cast<std::size_t>(k)][i] = F[static_cast<std::size_t>(k)];
    }
    r.delayed[i] = j >= 0 ? u[static_cast<std::size_t>(j)] : before;
    if (i + 1 == seg.end) break;
    const double to = t[i + 1];
    while (tau < to) {
      const double v = j >= 0 ? u[static_cast<std::size_t>(j)] : before;
      double until = to;
      bool switches = false;
      if (j + 1 < static_cast<long>(size) && switch_at(j + 1) < to) until = switch_at(j + 1), switches = true;
      const double h = until - tau;
      if (h > 0) {
        const StepMatrices<N>& step = cache.Get(h);
        const auto& E = step.E;
        const auto& G = step.G;
        std::array<double, N> nx;
        std::array<double, N * N> nF{};
        for (int a = 0; a < N; ++a) {
          double acc = G[static_cast<std::size_t>(a)] * v;
          for (int b = 0; b < N; ++b) acc += E[static_cast<std::size_t>(a * N + b)] * x[static_cast<std::size_t>(b)];
          nx[static_cast<std::size_t>(a)] = acc;
        }
        // Only the first row of exp(A t) is kept; it moves as F <- F E
        // (exp(A (t + h)) = exp(A t) exp(A h)).
        for (int b = 0; b < N; ++b) {
          double acc = 0;
          for (int c = 0; c < N; ++c) acc += F[static_cast<std::size_t>(c)] * E[static_cast<std::size_t>(c * N + b)];
          nF[static_cast<std::size_t>(b)] = acc;
        }
        x = nx;
        for (int b = 0; b < N; ++b) F[static_cast<std::size_t>(b)] = nF[static_cast<std::size_t>(b)];
      }
      tau = until;
      if (switches) ++j;
      while (j + 1 < static_cast<long>(size) && switch_at(j + 1) <= tau) ++j;
    }
    tau = to;
  }
}

// Controllable canonical form: x_k' = x_(k+1), x_(n-1)' = -sum a_(n-j) x_j + u.
template <int N>
void Walk(const std::vector<double>& den, double d, const std::vector<double>& t, const std::vector<double>& u,
          const std::vector<Segment>& segments, double before, StateResponses& r) {
  std::array<double, N * N> A{};
  for (int k = 0; k + 1 < N; ++k) A[static_cast<std::size_t>(k * N + k + 1)] = 1.0;
  for (int j = 0; j < N; ++j)
    A[static_cast<std::size_t>((N - 1) * N + j)] = -den[static_cast<std::size_t>(N - j)] / den[0];
  const double mean_step = t.size() > 1 ? (t.back() - t.front()) / static_cast<double>(t.size() - 1) : 0.0;
  StepCache<N> cache(A, mean_step);
  for (const Segment& seg : segments)
    if (seg.begin < seg.end && seg.end <= t.size()) WalkSegment<N>(cache, d, t, u, seg, before, r);
}

}  // namespace

StateResponses ComputeStateResponses(const std::vector<double>& den, double delay_s, const std::vector<double>& t,
                                     const std::vector<double>& u, const std::vector<Segment>& segments,
                                     std::optional<double> before_in) {
  const int n = static_cast<int>(den.size()) - 1;
  if (n < 1 || n >= kMax) throw Error("transfer function: 1 to 7 poles supported");
  if (t.size() != u.size()) throw Error("state responses: time and input lengths differ");
  const std::size_t N = t.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  StateResponses r;
  r.n = n;
  r.state.assign(static_cast<std::size_t>(n), std::vector<double>(N, nan));
  r.free.assign(static_cast<std::size_t>(n), std::vector<double>(N, nan));
  r.delayed.assign(N, nan);
  if (N == 0) return r;
  const double d = std::max(0.0, delay_s);
  const double before = before_in ? *before_in : u.front();
  switch (n) {
    case 1:
      Walk<1>(den, d, t, u, segments, before, r);
      break;
    case 2:
      Walk<2>(den, d, t, u, segments, before, r);
      break;
    case 3:
      Walk<3>(den, d, t, u, segments, before, r);
      break;
    case 4:
      Walk<4>(den, d, t, u, segments, before, r);
      break;
    case 5:
      Walk<5>(den, d, t, u, segments, before, r);
      break;
    case 6:
      Walk<6>(den, d, t, u, segments, before, r);
      break;
    default:
      Walk<7>(den, d, t, u, segments, before, r);
      break;
  }
  return r;
}

}  // namespace bead::model

namespace bead::model {

std::vector<std::vector<double>> FilterBasis(const std::vector<double>& den, double delay_s,
                                             const std::vector<double>& t, const std::vector<double>& u,
                                             const std::vector<Segment>& segments, int K) {
  const int n = static_cast<int>(den.size()) - 1;
  double p = 1.0;
  if (n > 0 && den[0] != 0.0 && den.back() != 0.0) p = std::pow(std::abs(den.back() / den[0]), 1.0 / n);
  if (!std::isfinite(p) || p <= 0) p = 1.0;
  std::vector<double> bank = {1.0};
  for (int k = 0; k < K; ++k) {
    std::vector<double> next(bank.size() + 1, 0.0);
    for (std::size_t i = 0; i < bank.size(); ++i) next[i] += bank[i], next[i + 1] += p * bank[i];
    bank = next;
  }
  // Each stretch in steady state at its first input, as the base model is:
  // the response to the input less that level, from rest, plus the level's
  // steady state (1 / p^K in the first state, 0 in the others).
  std::vector<std::vector<double>> out(static_cast<std::size_t>(K + 1), std::vector<double>(t.size(), 0.0));
  const double gain = std::pow(p, K);  // unit DC gain for the first state
  for (const Segment& s : segments) {
    if (s.begin >= s.end) continue;
    std::vector<double> w(u.size(), 0.0);
    for (std::size_t i = s.begin; i < u.size(); ++i) w[i] = u[i] - u[s.begin];
    const StateResponses r = ComputeStateResponses(bank, delay_s, t, w, {s}, 0.0);
    for (std::size_t i = s.begin; i < s.end; ++i) {
      for (int k = 0; k < K; ++k)
        out[static_cast<std::size_t>(k)][i] =
            (r.state[static_cast<std::size_t>(k)][i] + (k == 0 ? u[s.begin] / gain : 0.0)) * gain / std::pow(p, k);
      out[static_cast<std::size_t>(K)][i] = r.delayed[i] + u[s.begin];
    }
  }
  return out;
}

}  // namespace bead::model
