// Real polynomials in descending powers of s, for the control designs:
// products, sums, derivatives, complex evaluation and roots.
#pragma once

#include <complex>
#include <vector>

namespace bead::control {

std::vector<double> Multiply(const std::vector<double>& a, const std::vector<double>& b);
std::vector<double> Add(const std::vector<double>& a, const std::vector<double>& b);  // aligned at s^0
std::vector<double> Differentiate(const std::vector<double>& a);
std::vector<double> Trim(const std::vector<double>& a);  // leading zeros removed (at least one coefficient kept)
std::complex<double> Evaluate(const std::vector<double>& a, std::complex<double> s);
int Degree(const std::vector<double>& a);                               // of the trimmed polynomial
double Leading(const std::vector<double>& a);                           // its leading coefficient
std::vector<std::complex<double>> Roots(const std::vector<double>& a);  // companion matrix eigenvalues

}  // namespace bead::control
