#pragma once
// Pearson's correlation coefficient, the one definition every figure of the project uses
// (residual errors, hybrid spectra, fit checks).
#include <vector>

namespace amb::model::signal {

/// Pearson correlation of `a` and `b`, in [-1, 1].
/// Contract: the two series have the same length (std::invalid_argument otherwise); fewer than
/// three points, or a series without variance (a constant), carry no measurable linear relation
/// and give 0, never NaN. Sums in index order (reproducible bit for bit).
double pearson(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace amb::model::signal
