#include "libbead/control/polynomial.h"

#include "libbead/model/transfer_function.h"

#include <algorithm>

namespace bead::control {

std::vector<double> Multiply(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> out(a.size() + b.size() - 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) out[i + j] += a[i] * b[j];
  return out;
}

std::vector<double> Add(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> out(std::max(a.size(), b.size()), 0.0);
  for (std::size_t i = 0; i < a.size(); ++i) out[out.size() - a.size() + i] += a[i];
  for (std::size_t i = 0; i < b.size(); ++i) out[out.size() - b.size() + i] += b[i];
  return out;
}

std::vector<double> Differentiate(const std::vector<double>& a) {
  const std::size_t n = a.size() - 1;
  if (n == 0) return {0.0};
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = a[i] * static_cast<double>(n - i);
  return out;
}

std::vector<double> Trim(const std::vector<double>& a) {
  std::size_t first = 0;
  while (first + 1 < a.size() && a[first] == 0.0) ++first;
  return {a.begin() + static_cast<long>(first), a.end()};
}

std::complex<double> Evaluate(const std::vector<double>& a, std::complex<double> s) {
  std::complex<double> v = 0.0;
  for (double c : a) v = v * s + c;
  return v;
}

int Degree(const std::vector<double>& a) { return static_cast<int>(Trim(a).size()) - 1; }

double Leading(const std::vector<double>& a) { return Trim(a).front(); }

std::vector<std::complex<double>> Roots(const std::vector<double>& in) { return model::PolynomialRoots(Trim(in)); }

}  // namespace bead::control
