#pragma once
// Reading numeric variables from MATLAB v5/v7.3 .mat files (libmatio).
#include <string>
#include <vector>

namespace amb::host {

/// A real numeric matrix read from a .mat file, column-major as MATLAB stores it.
struct MatMatrix {
  std::vector<double> values;  ///< rows*cols values, column-major
  size_t rows = 0;
  size_t cols = 0;
  /// Column `c` as a vector (throws std::out_of_range if c >= cols).
  std::vector<double> column(size_t c) const;
};

/// Read variable `path` from `file`. `path` may name a struct field with dots, e.g.
/// "Signal.y_values.values". Any real numeric class is converted to double.
/// Throws std::runtime_error naming the file and variable if it is missing, complex,
/// sparse, not numeric, or empty.
MatMatrix read_mat_matrix(const std::string& file, const std::string& path);

/// Convenience: the variable as one vector (a row or column vector; for a matrix, all values).
std::vector<double> read_mat_vector(const std::string& file, const std::string& path);

/// Read a scalar (first element) of a numeric variable; throws like read_mat_matrix.
double read_mat_scalar(const std::string& file, const std::string& path);

/// Names of the top-level variables in `file` (throws if it cannot be opened).
std::vector<std::string> list_mat_variables(const std::string& file);

}  // namespace amb::host
