#include "host-tools/core/io/mat_file.hpp"

#include <matio.h>

#include "host-tools/core/io/mat_v5_check.hpp"

#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace amb::host {
namespace {

struct MatCloser {
  void operator()(mat_t* m) const { Mat_Close(m); }
};
struct VarFreer {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};
using MatPtr = std::unique_ptr<mat_t, MatCloser>;
using VarPtr = std::unique_ptr<matvar_t, VarFreer>;

[[noreturn]] void fail(const std::string& file, const std::string& path, const std::string& why) {
  throw std::runtime_error(file + ": variable '" + path + "': " + why);
}

MatPtr open_or_throw(const std::string& file) {
  // libmatio trusts the sizes a file declares; the structure is checked first (mat_v5_check.hpp).
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw std::runtime_error(file + ": cannot open for reading");
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    check_mat_structure(bytes, file);
  }
  MatPtr mat(Mat_Open(file.c_str(), MAT_ACC_RDONLY));
  if (!mat) throw std::runtime_error(file + ": cannot open as a MATLAB .mat file");
  return mat;
}

template <typename T>
void convert(const matvar_t* v, size_t n, std::vector<double>& out, const std::string& file, const std::string& path) {
  // The dimensions come from the file: they must fit the data the file actually holds
  // (found by fuzzing: a header declaring 10^12 elements over a few bytes of data).
  if (n > v->nbytes / sizeof(T))
    fail(file, path, std::to_string(n) + " elements declared but only " + std::to_string(v->nbytes) + " bytes of data");
  const T* p = static_cast<const T*>(v->data);
  out.resize(n);
  for (size_t i = 0; i < n; ++i) out[i] = static_cast<double>(p[i]);
}

}  // namespace

std::vector<double> MatMatrix::column(size_t c) const {
  if (c >= cols) throw std::out_of_range("column index beyond matrix width");
  return std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(c * rows),
                             values.begin() + static_cast<std::ptrdiff_t>((c + 1) * rows));
}

MatMatrix read_mat_matrix(const std::string& file, const std::string& path) {
  MatPtr mat = open_or_throw(file);
  std::vector<std::string> parts;
  {
    std::stringstream ss(path);
    std::string part;
    while (std::getline(ss, part, '.')) parts.push_back(part);
  }
  if (parts.empty() || parts[0].empty()) fail(file, path, "empty variable name");
  VarPtr top(Mat_VarRead(mat.get(), parts[0].c_str()));
  if (!top) fail(file, path, "not found in the file");
  matvar_t* v = top.get();
  for (size_t i = 1; i < parts.size(); ++i) {
    if (v->class_type != MAT_C_STRUCT) fail(file, path, "'" + parts[i - 1] + "' is not a struct");
    matvar_t* field = Mat_VarGetStructFieldByName(v, parts[i].c_str(), 0);
    if (!field) fail(file, path, "struct has no field '" + parts[i] + "'");
    v = field;
  }
  if (v->isComplex) fail(file, path, "complex data is not supported");
  if (v->rank != 2) fail(file, path, "expected a 2-D matrix, found rank " + std::to_string(v->rank));
  if (!v->data) fail(file, path, "has no data");
  MatMatrix m;
  m.rows = v->dims[0];
  m.cols = v->dims[1];
  if (m.rows != 0 && m.cols > std::numeric_limits<size_t>::max() / m.rows)
    fail(file, path, "dimensions overflow");
  const size_t n = m.rows * m.cols;
  if (n == 0) fail(file, path, "is empty");
  switch (v->data_type) {
    case MAT_T_DOUBLE: convert<double>(v, n, m.values, file, path); break;
    case MAT_T_SINGLE: convert<float>(v, n, m.values, file, path); break;
    case MAT_T_INT8: convert<int8_t>(v, n, m.values, file, path); break;
    case MAT_T_UINT8: convert<uint8_t>(v, n, m.values, file, path); break;
    case MAT_T_INT16: convert<int16_t>(v, n, m.values, file, path); break;
    case MAT_T_UINT16: convert<uint16_t>(v, n, m.values, file, path); break;
    case MAT_T_INT32: convert<int32_t>(v, n, m.values, file, path); break;
    case MAT_T_UINT32: convert<uint32_t>(v, n, m.values, file, path); break;
    case MAT_T_INT64: convert<int64_t>(v, n, m.values, file, path); break;
    case MAT_T_UINT64: convert<uint64_t>(v, n, m.values, file, path); break;
    default: fail(file, path, "is not numeric");
  }
  return m;
}

std::vector<double> read_mat_vector(const std::string& file, const std::string& path) {
  return read_mat_matrix(file, path).values;
}

double read_mat_scalar(const std::string& file, const std::string& path) {
  return read_mat_matrix(file, path).values.front();
}

std::vector<std::string> list_mat_variables(const std::string& file) {
  MatPtr mat = open_or_throw(file);
  std::vector<std::string> names;
  while (matvar_t* v = Mat_VarReadNextInfo(mat.get())) {
    if (v->name) names.emplace_back(v->name);
    Mat_VarFree(v);
  }
  return names;
}

}  // namespace amb::host
